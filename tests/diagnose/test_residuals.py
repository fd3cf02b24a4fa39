"""Noise from differences, and the trend at rest that no muscle parameter can make."""

import numpy as np
import pytest

from conftest import ar1
from neuromuscle.diagnose.residuals import noise_level, rest_mask, rest_trend_z
from neuromuscle.measured import Trial


@pytest.mark.parametrize("rho, rel", [(0.0, 0.1), (0.6, 0.15), (0.85, 0.5)])
def test_noise_level_under_a_smooth_misfit(rho, rel):
    """sd within rel (the differences carry little of strongly correlated noise: rho 0.85 is imprecise)."""
    rng = np.random.default_rng(5)
    t = np.arange(3000) * 1e-3
    misfit = 0.5 * np.sin(2 * np.pi * 1.5 * t)  # slow model error, 5x the noise
    nz = noise_level(misfit + ar1(rng, t.size, 0.1, rho))
    assert nz.sd_N == pytest.approx(0.1, rel=rel)
    assert nz.rho == pytest.approx(rho, abs=0.08)


def _twitch_trial(rng, extra, moving=False):
    """A 1 s twitch (stimulus at 0.1 s, model force back at rest by ~0.5 s) at 1 kHz: the model's force, and the
    trial measured as model + ``extra`` + AR(1) noise (sd 0.35 N, rho 0.8)."""
    t = np.arange(1000) * 1e-3
    s = np.clip(t - 0.1, 0, None)
    sim = 0.5 + 4.0 * (s / 0.08) * np.exp(1 - s / 0.08)
    force = sim + extra(t) + ar1(rng, t.size, 0.35, 0.8)
    length = -8.0 + (2.0 * t if moving else 0.0 * t)
    return Trial(trial_id="tw", protocol="twitch", time_s=t, force=force, force_unit="N", length_unit="mm",
                 length=length, stimulus_times_s=np.array([0.1])), sim


@pytest.mark.parametrize("extra, structured", [
    (lambda t: 0.0 * t, False),                               # noise only
    (lambda t: 0.0 * t + 0.6, False),                         # a constant offset (passive force misfit)
    (lambda t: 0.9 * np.sin(2 * np.pi * t / 4.0 + 2.5), True),  # a transducer drift, period 4 s
    (lambda t: 0.9 * np.sin(2 * np.pi * t / 4.0 - 0.5), True),
])
def test_rest_trend_sees_force_change_where_the_muscle_is_quiet(extra, structured):
    """Rest: before the stimulus and >= 250 ms after it, where the model's force is back at its level."""
    for seed in range(5):
        trial, sim = _twitch_trial(np.random.default_rng(seed), extra)
        nz = noise_level(trial.force - sim)
        m = rest_mask(trial, sim, nz.sd_N)
        assert m[:100].all() and not m[100:350].any() and m[-300:].all()
        z = rest_trend_z(trial, sim - trial.force, sim, nz)
        assert (abs(z) > 3.0) == structured, (seed, z)


def test_rest_trend_needs_an_isometric_trial_with_rest():
    trial, sim = _twitch_trial(np.random.default_rng(0), lambda t: 0.0 * t, moving=True)
    assert rest_trend_z(trial, sim - trial.force, sim, noise_level(trial.force - sim)) is None
