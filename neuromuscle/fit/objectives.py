"""Objectives of a fit: how the force errors of the trials are weighted into one residual vector.

* ``"sse"``: residuals sqrt(w_k) (F_sim - F_meas) (N); cost = sum of squares (eq 5 of van Zandwijk et al. 1998,
  weighted by
  trial).
* ``"nrmse"``: residuals sqrt(w_k) 100 (F_sim - F_meas) / (range_k sqrt(n_k)), so that
  cost = sum_k w_k NRMSE_k^2 (%^2, eq 17): trials of different size and force range count alike.

The cost of a fit is that sum of squares (not scipy's half of it).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..measured import Trial

OBJECTIVES = ("sse", "nrmse")


def residual_scales(trials: Sequence[Trial], weights: Sequence[float], objective: str) -> list[float]:
    """The factor that turns each trial's force error (N) into residuals of ``objective`` (one of
    ``OBJECTIVES``)."""
    scales = []
    for t, w in zip(trials, weights):
        if objective == "sse":
            scales.append(math.sqrt(w))
        else:
            span = float(np.max(t.force) - np.min(t.force))
            if span <= 0:
                raise InputError(f"trial '{t.trial_id}': constant force, NRMSE objective undefined")
            scales.append(math.sqrt(w) * 100.0 / (span * math.sqrt(t.n_samples)))
    return scales


def weighted_residuals(scales: Sequence[float | np.ndarray], simulated: Sequence[np.ndarray],
                       trials: Sequence[Trial]) -> np.ndarray:
    """One residual vector: each trial's simulated minus measured force (N) times its scale (a number, or one
    per sample)."""
    return np.concatenate([s * (f - t.force) for s, f, t in zip(scales, simulated, trials)])
