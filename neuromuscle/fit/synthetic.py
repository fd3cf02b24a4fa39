"""Synthetic measured trials: a trial simulated from known parameters, plus Gaussian or AR(1) noise.

The data of the package's example file (:mod:`neuromuscle.measured.example`), of ``neuromuscle bench fit`` and of
the tests: the simulation is :func:`.evaluate.trial_simulation`, so a fit with the same options sees the model
it was made with.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.signal import lfilter

from ..errors import InputError
from ..measured import Trial
from ..parameters import ParameterSet
from .evaluate import trial_simulation


def synthetic_trial(params: ParameterSet, trial_id: str, time_s: np.ndarray, stimulus_times_s: Sequence[float], *,
                    protocol: str = "twitch", length_mm: float | None = None, length: np.ndarray | None = None,
                    noise_N: float = 0.0, rng: np.random.Generator | None = None, dt_ms: float = 0.05,
                    **simulation: Any) -> Trial:
    """A measured-data Trial (N, mm) at time_s (s): the force of ``params`` simulated by ``trial_simulation``
    (dt_ms, and its keyword options ``simulation``: record_dt_ms, settle_ms, ...) plus Gaussian noise of sd
    noise_N (N) drawn from ``rng`` (required with noise, so that the data are reproducible; no draw when
    noise_N is 0).  Isometric at length_mm (mm), or the sampled ``length`` (mm, one value per time sample)."""
    if noise_N and rng is None:
        raise InputError(f"trial '{trial_id}': noise_N = {noise_N} N needs rng (np.random.default_rng(seed))")
    time_s = np.asarray(time_s, dtype=float)
    tr = Trial(trial_id=trial_id, protocol=protocol, time_s=time_s, force=np.zeros_like(time_s), force_unit="N",
               length_unit="mm", length_const=length_mm, length=length,
               stimulus_times_s=np.asarray(stimulus_times_s, dtype=float))
    force = trial_simulation(params, tr, dt_ms, **simulation)
    if noise_N:
        force = force + rng.normal(0.0, noise_N, force.size)
    tr.force = force
    return tr


def ar1_noise(n: int, sd_N: float, tau_ms: float, sample_ms: float, rng: np.random.Generator) -> np.ndarray:
    """n samples (every sample_ms, ms) of stationary AR(1) noise with marginal sd sd_N (N) and correlation time
    tau_ms (ms; lag-1 correlation exp(-sample_ms / tau_ms); 0: white), as force transducers give."""
    phi = float(np.exp(-sample_ms / tau_ms)) if tau_ms > 0 else 0.0
    x = sd_N * rng.standard_normal(n)
    x[1:] *= np.sqrt(1.0 - phi * phi)
    return lfilter([1.0], [1.0, -phi], x)
