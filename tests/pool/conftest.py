"""Pool tests' shared fixtures: a small recording in the Caillet layout."""

import numpy as np
import pytest
import scipy.io

FS = 2048.0


def write_small_caillet(path, seconds: float = 5.0, seed: int = 2, top: float = 1.0):
    """A Caillet-layout file: 4 units recruited in turn on a trapezoid, force a smoothed sum of their activity."""
    rng = np.random.default_rng(seed)
    n = int(seconds * FS)
    t = np.arange(n) / FS
    ramp = top * np.clip(np.minimum(t - 0.5, seconds - 0.5 - t) / 1.5, 0.0, 1.0)
    pulses = np.empty((1, 4), dtype=object)
    rate = np.zeros(n)
    for i in range(4):
        on = ramp > 0.2 * i
        times, s = [], 0.0
        while s < seconds:
            s += 1.0 / (8.0 + 6.0 * ramp[min(int(s * FS), n - 1)]) + rng.normal(0.0, 0.004)
            if s < seconds and on[min(int(s * FS), n - 1)]:
                times.append(s)
        k = np.unique(np.round(np.array(times) * FS).astype(int) + 1)
        pulses[0, i] = k[None, :]
        rate += np.convolve(np.bincount(k - 1, minlength=n)[:n].astype(float), np.hanning(400), "same")
    force = 0.9 + 0.05 * rate / rate.max() + rng.normal(0.0, 1e-4, n)
    scipy.io.savemat(path, {"MUPulses": pulses, "fsamp": np.array([[FS]]), "ref_signal": force[None, :]})
    return path


@pytest.fixture(scope="session")
def small_caillet():
    """``write_small_caillet(path, seconds=5, seed=2, top=1)``: writes the file, returns its path (``top`` < 1: a
    lower plateau, fewer units recruited)."""
    return write_small_caillet
