"""The comparison of a pool's discharges with recorded ones: a recording compared with itself passes every
criterion; a pool firing too fast or recruited too early fails the right ones."""

import numpy as np

from neuromuscle.pool.discharges import DischargeTrial
from neuromuscle.pool.recorded_comparison import compare_discharges

T = np.arange(0.0, 20001.0, 1.0)
FORCE = np.interp(T, [0, 4000, 16000, 20000], [0, 30, 30, 0])


def _trains(rates_hz, starts_ms):
    return [np.arange(s, 19000.0 - s / 4, 1000.0 / r) for r, s in zip(rates_hz, starts_ms)]


def _trial(trains):
    return DischargeTrial("made up", 0.0, 20000.0, trains, np.arange(len(trains)), T, FORCE)


def test_a_recording_compared_with_itself_passes():
    rec = _trains(np.linspace(20.0, 12.0, 12), np.linspace(100.0, 3800.0, 12))
    c = compare_discharges(_trial(rec), rec, T, FORCE).criteria()
    assert c["medians_inside"]["fraction"] > 0.8 and c["peak_ratio"]["value"] == 1.0
    assert c["thresholds_ks"]["value"] == 0.0 and c["thresholds_ks"]["pass"] and c["onion_skin"]["pass"]
    assert np.array_equal([c["delta_f_hz"]["value"]], [c["delta_f_hz"]["recorded"]], equal_nan=True)


def test_a_fast_early_pool_fails_rates_and_thresholds():
    rec = _trains(np.linspace(20.0, 12.0, 12), np.linspace(100.0, 3800.0, 12))
    fast = _trains(np.linspace(40.0, 45.0, 12), np.linspace(100.0, 600.0, 12))     # later units faster
    c = compare_discharges(_trial(rec), fast + [np.array([5000.0])], T, FORCE)
    crit = c.criteria()
    assert c.model_units.size == 12                                  # the unit with one discharge is left out
    assert not crit["medians_inside"]["pass"] and not crit["peak_ratio"]["pass"]
    assert not crit["thresholds_ks"]["pass"] and not crit["onion_skin"]["pass"]
    assert set(c.summary()) == {"plateau_ms", "model_units", "recorded", "model", "criteria"}
    # periodic trains: no interval varies; every unit fires through the plateau
    assert np.allclose(c.summary()["recorded"]["isi_cv_p5_p50_p95"], 0.0, atol=1e-12)


def test_the_plateau_isi_cv_of_each_side():
    rng = np.random.default_rng(1)
    rec = [np.cumsum(rng.gamma(25.0, 50.0 / 25.0, 380)) + 500.0 for _ in range(6)]   # CV 0.2 about 20 Hz
    c = compare_discharges(_trial(rec), _trains(np.linspace(21.0, 19.0, 6), np.linspace(100.0, 600.0, 6)), T, FORCE)
    recorded, model = c.summary()["recorded"]["isi_cv_p5_p50_p95"], c.summary()["model"]["isi_cv_p5_p50_p95"]
    assert np.all(np.isfinite(c.recorded.isi_cv)) and abs(recorded[1] - 0.2) < 0.03
    assert model[2] < 1e-9
