"""Discharge statistics on trains whose answers are known: rates, thresholds, onion skin, paired-unit Delta F, KS."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import discharge_stats as ds


def _train(rate_hz, start_ms, end_ms):
    return np.arange(start_ms, end_ms, 1000.0 / rate_hz)


def test_rates_median_and_peak_ignore_long_gaps():
    a = np.concatenate([_train(10.0, 0.0, 2000.0), _train(20.0, 5000.0, 5500.0)])   # a 3-s gap between episodes
    r = ds.unit_rates([a, _train(8.0, 0.0, 3000.0), np.array([1.0])])
    assert r.median_hz[0] == pytest.approx(10.0) and r.peak_hz[0] == pytest.approx(20.0)
    assert r.median_hz[1] == pytest.approx(8.0) and np.isnan(r.median_hz[2])
    s = r.summary()
    assert s["units"] == 2 and s["peak_max_hz"] == pytest.approx(20.0)


def test_thresholds_are_the_force_at_first_and_last_discharge():
    t = np.arange(0.0, 10001.0, 1.0)
    force = np.interp(t, [0, 5000, 10000], [0, 50, 0])
    trains = [_train(10.0, 1000.0, 9000.0), _train(10.0, 3000.0, 6000.0)]
    assert np.allclose(ds.recruitment_thresholds(trains, t, force), [10.0, 30.0])
    assert ds.derecruitment_thresholds(trains, t, force)[1] == pytest.approx(41.0)   # last discharge at 5.9 s


def test_onion_skin_sign():
    t = np.arange(0.0, 10001.0, 1.0)
    force = np.interp(t, [0, 2000, 10000], [0, 30, 30])
    early_fast = [_train(20.0, 100.0, 10000.0), _train(15.0, 1000.0, 10000.0), _train(10.0, 1800.0, 10000.0)]
    on = ds.onion_skin(early_fast, t, force, (3000.0, 9000.0))
    assert on.holds and on.rho == pytest.approx(-1.0) and on.slope_hz_per_unit < 0
    assert not ds.onion_skin(early_fast[::-1][:1] + [_train(25.0, 1900.0, 10000.0)], t, force,
                             (3000.0, 9000.0)).holds


def _ramp_train(on_ms, off_ms, f0, slope_hz_per_s, peak_ms):
    """A unit whose rate rises at slope_hz_per_s from f0 until peak_ms and falls back symmetrically."""
    out, t = [], on_ms
    while t < off_ms:
        out.append(t)
        f = f0 + slope_hz_per_s * (min(t, peak_ms) - on_ms - max(t - peak_ms, 0.0)) / 1000.0
        t += 1000.0 / max(f, 1.0)
    return np.array(out)


def test_delta_f_of_a_test_unit_that_derecruits_below_its_recruitment():
    # reference: rate 5 + 2 Hz/s from 0 to 10 s and back to 5 at 20 s (a linear indicator of the drive);
    # test: recruited at 4 s (reference 13 Hz), derecruited at 18 s (reference 9 Hz): Delta F = 4 Hz
    ref = _ramp_train(0.0, 20000.0, 5.0, 2.0, 10000.0)
    test = _ramp_train(4000.0, 18000.0, 6.0, 1.0, 10000.0)
    df = ds.delta_f([ref, test])
    assert df.pairs == 1 and list(df.per_test_unit_hz) == [1]
    assert df.median_hz == pytest.approx(4.0, abs=0.4)
    # recruited less than a second after the reference: no pair
    assert ds.delta_f([ref, _ramp_train(500.0, 18000.0, 6.0, 1.0, 10000.0)]).pairs == 0


def test_ks_distance_weighted_and_plain():
    a, b = np.arange(10.0), np.arange(10.0) + 100.0
    assert ds.ks_distance(a, a) == 0.0 and ds.ks_distance(a, b) == 1.0
    assert ds.ks_distance(np.array([0.0, 1.0]), np.array([0.0]), weights_a=np.array([1.0, 0.0])) == 0.0


def test_ks_by_chance_follows_kolmogorovs_distribution():
    """Samples of 20 from a fine, even distribution: median KS about 0.83 / sqrt(20) and 95th percentile the
    tabled critical value 0.294 (Massey 1951); a distribution of one value can only give 0."""
    p50, p95 = ds.ks_sampling_percentiles(np.linspace(0.0, 1.0, 1000), np.ones(1000), 20, draws=2000)
    assert 0.16 < p50 < 0.20 and 0.27 < p95 < 0.32
    assert ds.ks_sampling_percentiles(np.array([3.0, 4.0]), np.array([1.0, 0.0]), 20, draws=50) == [0.0, 0.0]
    assert np.isnan(ds.ks_sampling_percentiles(np.array([3.0]), np.array([0.0]), 20)).all()
    with pytest.raises(InputError, match="draws"):
        ds.ks_sampling_percentiles(np.array([3.0]), np.array([1.0]), 20, draws=0)


def test_plateau_window_and_bad_trains():
    t = np.arange(0.0, 1001.0, 1.0)
    assert ds.plateau_window_ms(t, np.interp(t, [0, 200, 800, 1000], [0, 10, 10, 0])) == (180.0, 820.0)
    with pytest.raises(InputError, match="train 0"):
        ds.unit_rates([np.array([2.0, 1.0])])


def test_plateau_rate_decline_of_units_firing_through_the_plateau():
    slowing = np.cumsum(np.concatenate([np.full(60, 50.0), np.full(60, 80.0)]))   # 20 Hz, then 12.5 Hz
    steady = np.arange(0.0, 6000.0, 100.0)                                        # 10 Hz throughout
    late = np.arange(4000.0, 6000.0, 100.0)                                       # misses the first edge
    plateau = (0.0, float(slowing[-1]))
    assert ds.plateau_rate_decline_hz([slowing], plateau, edge_ms=2000.0) == pytest.approx(7.5)
    assert ds.plateau_rate_decline_hz([steady, late], (0.0, 5900.0), edge_ms=2000.0) == 0.0
    assert np.isnan(ds.plateau_rate_decline_hz([late], (0.0, 5900.0), edge_ms=2000.0))


def test_smoothed_rate_of_a_firing_shorter_than_the_smoothing_window():
    # every unit of a trial firing for less than SMOOTHING_MS: the rate keeps the grid's length
    grid = np.arange(0.0, 0.6 * ds.SMOOTHING_MS, 1.0)
    rate = ds.smoothed_rate_hz(_train(10.0, 0.0, grid[-1]), grid)
    assert rate.shape == grid.shape
    assert np.nanmax(np.abs(rate - 10.0)) < 1e-9
    assert ds.delta_f([_train(10.0, 0.0, 900.0), _train(12.0, 0.0, 800.0)]).pairs == 0


def test_the_human_range_is_that_of_the_recorded_units(real_data):
    from neuromuscle.pool.discharges import load_caillet

    files = sorted((real_data / "human_mu_spike_trains_caillet").glob("*.mat"))
    recordings = [load_caillet(f) for f in files]
    rates = [ds.unit_rates(r.discharges_ms) for r in recordings]
    medians = np.concatenate([r.median_hz for r in rates])
    medians = medians[np.isfinite(medians)]
    assert len(files) == 8 and medians.size == 291
    assert np.percentile(medians, [5, 95]) == pytest.approx(ds.HUMAN_MEDIAN_RATES_HZ, abs=0.05)
    assert max(np.nanmax(r.peak_hz) for r in rates) == pytest.approx(ds.HUMAN_PEAK_RATE_HZ, abs=0.05)
    cv = np.concatenate([ds.isi_cv(r.discharges_ms, ds.plateau_window_ms(r.force_t_ms, r.force_percent_mvc))
                         for r in recordings])
    assert np.isfinite(cv).sum() == 291
    assert np.nanpercentile(cv, [5, 95]) == pytest.approx(ds.HUMAN_ISI_CV, abs=0.001)
    assert np.nanmedian(cv) == pytest.approx(ds.HUMAN_ISI_CV_MEDIAN, abs=0.001)
    assert ds.inside_human_range(ds.UnitRates(np.array([9.0, 12.0, 20.0, np.nan]), np.zeros(4))) == pytest.approx(2 / 3)


def test_isi_cv_on_the_window_and_its_intervals():
    rng = np.random.default_rng(4)
    regular = np.arange(0.0, 5000.0, 50.0)
    jittery = np.cumsum(rng.gamma(25.0, 2.0, 200))          # intervals of CV 1/sqrt(25) = 0.2
    paused = np.concatenate([np.arange(0.0, 1000.0, 50.0), np.arange(2000.0, 3000.0, 50.0)])
    few = np.arange(0.0, 400.0, 50.0)
    cv = ds.isi_cv([regular, jittery, paused, few], (0.0, 5000.0))
    assert cv[0] == pytest.approx(0.0, abs=1e-12)
    assert cv[1] == pytest.approx(0.2, abs=0.03)
    assert cv[2] == pytest.approx(0.0, abs=1e-12)           # the 1-s pause is not an interval
    assert np.isnan(cv[3])                                  # 7 intervals: too few
    assert np.isnan(ds.isi_cv([regular], (6000.0, 9000.0))[0])
