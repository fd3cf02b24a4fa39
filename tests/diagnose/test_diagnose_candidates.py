"""Where the causes defined after a movement are judged: each stimulated isometric hold from 0.2 s after an active
stretch or shortening (candidates.hold_window), the telling trials it makes, and the isometric force at the same
length that the hold is measured from (candidates.hold, Window.level)."""

import numpy as np
import pytest

from neuromuscle.diagnose.candidates import CAUSES, HOLD_DELAY_S, RISE_S, hold, hold_window, stimulated, trial_features
from neuromuscle.measured import Trial
from neuromuscle.synth import extended_protocols
from neuromuscle.synth.dataset import _empty_trial

OPT = -8.0


@pytest.fixture(scope="module")
def plan():
    return {p.trial_id: _empty_trial(p) for p in extended_protocols(OPT)}


def _moving_trial(knots_s, knots_mm, stimuli_s, duration_s=4.0):
    t = np.arange(0.0, duration_s, 0.001)
    return Trial(trial_id="x", protocol="test", time_s=t, force=np.zeros(t.size), force_unit="N", length_unit="mm",
                 length_const=None, length=np.interp(t, knots_s, knots_mm), stimulus_times_s=np.asarray(stimuli_s),
                 attrs={})


@pytest.mark.parametrize("tid, sign, ramp_end_s, last_stim_s",
                         [("stretch_hold40", 1, 0.6 + 0.25, 2.575), ("shorten_hold40_4s", -1, 1.1 + 0.25, 4.075),
                          ("ramp_lengthen40", 1, 0.5 + 0.3, 1.375)])
def test_the_hold_window_starts_after_the_movement_and_ends_with_the_activity(plan, tid, sign, ramp_end_s,
                                                                              last_stim_s):
    trial = plan[tid]
    t = np.asarray(trial.time_s)
    w = hold_window(trial, sign)
    assert t[w].min() == pytest.approx(ramp_end_s + HOLD_DELAY_S, abs=0.005)
    assert t[w].max() == pytest.approx(last_stim_s + 0.05, abs=0.002)
    assert np.all(np.diff(np.flatnonzero(w)) == 1)  # one stretch of samples
    assert not hold_window(trial, -sign).any()  # no movement of the other sign
    assert np.ptp(trial.length_at()[w]) < 1e-9  # the length is still there


def test_a_hold_ends_at_the_next_movement_and_belongs_to_the_movement_before_it():
    """Stretch (0.5-0.75 s), hold, shortening (1.5-1.75 s), hold, all during a 40 Hz train: the hold after the
    stretch ends where the shortening starts, and the hold after the shortening is force depression's."""
    trial = _moving_trial([0.0, 0.5, 0.75, 1.5, 1.75, 4.0], [-8, -8, -3, -3, -8, -8], 0.1 + np.arange(150) / 40)
    t = np.asarray(trial.time_s)
    fe, fd = hold_window(trial, 1), hold_window(trial, -1)
    assert t[fe].min() == pytest.approx(0.95, abs=0.003) and t[fe].max() < 1.5
    assert t[fd].min() == pytest.approx(1.95, abs=0.003) and t[fd].max() == pytest.approx(3.825 + 0.05, abs=0.002)
    assert not (fe & fd).any()


def test_a_pause_between_bursts_is_not_a_stimulated_hold():
    """A stretch during a 40 Hz burst that ends 0.1 s after it, then a second burst 1 s later: the pause is not
    stimulated, and the burst after it no longer follows the stretch (its hold is no hold after the movement)."""
    stim = np.concatenate([0.1 + np.arange(30) / 40, 2.0 + np.arange(40) / 40])  # 0.1-0.825 s, 2.0-2.975 s
    trial = _moving_trial([0.0, 0.5, 0.6, 4.0], [-8, -8, -6, -6], stim)
    t = np.asarray(trial.time_s)
    active = stimulated(t, stim)
    assert not active[(t > 0.9) & (t < 2.0)].any() and active[(t > 2.0) & (t < 3.0)].all()
    w = hold_window(trial, 1)
    assert t[w].min() == pytest.approx(0.8, abs=0.003) and t[w].max() == pytest.approx(0.875, abs=0.002)


def test_trials_without_a_hold_after_the_movement_have_no_window(plan):
    for tid in ("random_length10", "random_length20", "cyclic10", "cyclic20", "train40_opt", "twitch_opt", "step100"):
        assert not hold_window(plan[tid], 1).any() and not hold_window(plan[tid], -1).any(), tid


def test_the_causes_defined_after_a_movement_tell_by_their_hold(plan):
    by_name = {c.name: c for c in CAUSES}
    fe, fd = by_name["force_enhancement_after_stretch"], by_name["force_depression_after_shortening"]
    assert (fe.after, fd.after) == (1, -1)
    assert all(c.after == 0 for c in CAUSES if c not in (fe, fd))
    assert {t for t, tr in plan.items() if fe.telling(trial_features(tr, OPT))} == \
        {"ramp_lengthen10", "ramp_lengthen40", "stretch_hold40", "stretch_hold40_4s"}
    assert {t for t, tr in plan.items() if fd.telling(trial_features(tr, OPT))} == \
        {"ramp_shorten10", "ramp_shorten40", "shorten_hold40", "shorten_hold40_4s"}


@pytest.mark.parametrize("tid, sign, refs", [
    ("stretch_hold40_4s", 1, {"train40_long"}), ("shorten_hold40_4s", -1, {"train40_opt", "long_train40_opt"}),
    ("ramp_lengthen40", 1, {"train40_opt", "long_train40_opt"}), ("ramp_shorten10", -1, {"train10_short"}),
    ("ramp_lengthen10", 1, {"train10_opt"})])
def test_the_isometric_force_at_the_same_length_comes_from_regular_trains_at_that_length_and_rate(plan, tid, sign,
                                                                                                   refs):
    """Doublets (10 Hz with one 5-15 ms interval), post-tetanic probes and potentiation protocols are no
    reference; a hold at 40 Hz is matched by 40 Hz trains only."""
    h = hold(plan, tid, sign)
    assert set(h.references) == refs and h.mask.any()
    assert hold(plan, "random_length20", 1).references == ()


def test_the_isometric_level_is_over_the_same_span_of_stimulation_each_trial_counting_once(plan):
    """The rise (RISE_S) is left out, and a 12 s train counts only up to the hold's end (4.0 s of stimulation in
    the long shortening-hold), as much as a 1 s train."""
    h = hold(plan, "shorten_hold40_4s", -1)
    assert h.until_s == pytest.approx(4.075 + 0.05 - 0.1, abs=0.002)  # last stimulus + 50 ms, from the first
    res = {}
    for tid in h.references:
        t = np.asarray(plan[tid].time_s)
        res[tid] = np.where(t < 0.1 + RISE_S, 5.0, np.where(t > 0.1 + h.until_s + 0.01, 9.0,
                                                              1.0 if tid == "train40_opt" else 2.0))
    assert h.level(plan, res) == pytest.approx(1.5)
    assert hold(plan, "cyclic10", 1).level(plan, res) == 0.0  # no hold, no reference


def test_the_other_causes_are_defined_on_their_telling_trials_the_moving_ones_only_if_they_act_through_movement(plan):
    """Rule 7's window for a cause that is not defined after a movement: the whole of a telling trial, but a moving
    one only for movement-induced depression and lengthening below the optimum (a staircase judged on a
    random-length trial takes up the force-velocity misfit there: stop 39, suite seed 4's movement case)."""
    by_name = {c.name: c for c in CAUSES}
    assert {c.name for c in CAUSES if c.moves} == {"movement_induced_depression", "lengthening_below_optimum"}
    stair, move = by_name["staircase"], by_name["movement_induced_depression"]
    for tid, tells in (("twitch_series2_opt", True), ("random_length10", True), ("train40_opt", False)):
        assert stair.telling(trial_features(plan[tid], OPT)) is tells
    assert stair.where(plan, "twitch_series2_opt", True).mask.all()
    assert not stair.where(plan, "random_length10", True).mask.any()  # telling, but it moves
    assert not stair.where(plan, "train40_opt", False).mask.any()  # not telling
    assert move.where(plan, "random_length10", True).mask.all()
    w = by_name["force_enhancement_after_stretch"].where(plan, "stretch_hold40_4s", True)
    assert np.array_equal(w.mask, hold_window(plan["stretch_hold40_4s"], 1)) and w.references == ("train40_long",)
