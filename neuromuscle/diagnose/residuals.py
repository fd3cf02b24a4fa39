"""Step 3 of the diagnosis: residuals against what could explain them, the noise level, A(t) by inversion.

Explanatory variables, per sample of a trial (``explanatory_variables``; units in ``VARIABLES``):
length (mm), velocity (mm/s), time since movement onset (ms; 0 before and in isometric trials), stimulation rate
(Hz, 1000 / the last inter-stimulus interval), ISI (ms, the last interval; 0 before the second stimulus),
position in the train (stimuli delivered so far), recent activity (stimuli in the last 1 s, exponentially
weighted), stretch history (mm: length change since movement onset, + stretch, - shortening), time since the
last stimulus (ms), and the activation residual A_measured - A_baseline, both from inverting Module 3
(:func:`neuromuscle.analysis.inverse.inverse_activation`, 5 ms smoothing).

Noise (``noise_level``): each trial's residual taken as smooth model error plus AR(1) noise (sd s, lag-1
correlation rho).  First differences remove the smooth part: for AR(1) noise var(diff) = 2 s^2 (1 - rho) and
the lag-1 autocorrelation of the differences is -(1 - rho) / 2, so rho = 1 + 2 r1 and s^2 = var(diff) /
(2 (1 - rho)) (robust to a misfit that varies slowly against the sampling interval).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..analysis.inverse import inverse_activation
from ..errors import InputError
from ..measured import Trial

VARIABLES: dict[str, str] = {
    "length": "mm", "velocity": "mm/s", "time_since_movement_onset": "ms", "stimulation_rate": "Hz",
    "isi": "ms", "position_in_train": "stimuli", "recent_activity": "stimuli/s", "stretch_history": "mm",
    "time_since_last_stimulus": "ms", "activation_residual": "1",
}
MOVING_MM_S = 0.5  # |velocity| above this (mm/s) counts as movement
RECENT_S = 1.0
RHO_MAX = 0.95


@dataclass(frozen=True)
class Noise:
    """A trial's noise: sd (N), lag-1 correlation, and n_eff = n (1 - rho) / (1 + rho) (independent samples)."""

    sd_N: float
    rho: float
    n_eff: float

    def to_json(self) -> dict:
        return {"sd_N": self.sd_N, "rho": self.rho, "n_eff": self.n_eff}


def noise_level(residual: np.ndarray) -> Noise:
    """AR(1) noise of a residual (N) from its first differences (module docstring)."""
    r = np.asarray(residual, dtype=float)
    if r.size < 8:
        raise InputError(f"a residual of {r.size} samples is too short to estimate the noise")
    d = np.diff(r)
    d = d - d.mean()
    var_d = float(d @ d) / d.size
    r1 = float(d[1:] @ d[:-1]) / float(d @ d) if var_d > 0 else -0.5
    rho = float(np.clip(1.0 + 2.0 * r1, 0.0, RHO_MAX))
    sd = float(np.sqrt(var_d / (2.0 * (1.0 - rho))))
    return Noise(sd, rho, r.size * (1.0 - rho) / (1.0 + rho))


def explanatory_variables(trial: Trial, params: Mapping[str, float] | None = None,
                          simulated: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Every variable of ``VARIABLES`` at the trial's samples (the activation residual when ``params`` and the
    baseline's ``simulated`` force (N) are given)."""
    t_s = np.asarray(trial.time_s, dtype=float)
    t_ms = 1000.0 * (t_s - t_s[0])
    x = trial.length_at()
    v = np.gradient(x, t_s) if x.size > 1 else np.zeros_like(x)
    moving = np.abs(v) > MOVING_MM_S
    out: dict[str, np.ndarray] = {"length": x, "velocity": v}
    if np.any(moving):
        i0 = int(np.argmax(moving))
        since = np.where(np.arange(x.size) >= i0, t_ms - t_ms[i0], 0.0)
        out["time_since_movement_onset"] = since
        out["stretch_history"] = np.where(np.arange(x.size) >= i0, x - x[i0], 0.0)
    else:
        out["time_since_movement_onset"] = np.zeros_like(x)
        out["stretch_history"] = np.zeros_like(x)
    stim = np.sort(np.asarray(trial.stimulus_times_s, dtype=float))
    k = np.searchsorted(stim, t_s, side="right")  # stimuli delivered by each sample
    out["position_in_train"] = k.astype(float)
    isi = np.zeros_like(t_s)
    last = np.full_like(t_s, np.nan)
    has = k >= 1
    last[has] = stim[k[has] - 1]
    two = k >= 2
    isi[two] = 1000.0 * (stim[k[two] - 1] - stim[k[two] - 2])
    out["isi"] = isi
    out["stimulation_rate"] = np.where(isi > 0, 1000.0 / np.where(isi > 0, isi, 1.0), 0.0)
    out["time_since_last_stimulus"] = np.where(has, 1000.0 * (t_s - np.nan_to_num(last)), 0.0)
    dt = t_s[:, None] - stim[None, :]
    out["recent_activity"] = np.sum(np.where(dt >= 0, np.exp(-np.clip(dt, 0, None) / RECENT_S), 0.0),
                                    axis=1) / RECENT_S
    if params is not None and simulated is not None:
        out["activation_residual"] = activation_residual(trial, params, simulated)
    return out


def activation_residual(trial: Trial, params: Mapping[str, float], simulated: np.ndarray) -> np.ndarray:
    """A(t) from the measured force minus A(t) from the baseline's force, both by inverting Module 3 (1);
    NaN where the inversion has no answer or the time base is not uniform."""
    t_ms = 1000.0 * np.asarray(trial.time_s, dtype=float)
    x = trial.length_at()
    try:
        a_meas = inverse_activation(t_ms, trial.force, x, params, smooth_ms=5.0)
        a_sim = inverse_activation(t_ms, simulated, x, params, smooth_ms=5.0)
    except InputError:
        return np.full(t_ms.shape, np.nan)
    return a_meas - a_sim


def correlation_ratio(values: np.ndarray, residual: np.ndarray, bins: int = 10) -> float:
    """eta^2: the fraction of the residual's variance explained by its mean in ``bins`` quantile bins of
    ``values`` (0 when the variable is constant)."""
    ok = np.isfinite(values) & np.isfinite(residual)
    v, r = values[ok], residual[ok]
    if v.size < 2 * bins or np.ptp(v) == 0 or np.var(r) == 0:
        return 0.0
    edges = np.unique(np.quantile(v, np.linspace(0, 1, bins + 1)))
    if edges.size < 3:
        return 0.0
    idx = np.clip(np.searchsorted(edges, v, side="right") - 1, 0, edges.size - 2)
    means = np.bincount(idx, weights=r) / np.maximum(np.bincount(idx), 1)
    return float(np.var(means[idx]) / np.var(r))


@dataclass(frozen=True)
class Structure:
    """Where the residual has structure: the variable that explains most of it (eta^2, pooled over the trials
    given) and each variable's eta^2."""

    best_variable: str
    best_eta2: float
    eta2: dict[str, float]


def residual_structure(trials: Mapping[str, Trial], residuals: Mapping[str, np.ndarray],
                       variables: Mapping[str, Mapping[str, np.ndarray]]) -> Structure:
    """Pool the trials' residuals (each divided by its trial's force range) and rank the variables by eta^2."""
    ids = [i for i in residuals if i in trials]
    if not ids:
        return Structure("none", 0.0, {})
    r = np.concatenate([residuals[i] / max(float(np.ptp(trials[i].force)), 1e-12) for i in ids])
    eta = {}
    for name in VARIABLES:
        if all(name in variables[i] for i in ids):
            eta[name] = correlation_ratio(np.concatenate([variables[i][name] for i in ids]), r)
    best = max(eta, key=eta.get) if eta else "none"
    return Structure(best, eta.get(best, 0.0), eta)
