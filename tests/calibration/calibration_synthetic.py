"""A synthetic CT09-like preparation for the calibration tests (and the fit report tests)."""

from __future__ import annotations

import numpy as np

from neuromuscle.calibration import (FORCE_LENGTH_PATH, FORCE_VELOCITY_PATH, gaussian_force_length, hill_tension,
                                     mashima_tension)
from neuromuscle.fit import SimulationOptions, synthetic_trial
from neuromuscle.measured import MeasuredData

DT = 0.1
SETTLE = 300.0
OPTS = SimulationOptions(dt_ms=DT, record_dt_ms=0.5, settle_ms=SETTLE)

def _trial(params, tid, protocol, t, stims, length_const=None, length=None, noise=0.0, rng=None):
    return synthetic_trial(params, tid, t, stims, protocol=protocol, length_mm=length_const, length=length,
                           noise_N=noise, rng=rng, dt_ms=DT, record_dt_ms=0.5 if length is None else DT,
                           settle_ms=SETTLE)


def synthetic_data(params, noise=0.005, seed=1, full=True) -> MeasuredData:
    """CT09-like preparation: twitch + 10/20/40 Hz at g1, twitches at g1 -/+ 8 mm, a step shortening during a
    100 Hz train, isometric force-length and isokinetic velocity-tension points (extra datasets)."""
    rng = np.random.default_rng(seed)
    g1 = params["g1"]
    t = np.arange(0.0, 0.45, 0.002)
    trials = [_trial(params, "twitch_opt", "twitch", t, [0.02], g1, noise=noise, rng=rng)]
    if full:
        for rate in (10, 20, 40):
            trials.append(_trial(params, f"train{rate}", "train", t, np.arange(0.02, 0.3, 1.0 / rate), g1,
                                 noise=noise, rng=rng))
        for x in (g1 - 8.0, g1 + 8.0):
            trials.append(_trial(params, f"twitch_{x:g}mm", "twitch", t, [0.02], x, noise=noise, rng=rng))
    ts = np.arange(0.0, 0.2, 0.0001)
    xs = np.interp(ts, [0.0, 0.15, 0.1505, 0.2], [g1, g1, g1 - 0.5, g1 - 0.5])
    trials.append(_trial(params, "step", "step", ts, np.arange(0.0, 0.2, 0.01), length=xs))
    xl = np.linspace(g1 - 16, g1 + 8, 9)
    fl = gaussian_force_length(xl, g1, params["g2"], params["P0"]) + rng.normal(0, 0.05, xl.size)
    vs = np.array([-160.0, -80.0, -40.0, -10.0, -1.0])
    vl = np.array([1.0, 10.0, 40.0, 80.0])
    fv = np.concatenate([hill_tension(vs, params["a0"], params["b0"], params["P0"]),
                         mashima_tension(vl, params["c0"], params["d0"], params["P0"])])
    fv = fv + rng.normal(0, 0.05, fv.size)
    return MeasuredData(trials={tr.trial_id: tr for tr in trials}, attrs={"source": "synthetic CT09"},
                        extra_datasets={FORCE_LENGTH_PATH: np.column_stack([xl, fl]),
                                        FORCE_VELOCITY_PATH: np.column_stack([np.concatenate([vs, vl]), fv])})
