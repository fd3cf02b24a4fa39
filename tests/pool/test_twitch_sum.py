"""The twitch-sum reference: a single twitch peaks at its contraction time with amplitude 1, the rate gain makes
Fuglevand's sigmoid force-rate curve, and the fit recovers a known twitch sum from its own first half."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.twitch_sum import fit_twitch_sum, rate_gain, twitch_sum_basis, unit_twitch_force


def test_single_twitch_peaks_at_its_contraction_time():
    t = np.arange(0.0, 1000.0, 1.0)
    f = unit_twitch_force(np.array([100.0]), t, 60.0)
    assert t[np.argmax(f)] == pytest.approx(160.0, abs=1.0)
    assert f.max() == pytest.approx(1.0, rel=1e-3)
    assert f[:100].max() == 0.0
    # a discharge between samples is split between them: the peak moves by the fraction
    g = unit_twitch_force(np.array([100.5]), t, 60.0)
    assert np.sum(g * t) / np.sum(g) - np.sum(f * t) / np.sum(f) == pytest.approx(0.5, abs=1e-3)


def test_rate_gain_makes_the_force_rate_curve_sigmoid():
    r = np.array([0.1, 0.4, 0.8, 2.0, 5.0])
    g = rate_gain(r)
    assert g[0] == g[1] == 1.0
    # the mean force of a train grows as gain x rate: steeply above 0.4, then it saturates
    mean = g * r
    assert mean[2] / mean[1] > 4.0 and mean[4] / mean[3] == pytest.approx(1.0, abs=1e-3)
    assert mean[1] / mean[0] == pytest.approx(4.0)


def _trains(n_units: int, seconds: float, seed: int = 1) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_units):
        start, stop = 300.0 + 250.0 * i, seconds * 1000.0 - 300.0 - 200.0 * i
        isi = rng.normal(1000.0 / (12.0 + 2.0 * np.sin(np.arange(400) / 7.0 + i)), 6.0)
        out.append(start + np.cumsum(np.clip(isi, 30.0, None)))
        out[-1] = out[-1][out[-1] < stop]
    return out


def test_fit_recovers_a_known_twitch_sum_and_predicts_the_held_out_half():
    t = np.arange(0.0, 6000.0, 1.0)
    d = _trains(5, 6.0)
    x = np.linspace(0.0, 1.0, 5)
    y = 0.3 * twitch_sum_basis(d, t, x, 20.0, 90.0, 2.0, 30.0) + 1.0
    fit = fit_twitch_sum(d, t, x, y, calibration_ms=(0.0, 3000.0), heldout_ms=(3000.0, 6000.0))
    assert fit.nrmse_heldout_percent < 1.0 and fit.nrmse_calibration_percent < 1.0
    assert fit.rp == pytest.approx(20.0, rel=0.2) and fit.tl_ms == pytest.approx(90.0, rel=0.1)
    assert fit.delay_ms == pytest.approx(30.0, abs=5.0) and fit.offset == pytest.approx(1.0, abs=0.1)


def test_fit_refuses_mismatched_inputs():
    t = np.arange(0.0, 100.0, 1.0)
    with pytest.raises(InputError, match="positions"):
        fit_twitch_sum([np.array([10.0])], t, [0.0, 1.0], np.zeros(100), calibration_ms=(0, 50),
                       heldout_ms=(50, 100))
    with pytest.raises(InputError, match="held-out window"):
        fit_twitch_sum([np.array([10.0])], t, [0.0], np.zeros(100), calibration_ms=(0, 50), heldout_ms=(99, 100))
