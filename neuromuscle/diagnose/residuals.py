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

Rest (``rest_trend_z``): where the model's muscle is quiet -- an isometric trial, before its first stimulus or at
least ``REST_AFTER_MS`` after a stimulus, with the simulated force within ``REST_MODEL_TOL`` noise sd of its
level before the first stimulus -- no parameter of Modules 1-3 and no cause of the catalogue can make the force
change.  The least-squares slope of the residual against time over those samples, divided by its standard error
under the trial's AR(1) noise (sd / sqrt(sum (t - tbar)^2) x sqrt((1 + rho) / (1 - rho))), is a z score: force
that changes while the muscle rests (a drifting transducer, a process outside the muscle).  A constant offset
(e.g. a passive force misfit at that length) has no slope.  On a synth null preparation (no effect, every
parameter ~20 % off) the 17 isometric trials gave |z| <= 2.0 (median 0.59, as for N(0, 1)); with the
out-of-catalogue drift at its weakest, 12 of 17 gave |z| > 3.
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
REST_AFTER_MS = 250.0  # a stimulus' force has relaxed by then in the model (CT09 twitch: < 1 % of peak)
REST_MODEL_TOL = 0.25  # rest: the simulated force within this many noise sd of its pre-stimulus level
MIN_REST_NEFF = 10.0  # fewest independent rest samples for a trial's rest variation


@dataclass(frozen=True)
class Noise:
    """A trial's noise: sd (N), lag-1 correlation, and n_eff = n (1 - rho) / (1 + rho) (independent samples)."""

    sd_N: float
    rho: float
    n_eff: float

    @property
    def chi2_weight(self) -> float:
        """The weight (1/N^2) of a squared residual (N^2) in the autocorrelation-corrected chi-square of the
        verdict, the fits and the screening: (1 - rho) / ((1 + rho) sd^2)."""
        return (1.0 - self.rho) / ((1.0 + self.rho) * self.sd_N ** 2)

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


def rest_mask(trial: Trial, simulated: np.ndarray, sd_N: float) -> np.ndarray:
    """Samples where the model's muscle is quiet (module docstring); all False in a trial that moves or has no
    sample before its first stimulus."""
    t_s = np.asarray(trial.time_s, dtype=float)
    x = trial.length_at()
    stim = np.sort(np.asarray(trial.stimulus_times_s, dtype=float))
    none = np.zeros(t_s.size, bool)
    if stim.size == 0 or t_s.size < 2 or np.any(np.abs(np.gradient(x, t_s)) > MOVING_MM_S):
        return none
    before = t_s < stim[0]
    if not np.any(before):
        return none
    sim = np.asarray(simulated, dtype=float)
    level = float(np.median(sim[before]))
    k = np.searchsorted(stim, t_s, side="right")
    since_ms = np.where(k >= 1, 1000.0 * (t_s - stim[np.maximum(k - 1, 0)]), np.inf)
    quiet = np.abs(sim - level) <= REST_MODEL_TOL * sd_N
    return quiet & (before | (since_ms >= REST_AFTER_MS))



def rest_trend_z(trial: Trial, residual: np.ndarray, simulated: np.ndarray, noise: Noise) -> float | None:
    """z score (1) of the residual's (N) linear trend in time over the trial's rest samples (module docstring);
    None when the trial has fewer than MIN_REST_NEFF independent rest samples."""
    m = rest_mask(trial, simulated, noise.sd_N)
    n = int(m.sum())
    if n * (1.0 - noise.rho) / (1.0 + noise.rho) < MIN_REST_NEFF or noise.sd_N <= 0:
        return None
    t = np.asarray(trial.time_s, dtype=float)[m]
    t = t - t.mean()
    r = np.asarray(residual, dtype=float)[m]
    stt = float(t @ t)
    if stt <= 0:
        return None
    slope = float(t @ (r - r.mean())) / stt
    se = noise.sd_N / np.sqrt(stt) * np.sqrt((1.0 + noise.rho) / (1.0 - noise.rho))
    return slope / se
