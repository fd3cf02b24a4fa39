"""The causes as the diagnosis sees them: each catalogue extension's facts (telling trials, where it is defined),
evaluated on trial descriptions; and the holds after a movement, measured from the isometric force at the same
length."""

from pathlib import Path

import numpy as np
import pytest

from neuromuscle.diagnose.causes import RISE_S, causes, tells, where_defined
from neuromuscle.diagnose.phases import HOLD_DELAY_S, describe, describe_all
from neuromuscle.measured import Trial
from neuromuscle.model.extensions import registry
from neuromuscle.synth import CAUSES as SYNTH_CAUSES
from neuromuscle.synth import extended_protocols
from neuromuscle.synth.dataset import _empty_trial

OPT = -8.0


@pytest.fixture(scope="module")
def plan():
    return describe_all({p.trial_id: _empty_trial(p) for p in extended_protocols(OPT)})


def _moving(knots_s, knots_mm, stimuli_s, duration_s=4.0):
    t = np.arange(0.0, duration_s, 0.001)
    return describe(Trial(trial_id="x", protocol="test", time_s=t, force=np.zeros(t.size), force_unit="N",
                          length_unit="mm", length_const=None, length=np.interp(t, knots_s, knots_mm),
                          stimulus_times_s=np.asarray(stimuli_s), attrs={}))


def test_the_extensions_and_synth_name_the_same_causes_each_with_its_facts():
    """One set of canonical causes: the catalogue's extensions, the diagnosis's causes and synth's hidden effects."""
    assert set(causes()) == set(registry()) == set(SYNTH_CAUSES)
    root = Path(__file__).resolve().parents[2] / "docs"
    for name, ext in causes().items():
        assert ext.shows and ext.telling.text, name
        assert f"**{name}**" in (root / ext.docs).read_text(), (name, ext.docs)
        assert set(ext.interacts) <= {"C1", "C2", "C3", "alpha", "Umax", "tau2", "P0", "g1", "g2", "KSE", "a0", "b0",
                                      "c0", "d0"}, name


@pytest.mark.parametrize("tid, sign, ramp_end_s, last_stim_s",
                         [("stretch_hold40", 1, 0.6 + 0.25, 2.575), ("shorten_hold40_4s", -1, 1.1 + 0.25, 4.075),
                          ("ramp_lengthen40", 1, 0.5 + 0.3, 1.375)])
def test_the_hold_window_starts_after_the_movement_and_ends_with_the_activity(plan, tid, sign, ramp_end_s,
                                                                              last_stim_s):
    ph = plan[tid]
    w = ph.hold_after(sign)
    assert ph.time_s[w].min() == pytest.approx(ramp_end_s + HOLD_DELAY_S, abs=0.005)
    assert ph.time_s[w].max() == pytest.approx(last_stim_s + 0.05, abs=0.002)
    assert np.all(np.diff(np.flatnonzero(w)) == 1)
    assert not ph.hold_after(-sign).any()
    assert np.ptp(ph.length_mm[w]) < 1e-9


def test_a_hold_ends_at_the_next_movement_and_belongs_to_the_movement_before_it():
    ph = _moving([0.0, 0.5, 0.75, 1.5, 1.75, 4.0], [-8, -8, -3, -3, -8, -8], 0.1 + np.arange(150) / 40)
    fe, fd = ph.hold_after(1), ph.hold_after(-1)
    assert ph.time_s[fe].min() == pytest.approx(0.95, abs=0.003) and ph.time_s[fe].max() < 1.5
    assert ph.time_s[fd].min() == pytest.approx(1.95, abs=0.003)
    assert ph.time_s[fd].max() == pytest.approx(3.825 + 0.05, abs=0.002)
    assert not (fe & fd).any()


def test_a_pause_between_bursts_is_not_a_stimulated_hold():
    stim = np.concatenate([0.1 + np.arange(30) / 40, 2.0 + np.arange(40) / 40])
    ph = _moving([0.0, 0.5, 0.6, 4.0], [-8, -8, -6, -6], stim)
    t = ph.time_s
    assert not ph.stimulated[(t > 0.9) & (t < 2.0)].any() and ph.stimulated[(t > 2.0) & (t < 3.0)].all()
    w = ph.hold_after(1)
    assert t[w].min() == pytest.approx(0.8, abs=0.003) and t[w].max() == pytest.approx(0.875, abs=0.002)


def test_trials_without_a_hold_after_the_movement_have_no_window(plan):
    for tid in ("random_length10", "random_length20", "cyclic10", "cyclic20", "train40_opt", "twitch_opt", "step100"):
        assert not plan[tid].hold_after(1).any() and not plan[tid].hold_after(-1).any(), tid


def test_the_causes_defined_after_a_movement_tell_by_their_hold(plan):
    c = causes()
    fe, fd = c["force_enhancement_after_stretch"], c["force_depression_after_shortening"]
    assert (fe.after, fd.after) == (1, -1)
    assert all(e.after == 0 for n, e in c.items() if e not in (fe, fd))
    assert {t for t, ph in plan.items() if tells(fe.telling, ph, OPT)} == \
        {"ramp_lengthen10", "ramp_lengthen40", "stretch_hold40", "stretch_hold40_4s"}
    assert {t for t, ph in plan.items() if tells(fd.telling, ph, OPT)} == \
        {"ramp_shorten10", "ramp_shorten40", "shorten_hold40", "shorten_hold40_4s"}


@pytest.mark.parametrize("tid, refs", [
    ("stretch_hold40_4s", {"train40_long"}), ("shorten_hold40_4s", {"train40_opt", "long_train40_opt"}),
    ("ramp_lengthen40", {"train40_opt", "long_train40_opt"}), ("ramp_shorten10", {"train10_short"}),
    ("ramp_lengthen10", {"train10_opt"})])
def test_the_isometric_force_at_the_same_length_comes_from_regular_trains_at_that_length_and_rate(plan, tid, refs):
    """Doublets, post-tetanic probes and potentiation protocols are no reference; a 40 Hz hold is matched by 40 Hz
    trains only."""
    name = "force_enhancement_after_stretch" if "lengthen" in tid or "stretch" in tid else \
        "force_depression_after_shortening"
    w = where_defined(causes()[name], plan, tid, OPT)
    assert set(w.references) == refs and w.mask.any()


def test_the_isometric_level_is_over_the_same_span_of_stimulation_each_trial_counting_once(plan):
    w = where_defined(causes()["force_depression_after_shortening"], plan, "shorten_hold40_4s", OPT)
    assert w.until_s == pytest.approx(4.075 + 0.05 - 0.1, abs=0.002)
    res = {}
    for tid in w.references:
        t = plan[tid].time_s
        res[tid] = np.where(t < 0.1 + RISE_S, 5.0, np.where(t > 0.1 + w.until_s + 0.01, 9.0,
                                                              1.0 if tid == "train40_opt" else 2.0))
    assert w.level(plan, res) == pytest.approx(1.5)


def test_the_other_causes_are_defined_on_their_telling_trials(plan):
    """Only the two causes that act through movement tell on moving trials; the others on isometric ones."""
    c = causes()
    assert {n for n, e in c.items() if e.moves} == {"movement_induced_depression", "lengthening_below_optimum"}
    stair, move = c["staircase"], c["movement_induced_depression"]
    for tid, expect in (("twitch_series2_opt", True), ("random_length10", False), ("train40_opt", False)):
        assert tells(stair.telling, plan[tid], OPT) is expect, tid
        assert bool(where_defined(stair, plan, tid, OPT).mask.all()) is expect
    assert where_defined(move, plan, "random_length10", OPT).mask.all()
    assert tells(c["length_dependent_activation"].telling, plan["train10_short"], OPT)
    assert tells(c["length_dependent_activation"].telling, plan["train40_short"], OPT)  # at any rate
    assert not tells(c["length_dependent_activation"].telling, plan["train40_opt"], OPT)
    assert tells(c["fatigue"].telling, plan["long_train30_opt"], OPT)
    assert tells(c["doublet_potentiation"].telling, plan["doublet5_opt"], OPT)
    assert tells(c["post_activation_potentiation"].telling, plan["potentiation_opt"], OPT)


def test_with_no_isometric_trial_a_hold_is_compared_with_the_holds_after_the_opposite_movement():
    """Ramps to one final length (no isometric trial): a stretch-hold is measured from the shortening-holds at the
    same length and rate, over their own holds."""
    from neuromuscle.synth.protocols import protocol_set

    plan = describe_all({p.trial_id: _empty_trial(p) for p in protocol_set("ramps", OPT)})
    w = where_defined(causes()["force_enhancement_after_stretch"], plan, "stretch2mm_4mm_s", OPT)
    assert w.opposite and w.mask.any()
    assert set(w.references) == {"shorten2mm_4mm_s", "shorten2mm_12mm_s", "shorten6mm_4mm_s", "shorten6mm_12mm_s"}
    res = {i: np.where(plan[i].hold_after(-1), 2.0, 7.0) for i in w.references}
    assert w.level(plan, res) == pytest.approx(2.0)


def test_a_moving_trial_is_measured_from_the_isometric_misfit_at_each_samples_length(plan):
    """Isometric 10 Hz trains at three lengths misfit by -10 %, 0 and +10 % of the model's force: a 10 Hz
    random-length trial's level follows its length between them; a rate without isometric trains gives 0."""
    from neuromuscle.diagnose.causes import isometric_level

    sims, meas = {}, {}
    rel = {"train10_short": -0.1, "train10_opt": 0.0, "train10_long": 0.1}
    for i, ph in plan.items():
        sims[i] = np.full(ph.time_s.size, 10.0)
        meas[i] = sims[i] - rel.get(i, 0.0) * sims[i]
    level = isometric_level(plan, "random_length10", sims, meas)
    x = plan["random_length10"].length_mm
    lengths = [plan[i].isometric_length_mm for i in rel]
    expect = np.interp(x, sorted(lengths), [rel[i] for i in sorted(rel, key=lambda k: plan[k].isometric_length_mm)])
    np.testing.assert_allclose(level, expect * 10.0)
    assert isometric_level(plan, "cyclic20", sims, meas) == 0.0  # 20 Hz: isometric trains at one length only
