"""Following a recorded force: the P0 spread, the MVC at the upper limit of recruitment, the drive found by
inverting the calibration ramp (on a made-up calibration whose answers are known), and one short pool run."""


import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.follow_force import (HUMAN_MUSCLES, Calibration, best_spread, calibrate,
                                          fit_p0_spread_to_recording, p0_spread, spread_distances, time_above_s)
from neuromuscle.pool.identification import IdentificationModel, identify
from neuromuscle.pool.result import PoolResult

TA = HUMAN_MUSCLES["TA"]


def _made_up(definition, n=5, top=1.0):
    """A triangle 0 -> top -> 0 over 10 s each way; unit i recruited at 0.1 (i + 1) uS, its force per newton
    (G - onset) / 0.3, at most 1, on both branches (no hysteresis)."""
    t = np.arange(0.0, 20001.0, 10.0)
    g = np.interp(t, [0.0, 10000.0, 20000.0], [0.0, top, 0.0])
    on = 0.1 * (np.arange(n) + 1)
    basis = np.clip((g[None, :] - on[:, None]) / 0.3, 0.0, 1.0)
    return Calibration(definition, t, g, basis, on, 10000.0)


@pytest.fixture(scope="module")
def cal():
    return _made_up(TA.definition(5))


def test_published_thresholds_and_spread():
    rank = np.array([0.0, 1.0])
    assert TA.thresholds(rank)[-1] == pytest.approx(90.0, abs=0.1)     # TA's upper limit of recruitment
    assert HUMAN_MUSCLES["GM"].thresholds(rank)[-1] == pytest.approx(90.0, abs=0.5)
    assert np.allclose(p0_spread(rank, 40.0, 3.0), [1.0, 40.0])


def test_the_last_unit_is_recruited_at_the_limit(cal):
    s = cal.spread_for(5.0, 1.0, TA)
    assert s.thresholds_percent[-1] == pytest.approx(90.0)
    assert np.all(np.diff(s.thresholds_percent) > 0) and s.thresholds_percent[0] == 0.0
    assert 0.5 < s.mvc_drive_uS < 1.0                      # past the last onset (0.5 uS), inside the ramp
    assert s.percent_mvc(s.mvc_force) == pytest.approx(100.0)
    fit = cal.fit_p0_spread(TA, ratios=[2.0, 5.0, 20.0], exponents=[1.0, 2.0])
    assert fit.rms_error_percent <= s.rms_error_percent
    assert fit.definition(cal).p0_N == pytest.approx(tuple(fit.p0_N(cal.rank)))


def test_a_spread_fitted_to_a_recording_comes_back_near_the_one_that_made_it():
    """The sample a decomposition would take of a pool of known spread: the fit (the smallest distance averaged
    with the grid neighbours) comes back within one grid step of range and exponent, its thresholds within 3.5 % MVC
    of the truth's; the published fit answers another question."""
    cal = _made_up(TA.definition(20), n=20, top=3.0)
    size_only = IdentificationModel(depth_attenuation=0.0)        # the largest active units, whatever the depths
    ratios, powers = np.geomspace(1.5, 100.0, 37), np.geomspace(0.25, 30.0, 23)
    for i, j in ((20, 11), (10, 5), (30, 16)):
        truth = cal.spread_for(ratios[i], powers[j], TA)
        active = truth.thresholds_percent <= 30.0
        found = identify(truth.p0_N(cal.rank), active, 60, motor_units=400, model=size_only)
        recorded = np.repeat(truth.thresholds_percent[found.units], found.weights)
        fit, d = fit_p0_spread_to_recording(cal, TA, recorded, 30.0, model=size_only, seeds=[0])
        near = np.argmin(abs(ratios - fit.range_ratio)), np.argmin(abs(powers - fit.exponent))
        assert abs(near[0] - i) <= 1 and abs(near[1] - j) <= 1
        assert np.max(abs(fit.thresholds_percent - truth.thresholds_percent)) < 3.5 and d < 0.5
    published = cal.fit_p0_spread(TA)
    assert published.rms_error_percent < fit.rms_error_percent   # the published fit answers another question
    with pytest.raises(InputError, match="recruits enough units below 0 % MVC"):
        fit_p0_spread_to_recording(cal, TA, recorded, 0.0, model=size_only, seeds=[0])
    with pytest.raises(InputError, match="no finite recruitment threshold"):
        fit_p0_spread_to_recording(cal, TA, [np.nan], 30.0)
    with pytest.raises(InputError, match="peak_percent"):
        fit_p0_spread_to_recording(cal, TA, recorded, float("nan"))


def test_one_spread_fitted_to_two_recordings_of_one_muscle():
    """Two decompositions of one pool (different counts, different depth seeds): the spread that minimises the sum
    of their distances comes back within one grid step of the truth; one recording's distances alone give its own
    fit; a grid of no finite distance is refused."""
    cal = _made_up(TA.definition(20), n=20, top=3.0)
    model = IdentificationModel(depth_attenuation=2.0)
    ratios, powers = np.geomspace(1.5, 100.0, 37), np.geomspace(0.25, 30.0, 23)
    truth = cal.spread_for(ratios[20], powers[11], TA)
    active = truth.thresholds_percent <= 30.0
    recordings, distances = [], []
    for count, seed in ((80, 7), (30, 8)):
        found = identify(truth.p0_N(cal.rank), active, count, motor_units=400,
                         model=IdentificationModel(2.0, seed=seed))
        recordings.append(np.repeat(truth.thresholds_percent[found.units], found.weights))
        grid, d = spread_distances(cal, TA, recordings[-1], 30.0, model=model, seeds=[7, 8])
        distances.append(d)
    fit, d = best_spread(grid, distances[0] + distances[1])
    near = np.argmin(abs(ratios - fit.range_ratio)), np.argmin(abs(powers - fit.exponent))
    assert abs(near[0] - 20) <= 1 and abs(near[1] - 11) <= 1 and d < 1.0      # d: the two distances' sum
    alone = fit_p0_spread_to_recording(cal, TA, recordings[0], 30.0, model=model, seeds=[7, 8])
    own = best_spread(grid, distances[0])
    assert (own[0].range_ratio, own[0].exponent, own[1]) == (alone[0].range_ratio, alone[0].exponent, alone[1])
    with pytest.raises(InputError, match="finite distance"):
        best_spread(grid, np.full(distances[0].shape, np.inf))


def test_time_above_a_level():
    force = np.array([0.0, 10.0, 20.0, 30.0, 30.0, 20.0, 10.0, 0.0])      # sampled every 0.5 s
    assert time_above_s(force, 0.5, np.array([0.0, 15.0, 30.0, 31.0, np.nan])) == pytest.approx(
        [4.0, 2.0, 1.0, 0.0, 0.0])
    with pytest.raises(InputError, match="sample_s"):
        time_above_s(force, 0.0, np.array([1.0]))


def test_a_spread_fitted_with_the_times_discharging_comes_back_near_the_truth():
    """Identified by size and time discharging (the time a trapezoid to 30 % MVC stays above each threshold):
    the fit given the same force comes back within one grid step; a bad force is refused."""
    cal = _made_up(TA.definition(20), n=20, top=3.0)
    model = IdentificationModel(depth_attenuation=0.0, activity_exponent=1.0)
    ratios, powers = np.geomspace(1.5, 100.0, 37), np.geomspace(0.25, 30.0, 23)
    force = np.interp(np.arange(0.0, 40.0, 0.01), [0.0, 6.0, 34.0, 40.0], [0.0, 30.0, 30.0, 0.0])
    for i, j in ((20, 11), (10, 5), (30, 16)):
        truth = cal.spread_for(ratios[i], powers[j], TA)
        active = truth.thresholds_percent <= 30.0
        found = identify(truth.p0_N(cal.rank), active, 60, motor_units=400, model=model,
                         active_s=time_above_s(force, 0.01, truth.thresholds_percent))
        recorded = np.repeat(truth.thresholds_percent[found.units], found.weights)
        fit, d = fit_p0_spread_to_recording(cal, TA, recorded, 30.0, model=model, seeds=[0],
                                            recorded_force_percent=force, force_sample_s=0.01)
        near = np.argmin(abs(ratios - fit.range_ratio)), np.argmin(abs(powers - fit.exponent))
        assert abs(near[0] - i) <= 1 and abs(near[1] - j) <= 1 and d < 0.5
    with pytest.raises(InputError, match="recorded_force_percent"):
        fit_p0_spread_to_recording(cal, TA, recorded, 30.0, recorded_force_percent=[np.nan, 1.0],
                                   force_sample_s=0.01)
    with pytest.raises(InputError, match="force_sample_s"):
        fit_p0_spread_to_recording(cal, TA, recorded, 30.0, recorded_force_percent=force)


def test_a_ramp_that_never_reaches_the_mvc_is_refused():
    short = _made_up(TA.definition(5), top=0.501)           # the last unit barely recruited, no force above it
    with pytest.raises(InputError, match="raise top_uS"):
        short.fit_p0_spread(TA, ratios=[2.0], exponents=[1.0])


def test_the_drive_inverts_the_ramp_and_a_zero_error_leaves_it(cal):
    s = cal.spread_for(5.0, 1.0, TA)
    (gu, fu), _ = cal.branches(s.p0_N(cal.rank))
    g_true = 0.4
    target = 100.0 * np.interp(g_true, gu, fu) / s.mvc_force
    t = np.arange(0.0, 2001.0, 1.0)
    times, drive = cal.drive_for(s, t, np.full(t.size, target), descent_ms=1e9)
    assert np.allclose(drive, g_true, atol=1e-3)
    force_N = np.full(times.size, target * s.mvc_force / 100.0)
    result = PoolResult(times, np.vstack([np.r_[0.0, force_N[1:]]]), [np.array([])], [{}], "synaptic")
    _, again = cal.correct_drive(s, times, drive, result, t, np.full(t.size, target), lag_ms=0.0, smooth_ms=20.0)
    assert np.allclose(again[5:-5], drive[5:-5], atol=1e-9)
    short = slice(0, 6)   # a trial of 100 ms, shorter than the smoothing window: the drive keeps its length
    sub = PoolResult(times[short], result.unit_force_N[:, short], [np.array([])], [{}], "synaptic")
    _, again = cal.correct_drive(s, times[short], drive[short], sub, t[:101], np.full(101, target), lag_ms=0.0)
    assert again.shape == drive[short].shape and np.all(np.isfinite(again))


def test_the_correction_sees_through_a_staircase_branch(cal):
    """A calibration sampled every millisecond rises in stairs (each twitch, each recruitment): the correction for a
    1 % MVC error is the one the smooth branch gives, within 15 %, at every drive."""
    t = np.arange(0.0, 80001.0, 1.0)
    g = np.interp(t, [0.0, 40000.0, 80000.0], [0.0, 1.0, 0.0])
    on = 0.1 * (np.arange(5) + 1)
    stairs = np.clip(np.floor((g[None, :] - on[:, None]) / 0.3 * 40.0) / 40.0, 0.0, 1.0)
    rough = Calibration(TA.definition(5), t, g, stairs, on, 40000.0)
    s = cal.spread_for(5.0, 1.0, TA)
    times = np.arange(0.0, 2001.0, 20.0)
    steps = []
    for c in (cal, rough):
        drive = np.full(times.size, 0.45)
        result = PoolResult(times, np.zeros((1, times.size)), [np.array([])], [{}], "synaptic")
        target = np.full(times.size, 1.0)                               # 1 % MVC, the pool at rest
        _, new = c.correct_drive(s, times, drive, result, times, target, lag_ms=0.0, smooth_ms=20.0)
        steps.append(new - drive)
    assert np.all(steps[0] > 0.0)
    np.testing.assert_allclose(steps[1], steps[0], rtol=0.15)


def test_a_small_pool_calibrates():
    cal = calibrate(TA.definition(3), top_uS=1.0, ramp_ms=1500.0, dt_ms=0.05)
    assert np.all(np.isfinite(cal.onset_uS)) and np.all(np.diff(cal.onset_uS) > 0)   # the size principle
    assert cal.basis.shape[0] == 3 and cal.basis.max() > 0.1


def test_follow_keeps_the_best_pass_and_shortens_a_step_that_overshot(cal):
    # a plant three times as strong as the calibration: full ILC steps overshoot; the kept pass is the best one
    from neuromuscle.pool.follow_force import follow

    s = cal.spread_for(5.0, 1.0, TA)
    (gu, fu), _ = cal.branches(s.p0_N(cal.rank))
    t = np.arange(0.0, 3001.0, 10.0)
    target = np.interp(t, [0.0, 1000.0, 3000.0], [0.0, 40.0, 40.0])

    def plant(times, drive):
        force_N = 3.0 * np.interp(drive, gu, fu)
        return PoolResult(times, np.vstack([np.r_[0.0, force_N[1:]]]), [np.array([])], [{}], "synaptic")

    seen = []
    best = follow(cal, s, t, target, plant, corrections=4, descent_ms=1e9, report=lambda k, e: seen.append((k, e)))
    assert [k for k, _ in seen] == [0, 1, 2, 3, 4] and list(best.nrmse_passes) == [e for _, e in seen]
    assert best.nrmse_percent == min(best.nrmse_passes) < best.nrmse_passes[0]
    assert best.nrmse_passes[-1] == best.nrmse_percent < 10.0   # full steps would diverge (error x -2 a pass)
    model = s.percent_mvc(best.result.pool_force_N - best.result.pool_force_N[0])
    assert np.allclose(model, best.force_percent)
    with pytest.raises(InputError, match="corrections"):
        follow(cal, s, t, target, plant, corrections=-1, descent_ms=1e9)


def test_a_pass_with_a_non_finite_force_is_reported_not_kept(cal):
    from neuromuscle.pool.follow_force import follow

    s = cal.spread_for(5.0, 1.0, TA)
    t = np.arange(0.0, 3001.0, 10.0)

    def plant(times, drive):   # numerical trouble in the run: a NaN force
        return PoolResult(times, np.vstack([np.full(times.size, np.nan)]), [np.array([])], [{}], "synaptic")

    with pytest.raises(InputError, match="not finite"):
        follow(cal, s, t, np.full(t.size, 40.0), plant, corrections=2, descent_ms=1e9)
