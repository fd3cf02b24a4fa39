"""Synthetic measured trials: a trial simulated from known parameters, plus Gaussian noise.

The data of the package's example file (:mod:`neuromuscle.measured.example`), of ``neuromuscle bench fit`` and of
the tests: the simulation is :func:`.evaluate.trial_simulation`, so a fit with the same options sees the model
it was made with.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

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
