"""Synthetic measured trials for the fit tests: CT09 force with Gaussian noise (sd 0.02 N); short trials
(<= 300 ms, 1 ms samples), dt 0.1 ms and a 200 ms settling period keep each simulation at a few ms."""

import numpy as np

from neuromuscle import fit
from neuromuscle.fit import SimulationOptions

OPTS = SimulationOptions(dt_ms=0.1, settle_ms=200.0)
NOISE_N = 0.02


def synthetic_trial(params, tid, stim_s, length_mm=-8.0, duration_s=0.3, seed=0, length=None,
                    protocol="twitch"):
    """A synthetic measured trial: CT09 force at 1 ms samples plus Gaussian noise (sd NOISE_N)."""
    t = np.arange(0.0, duration_s, 0.001)
    return fit.synthetic_trial(params, tid, t, stim_s, protocol=protocol,
                               length_mm=length_mm if length is None else None,
                               length=None if length is None else length(t), noise_N=NOISE_N,
                               rng=np.random.default_rng(seed), dt_ms=OPTS.dt_ms, settle_ms=OPTS.settle_ms)


def far_start(ct09):
    """Start values of C3 and C1 far (x1.6, x0.6) from CT09."""
    return {"C3": ct09["C3"] * 1.6, "C1": ct09["C1"] * 0.6}
