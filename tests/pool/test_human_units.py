"""Threshold-based muscle units: the speed grid interpolates between simulated speeds, the properties follow the
thresholds, and the fit recovers a force made by the model itself, its intervals covering the truth."""

import numpy as np
import pytest

from neuromuscle import load_parameters
from neuromuscle.analysis import twitch_metrics
from neuromuscle.errors import InputError
from neuromuscle.pool.force_calibration import unit_force_basis
from neuromuscle.pool.human_units import (BOUNDS, MIN_GAP_PERCENT_MVC, SPEED_GRID, SpeedBases, fit_human_units,
                                          represented_gaps, speed_bases, unit_properties)


@pytest.fixture(scope="module")
def bases():
    rng = np.random.default_rng(3)
    trains = []
    for i in range(4):
        start, stop = 300.0 + 300.0 * i, 3700.0 - 250.0 * i
        isi = np.clip(rng.normal(70.0 - 5.0 * i, 8.0, 80), 35.0, None)
        d = start + np.cumsum(isi)
        trains.append(d[d < stop])
    return speed_bases(trains, 4000.0, load_parameters("CT09"), speeds=(0.4, 0.65, 1.0, 1.6, 2.5), dt_ms=0.1)


def test_bases_interpolate_in_log_speed(bases):
    n = bases.forces.shape[1]
    assert np.array_equal(bases.at(np.full(n, 1.0)), bases.forces[2])
    mid = bases.at(np.full(n, np.sqrt(1.0 * 1.6)))
    assert np.allclose(mid, 0.5 * (bases.forces[2] + bases.forces[3]))
    assert np.array_equal(bases.at(np.full(n, 9.0)), bases.forces[-1])  # clipped to the grid
    # faster units relax sooner: less force per newton at these rates
    assert bases.forces[-1].sum() < bases.forces[0].sum()
    # a weighted sum of the units at their own speeds is the product of the weights and the interpolated forces
    rng = np.random.default_rng(3)
    speeds, weights = rng.uniform(0.3, 3.0, n), rng.uniform(0.0, 2.0, n)
    speeds[0] = speeds[1] = 0.65  # on a grid speed, and two units sharing its coefficients
    expected = weights @ bases.at(speeds)
    assert np.allclose(bases.weighted_sum(speeds, weights), expected, rtol=1e-12, atol=1e-12 * expected.max())


def test_slowest_prior_unit_twitches_in_about_200_ms():
    # the prior's slowest units (S0 at its lower bound, the grid's slowest speed) peak at CT09's 81 ms / 0.4,
    # the slow end of human whole-muscle twitches (soleus 157 +/- 15 ms, Vandervoort & McComas 1983)
    assert SPEED_GRID[0] == BOUNDS["S0"][0] == 0.4
    t, g = unit_force_basis([np.array([100.0])], 800.0, load_parameters("CT09"), speed=0.4, dt_ms=0.1)
    tw = twitch_metrics(t, g[0], 100.0)
    assert tw.time_to_peak_ms == pytest.approx(81.2 / 0.4, rel=0.02), tw  # 81.2 ms at speed 1


def test_unit_properties_follow_thresholds():
    speed, p0 = unit_properties(np.array([0.0, 50.0, 100.0]), 1.2, 2.0, 100.0)
    assert np.allclose(speed, [1.2, 1.2 * np.sqrt(2.0), 2.4]) and np.allclose(p0, [1.0, 10.0, 100.0])
    # W weighs each unit by the threshold interval it stands for
    _, p1 = unit_properties(np.array([0.0, 50.0, 100.0]), 1.2, 2.0, 100.0, 1.0)
    assert np.allclose(p1 / p0, represented_gaps(np.array([0.0, 50.0, 100.0])))


def test_represented_gaps_tile_the_thresholds_from_zero():
    th = np.array([10.0, 2.0, 4.0, 4.0])
    gaps = represented_gaps(th)
    # thresholds 2, 4, 10: midpoints 0 | 3 | 7 | 13 (the top reaches as far above 10 as 7 is below); the two units
    # at 4 % MVC share their interval
    assert np.allclose(gaps, [6.0, 3.0, 2.0, 2.0]) and gaps.sum() == pytest.approx(13.0)
    assert represented_gaps(np.array([5.0, 5.0 + 1e-9]))[1] == MIN_GAP_PERCENT_MVC


def _clean_force(bases, th, truth, scale, offset):
    """The model's force (N) of units at thresholds ``th`` under parameters ``truth``, times ``scale`` plus
    ``offset``, delayed by truth["delay_ms"]: what a fit should recover."""
    speed, p0 = unit_properties(th, truth["S0"], truth["RS"], truth["RP"], truth["W"])
    t = bases.t_ms
    return np.interp(t - truth["delay_ms"], t, scale * p0 @ bases.at(speed)) + offset


def test_fit_recovers_the_model_and_its_intervals_cover_it(bases):
    th = np.array([2.0, 8.0, 15.0, 25.0])
    truth = {"S0": 1.1, "RS": 1.8, "RP": 30.0, "W": 0.6, "delay_ms": 40.0}
    clean = _clean_force(bases, th, truth, scale=2.0, offset=0.5)
    t = bases.t_ms
    covered = dict.fromkeys(truth, 0)
    draws = 20
    for seed in range(draws):
        y = clean + np.random.default_rng(seed + 10).normal(0.0, 0.01 * clean.max(), t.size)
        fit = fit_human_units(bases, th, y, calibration_ms=(0.0, 2000.0), heldout_ms=(2000.0, 4000.0))
        assert fit.nrmse_heldout_percent < 2.0 and fit.params["delay_ms"] == pytest.approx(40.0, abs=10.0)
        for name, value in truth.items():
            lo, hi = fit.intervals[name]
            covered[name] += lo <= value <= hi
            low, high, _ = BOUNDS[name]
            assert hi - lo < 0.5 * (high - low), (name, fit.intervals[name])  # informative, not the prior range
    # 95 % intervals: at least 15 of 20 draws cover each parameter (local intervals: RP and W, which trade off,
    # come lowest)
    assert min(covered.values()) >= 15, covered


def test_fit_recovers_slow_units(bases):
    # contraction time 81 / 0.5 = 162 ms at 0 % MVC, near the soleus's whole-muscle 157 ms
    th = np.array([2.0, 8.0, 15.0, 25.0])
    truth = {"S0": 0.5, "RS": 1.5, "RP": 10.0, "W": 1.0, "delay_ms": 20.0}
    clean = _clean_force(bases, th, truth, scale=3.0, offset=0.2)
    y = clean + np.random.default_rng(7).normal(0.0, 0.01 * clean.max(), clean.size)
    fit = fit_human_units(bases, th, y, calibration_ms=(0.0, 2000.0), heldout_ms=(2000.0, 4000.0))
    lo, hi = fit.intervals["S0"]
    assert fit.params["S0"] == pytest.approx(0.5, rel=0.1) and lo <= 0.5 <= hi, (fit.params, fit.intervals)
    assert fit.nrmse_heldout_percent < 2.0


def test_fit_refuses_a_target_of_the_wrong_length(bases):
    with pytest.raises(InputError, match="target"):
        fit_human_units(bases, np.zeros(4), np.zeros(10), calibration_ms=(0, 5), heldout_ms=(5, 10))
    with pytest.raises(InputError, match="two speeds"):
        speed_bases([np.array([10.0])], 100.0, load_parameters("CT09"), speeds=(1.0,))
    assert isinstance(bases, SpeedBases)
