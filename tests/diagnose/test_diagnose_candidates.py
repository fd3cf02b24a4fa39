"""Where the causes defined after a movement are judged: the isometric hold from 0.2 s after an active stretch or
shortening, while stimulated (candidates.hold_window), the telling trials it makes, and the isometric force at
the same length that the hold is measured from."""

import numpy as np
import pytest

from neuromuscle.diagnose.candidates import (CAUSES, HOLD_DELAY_S, hold_window, isometric_level, isometric_references,
                                             plateau, trial_features)
from neuromuscle.measured import MeasuredData
from neuromuscle.synth import extended_protocols
from neuromuscle.synth.dataset import _empty_trial

OPT = -8.0


@pytest.fixture(scope="module")
def plan():
    return {p.trial_id: _empty_trial(p) for p in extended_protocols(OPT)}


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


def test_trials_without_a_hold_after_the_movement_have_no_window(plan):
    for tid in ("random_length20", "cyclic10", "train40_opt", "twitch_opt"):
        assert not hold_window(plan[tid], 1).any() and not hold_window(plan[tid], -1).any(), tid


def test_the_causes_defined_after_a_movement_tell_from_the_same_window(plan):
    by_name = {c.name: c for c in CAUSES}
    fe, fd = by_name["force_enhancement_after_stretch"], by_name["force_depression_after_shortening"]
    assert (fe.after, fd.after) == (1, -1)
    assert all(c.after == 0 and c.window(plan["stretch_hold40"]) is None for c in CAUSES if c not in (fe, fd))
    for tid, trial in plan.items():
        f = trial_features(trial, OPT)
        assert fe.telling(f) == bool(fe.window(trial).sum() * 1e-3 >= 0.05), tid
        assert fd.telling(f) == bool(fd.window(trial).sum() * 1e-3 >= 0.05), tid
    assert {t for t, tr in plan.items() if fe.telling(trial_features(tr, OPT))} == \
        {"ramp_lengthen10", "ramp_lengthen40", "stretch_hold40", "stretch_hold40_4s"}
    assert {t for t, tr in plan.items() if fd.telling(trial_features(tr, OPT))} == \
        {"ramp_shorten10", "ramp_shorten40", "shorten_hold40", "shorten_hold40_4s"}


@pytest.mark.parametrize("tid, sign, refs", [
    ("stretch_hold40_4s", 1, {"train40_long"}), ("shorten_hold40_4s", -1, {"train40_opt", "long_train40_opt"}),
    ("ramp_lengthen40", 1, {"train40_opt", "long_train40_opt"}), ("ramp_shorten10", -1, {"train10_short"})])
def test_the_isometric_force_at_the_same_length_comes_from_trials_at_that_length_and_rate(plan, tid, sign, refs):
    assert set(isometric_references(plan, plan[tid], hold_window(plan[tid], sign))) == refs
    assert isometric_references(plan, plan["random_length20"], hold_window(plan["random_length20"], 1)) == []


def test_the_isometric_level_is_the_mean_residual_on_the_plateaus(plan):
    """The rise (the first 0.2 s of stimulation) and the relaxation are left out; trials count by their samples."""
    res = {}
    for tid in ("train40_opt", "long_train40_opt"):
        t = np.asarray(plan[tid].time_s)
        res[tid] = np.where(t < 0.1 + HOLD_DELAY_S, 5.0, 1.0 if tid == "train40_opt" else 2.0)
    n1, n2 = (int(plateau(plan[i]).sum()) for i in ("train40_opt", "long_train40_opt"))
    assert isometric_level(["train40_opt", "long_train40_opt"], plan, res) == pytest.approx((n1 + 2 * n2) / (n1 + n2))
    assert isometric_level([], plan, res) == 0.0
