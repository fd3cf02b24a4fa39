"""Each hidden effect shows in the trials that should show it, by more than the noise, and not in the others (the
files of one seed share the preparation and the noise, so a cause's file minus the null file is the effect)."""

import numpy as np
import pytest

from neuromuscle.synth import CAUSES, truth

from synth_cache import dataset


def _window(trial, a_s, b_s):
    m = (trial.time_s >= a_s) & (trial.time_s < b_s)
    return trial.force[m]


def _peaks(trial, times_s, width_s=0.15):
    return np.array([_window(trial, t, t + width_s).max() for t in times_s])


def _pair(cause, shows, absent, strength=0.0):
    ids = tuple(sorted({shows, *absent}))
    d = dataset(cause, strength, ids)
    n = dataset(None, 0.0, ids)
    return d, n, truth(n)["noise_sd_N"]


def _check_absent(d, n, absent, sd, tol=0.0):
    for tid in absent:
        diff = np.max(np.abs(d.trials[tid].force - n.trials[tid].force))
        assert diff <= tol * sd, (tid, diff)


def test_length_dependent_activation_lowers_low_rate_force_away_from_the_optimum():
    d, n, sd = _pair("length_dependent_activation", "train10_short", ("train10_opt",))
    assert np.mean(n.trials["train10_short"].force - d.trials["train10_short"].force) > 3 * sd
    _check_absent(d, n, ("train10_opt",), sd, tol=0.05)  # the optimum is set to 0.1 mm


def test_movement_induced_depression_shows_under_movement_only():
    d, n, sd = _pair("movement_induced_depression", "random_length10", ("train10_opt",))
    late = _window(n.trials["random_length10"], 2.0, 4.1) - _window(d.trials["random_length10"], 2.0, 4.1)
    assert np.mean(late) > 2 * sd
    _check_absent(d, n, ("train10_opt",), sd)


def test_lengthening_below_optimum_lowers_force_during_the_lengthening_ramp_only():
    d, n, sd = _pair("lengthening_below_optimum", "ramp_lengthen10", ("ramp_shorten10",))
    during = _window(n.trials["ramp_lengthen10"], 0.5, 1.1) - _window(d.trials["ramp_lengthen10"], 0.5, 1.1)
    assert np.mean(during) > 2 * sd
    _check_absent(d, n, ("ramp_shorten10",), sd)


def test_staircase_grows_successive_twitches_at_a_low_rate():
    d, n, sd = _pair("staircase", "train3_opt", ("twitch_opt", "train100_opt"))
    stims = d.trials["train3_opt"].stimulus_times_s
    gain = _peaks(d.trials["train3_opt"], stims) - _peaks(n.trials["train3_opt"], stims)
    assert abs(gain[0]) < 3 * sd and gain[-4:].mean() > 3 * sd
    _check_absent(d, n, ("twitch_opt",), sd)
    _check_absent(d, n, ("train100_opt",), sd, tol=0.5)  # a high-rate burst does not build it


def test_doublet_adds_force_after_a_short_interval_only():
    d, n, sd = _pair("doublet_potentiation", "doublet5_opt", ("train10_opt",))
    extra = _window(d.trials["doublet5_opt"], 0.1, 0.5) - _window(n.trials["doublet5_opt"], 0.1, 0.5)
    assert np.mean(extra) > 3 * sd
    _check_absent(d, n, ("train10_opt",), sd)


def test_post_activation_potentiation_grows_twitches_after_the_tetanus_only():
    d, n, sd = _pair("post_activation_potentiation", "potentiation_opt", ("twitch_opt",))
    tt = d.trials["potentiation_opt"].attrs["twitch_times_s"]
    gain = _peaks(d.trials["potentiation_opt"], tt) - _peaks(n.trials["potentiation_opt"], tt)
    assert np.all(np.abs(gain[:3]) < 3 * sd) and np.all(gain[3:] > 5 * sd)
    _check_absent(d, n, ("twitch_opt",), sd)


def test_relaxation_rate_slows_relaxation_after_a_tetanus_more_than_after_a_twitch():
    """Ca2+ removal slows with the recent spike count: the force after a 100 Hz train falls more slowly than the
    null's, by many noise sd; a lone twitch changes far less (its pump is slowed by 7 % at the weakest
    amplitude, and a recalibrated pump takes that)."""
    d, n, sd = _pair("relaxation_rate", "train100_opt", ("twitch_opt",))
    last = float(d.trials["train100_opt"].stimulus_times_s[-1])
    slower = _window(d.trials["train100_opt"], last + 0.02, last + 0.25) - \
        _window(n.trials["train100_opt"], last + 0.02, last + 0.25)
    assert np.max(slower) > 5 * sd and np.mean(slower) > 2 * sd
    twitch = np.abs(d.trials["twitch_opt"].force - n.trials["twitch_opt"].force)
    assert np.max(twitch) < 0.25 * np.max(slower)


def test_force_enhancement_raises_force_after_stretch_only():
    d, n, sd = _pair("force_enhancement_after_stretch", "stretch_hold40", ("shorten_hold40",))
    hold = _window(d.trials["stretch_hold40"], 1.5, 2.5) - _window(n.trials["stretch_hold40"], 1.5, 2.5)
    assert np.mean(hold) > 3 * sd
    _check_absent(d, n, ("shorten_hold40",), sd)


def test_force_depression_lowers_force_after_shortening_only():
    d, n, sd = _pair("force_depression_after_shortening", "shorten_hold40", ("stretch_hold40",))
    hold = _window(n.trials["shorten_hold40"], 1.5, 2.5) - _window(d.trials["shorten_hold40"], 1.5, 2.5)
    assert np.mean(hold) > 3 * sd
    _check_absent(d, n, ("stretch_hold40",), sd)


def test_fatigue_lowers_the_end_of_the_long_train():
    d, n, sd = _pair("fatigue", "long_train40_opt", ("twitch_opt",))
    end_d, end_n = _window(d.trials["long_train40_opt"], 11.5, 12.1), _window(n.trials["long_train40_opt"], 11.5, 12.1)
    start_d, start_n = _window(d.trials["long_train40_opt"], 0.4, 1.0), _window(n.trials["long_train40_opt"], 0.4, 1.0)
    assert end_d.mean() < 0.9 * end_n.mean()
    assert (end_n.mean() - end_d.mean()) > 3 * (start_n.mean() - start_d.mean())  # it grows with the train
    _check_absent(d, n, ("twitch_opt",), sd, tol=0.1)


def test_every_cause_is_tested_here():
    tested = {name for name in CAUSES}
    assert len(tested) == 10


def test_out_of_catalogue_drift_is_present_at_rest_in_every_trial():
    ids = ("twitch_opt", "train10_opt", "step100")
    d, n = dataset("transducer_drift", 0.0, ids), dataset(None, 0.0, ids)
    t = truth(d)
    P0 = t["parameters"]["P0"]
    for tid in ids:
        diff = d.trials[tid].force - n.trials[tid].force
        drift = t["drift"][tid]
        expected = drift["amplitude_N"] * np.sin(2 * np.pi * d.trials[tid].time_s / drift["period_s"]
                                                 + drift["phase_rad"])
        np.testing.assert_allclose(diff, expected, atol=1e-9 * P0)
        assert drift["amplitude_N"] == pytest.approx(0.04 * P0)
    rest = [abs(np.mean(d.trials[tid].force[:90] - n.trials[tid].force[:90])) for tid in ids if tid != "step100"]
    assert max(rest) > 2 * t["noise_sd_N"]
