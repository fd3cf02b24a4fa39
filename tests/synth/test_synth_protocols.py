"""The protocol sets: the extended set is the standard one unchanged plus three protocols of two trials, each on
both sides of the diagnosis's split, and a second stretch-hold and shortening-hold that the split holds out; each
telling for the causes it targets; the hidden effects show in them."""

import numpy as np
import pytest

from neuromuscle import InputError
from neuromuscle.cli import main
from neuromuscle.diagnose.causes import causes, tells as cause_tells
from neuromuscle.diagnose.phases import describe
from neuromuscle.diagnose.split import automatic_split
from neuromuscle.measured import MeasuredData, read_measured
from neuromuscle.synth import extended_protocols, make_dataset, protocol_set, standard_protocols, truth
from neuromuscle.synth.dataset import _empty_trial
from neuromuscle.synth.protocols import total_duration_s

from synth_cache import NOISE_PCT, SEED

OPT = -8.0
NEW = {"twitch_series": ("twitch_series1_opt", "twitch_series2_opt"),
       "post_tetanic": ("post_tetanic100_opt", "post_tetanic50_opt"),
       "cyclic_length": ("cyclic10", "cyclic20")}
#: A second hold of each kind, held longer (4 s trains), judged where the standard one calibrates.
HOLDS = {"stretch_hold": ("stretch_hold40", "stretch_hold40_4s"),
         "shorten_hold": ("shorten_hold40", "shorten_hold40_4s")}


def _data(plan):
    return MeasuredData(trials={p.trial_id: _empty_trial(p) for p in plan}, attrs={})


def test_extended_set_is_the_standard_set_unchanged_then_three_protocols_of_two_trials():
    std, ext = standard_protocols(OPT), extended_protocols(OPT)
    assert [p.trial_id for p in ext[:len(std)]] == [p.trial_id for p in std]
    for a, b in zip(std, ext):
        assert np.array_equal(a.stimulus_times_s, b.stimulus_times_s) and np.array_equal(a.time_s, b.time_s)
    added = ext[len(std):]
    assert {p.protocol: sorted(q.trial_id for q in added if q.protocol == p.protocol) for p in added} == \
        {**{k: sorted(v) for k, v in NEW.items()}, **{k: [v[1]] for k, v in HOLDS.items()}}
    assert 125.0 < total_duration_s(ext) < 128.0  # 126.6 s against the standard's 92 s
    assert [p.trial_id for p in protocol_set("extended", OPT)] == [p.trial_id for p in ext]
    with pytest.raises(InputError, match="unknown protocol set 'long'; known: standard, extended, reduced, ramps"):
        protocol_set("long", OPT)


def test_each_added_protocol_has_a_trial_on_each_side_and_the_standard_split_is_kept():
    std = automatic_split(_data(standard_protocols(OPT)))
    ext = automatic_split(_data(extended_protocols(OPT)))
    assert set(std.calibration) <= set(ext.calibration) and set(std.heldout) <= set(ext.heldout)
    for ids in NEW.values():
        assert len(set(ids) & set(ext.calibration)) == 1 and len(set(ids) & set(ext.heldout)) == 1
    for first, second in HOLDS.values():  # the standard hold keeps calibrating; the longer one is judged
        assert first in ext.calibration and second in ext.heldout
    assert "post_tetanic100_opt" in ext.heldout  # the probes after the higher-rate train are judged


def test_added_trials_are_telling_for_the_causes_they_target():
    plan = {p.trial_id: describe(_empty_trial(p)) for p in extended_protocols(OPT)[len(standard_protocols(OPT)):]}
    catalogue = causes()

    def tells(cause, tid):
        return cause_tells(catalogue[cause].telling, plan[tid], OPT)

    assert all(tells("staircase", t) for t in NEW["twitch_series"])
    assert all(tells("post_activation_potentiation", t) for t in NEW["post_tetanic"])
    for cause in ("movement_induced_depression", "lengthening_below_optimum"):
        assert all(tells(cause, t) for t in NEW["cyclic_length"]), cause
    assert not any(tells("movement_induced_depression", t) for t in NEW["twitch_series"] + NEW["post_tetanic"])
    assert tells("force_enhancement_after_stretch", HOLDS["stretch_hold"][1])
    assert tells("force_depression_after_shortening", HOLDS["shorten_hold"][1])


@pytest.mark.parametrize("cause, tid", [("force_enhancement_after_stretch", "stretch_hold40_4s"),
                                        ("force_depression_after_shortening", "shorten_hold40_4s")])
def test_the_hidden_force_history_lasts_through_the_long_hold(cause, tid):
    """At the weakest strength, the hidden enhancement / depression is still beyond the noise sd in the last
    second of the long hold (the window where the diagnosis judges them), with the sign of its cause."""
    d, n, sd = _pair(cause, (tid,))
    last = float(d.trials[tid].stimulus_times_s[-1])
    late = _excess(d, n, tid, last, -1.0, 0.0)
    assert abs(late) > sd and np.sign(late) == (1 if cause.startswith("force_enh") else -1), (late, sd)


def _pair(cause, ids):
    d = make_dataset(cause, 0.0, SEED, noise_pct=NOISE_PCT, trials=list(ids), dt_ms=0.05, protocols="extended")
    n = make_dataset(None, 0.0, SEED, noise_pct=NOISE_PCT, trials=list(ids), dt_ms=0.05, protocols="extended")
    return d, n, truth(n)["noise_sd_N"]


def _excess(d, n, tid, t_s, a_s=0.01, b_s=0.06):
    """Mean force of the effect's file above the null's (N) from t_s + a_s to t_s + b_s (the noise cancels)."""
    tr_d, tr_n = d.trials[tid], n.trials[tid]
    m = (tr_d.time_s >= t_s + a_s) & (tr_d.time_s < t_s + b_s)
    return float(np.mean(tr_d.force[m] - tr_n.force[m]))


def test_hidden_staircase_grows_the_twitch_series_and_relaxation_slows_the_early_probes():
    ids = ("twitch_series1_opt", "twitch_series2_opt")
    d, n, sd = _pair("staircase", ids)
    grow = {t: [_excess(d, n, t, s) for s in d.trials[t].stimulus_times_s] for t in ids}
    two, one = grow["twitch_series2_opt"], grow["twitch_series1_opt"]
    assert abs(two[0]) < 1e-9 and two[-1] > 5 * two[1] > 0  # the first twitch as the null's, then growing
    # at the weakest strength the tenth twitch gains ~0.45 noise sd over 50 samples; treppe is larger at 2 Hz than 1 Hz
    assert two[-1] > 0.3 * sd and two[-1] > 3 * one[-1]
    assert truth(d)["protocol_set"].endswith("protocol_set('extended')")
    d, n, sd = _pair("relaxation_rate", ("post_tetanic100_opt",))
    probes = np.asarray(d.trials["post_tetanic100_opt"].attrs["twitch_times_s"], dtype=float)
    slowed = [_excess(d, n, "post_tetanic100_opt", t, 0.03, 0.12) for t in probes]  # in each probe's relaxation
    assert slowed[0] > sd and slowed[0] > 3 * abs(slowed[-1])  # recovering within a second, unlike a potentiation


def test_cli_writes_a_standard_file_on_request_and_refuses_an_unknown_set(tmp_path, capsys):
    bad = tmp_path / "bad.h5"
    assert main(["synth", "--cause", "none", "--seed", "1", "--protocols", "long", "--out", str(bad)]) == 2
    assert "unknown protocol set 'long'" in capsys.readouterr().err
    assert not bad.exists()
    out = tmp_path / "std.h5"
    assert main(["synth", "--cause", "none", "--strength", "0", "--seed", "2", "--protocols", "standard",
                 "--out", str(out)]) == 0
    assert main(["data", "check", str(out)]) == 0
    assert set(read_measured(out).trials) == {p.trial_id for p in standard_protocols(OPT)}
