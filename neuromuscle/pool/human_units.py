"""Muscle units that fit human motor units: twitch speed and force of each unit as functions of its recruitment
threshold (% MVC), fitted per recording on a calibration window.

Model: unit i with recruitment threshold th_i (% MVC, the recorded force at its first discharge) is a Kim muscle unit
(base set CT09, isometric) whose Modules 1-2 run ``speed_i = S0 * RS ** (th_i / 100)`` times faster than CT09 (the
twitch time to peak, about 81 ms at speed 1, shrinks as 1 / speed) and whose force is ``RP ** (th_i / 100)``
(relative) times ``gap_i ** W``.  The recorded units are a sample of the pool: unit i stands for the pool's units
whose thresholds lie nearer to its own than to its recorded neighbours', a threshold interval of ``gap_i`` % MVC
(:func:`represented_gaps`; the lowest unit's reaches down to 0 % MVC, so it stands for the unrecorded units recruited
before it); W = 1 is a pool spread uniformly over thresholds, W = 0 gives every recorded unit the same weight.
The rate-dependent gain is the one Modules 1-2 give: no separate force-rate curve.  The predicted force is
``scale * sum_i P0_i g_i(t - delay; speed_i) + offset``, g_i being unit i's force per newton of P0 under its
recorded discharges.

Because the speeds are continuous, every unit's g_i is simulated once at each speed of :data:`SPEED_GRID` (one pool
run per speed, every P0 = 1 N) and interpolated linearly in log speed between the two nearest grid speeds.

Priors (uniform over the ranges of :data:`BOUNDS`), from published human motor-unit properties:

- S0: twitch contraction times of human motor units from about 40 to 200 ms: tibialis anterior units span about
  20-85 ms in spike-triggered averages (Van Cutsem et al., as summarised by Nagamori et al. 2021), which shorten
  the contraction time of units slower than about 50 ms because their twitches fuse at the trigger rates (Taylor
  et al. 2002); medial gastrocnemius has slow type S units (Garnett et al. 1979); the whole triceps surae's
  twitches, seen at the joint, take 114 +/- 20 ms (medial gastrocnemius) and 157 +/- 15 ms (soleus) to peak
  (Vandervoort & McComas 1983), so the slowest units reach about 200 ms (the soleus mean + 3 SD).  The
  low-threshold units are the slow end: S0 = 81 ms / contraction time in 0.4..2 (CT09's time to peak is 81 ms
  at speed 1; 202 ms at 0.4).
- RS: contraction times shorten with threshold over at most a 3-fold range across the pool (Fuglevand et al. 1993):
  RS in 1..3 per 100 % MVC of threshold.
- RP: twitch force grows with recruitment threshold (Milner-Brown, Stein & Yemm 1973; Desmedt & Godaux 1977), over
  a range of up to 100-fold across the pool (Fuglevand et al. 1993): RP in 1..300 per 100 % MVC of threshold.
- W: 0..2, how the sample stands for the pool (no published prior: a property of the decomposition's sample).
- delay: 0..200 ms between the decomposed discharges and the transducer force.

Intervals: each parameter's 95 % interval from the curvature of the calibration cost at the fit (Gauss-Newton),
its residual variance inflated by the residuals' autocorrelation (effective sample count n (1 - r1) / (1 + r1),
r1 the lag-1 autocorrelation), clipped to the prior range.  Units: ms, % MVC.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..parameters import ParameterSet
from ..validate import finite_series
from .force_calibration import unit_force_basis
from .window_fit import WindowScores, bounded_minimize, linear_scale_offset, window_mask, window_scores

#: Twitch speeds (relative to CT09) at which every unit's force is simulated; between them it is interpolated.
SPEED_GRID = (0.4, 0.65, 0.95, 1.4, 2.1, 3.2)
#: (low, high, logarithmic) of the fitted parameters: the priors of the module docstring.
BOUNDS = {"S0": (0.4, 2.0, True), "RS": (1.0, 3.0, True), "RP": (1.0, 300.0, True), "W": (0.0, 2.0, False),
          "delay_ms": (0.0, 200.0, False)}
#: Starting points of the search.
STARTS = ({"S0": 1.0, "RS": 1.5, "RP": 10.0, "W": 1.0, "delay_ms": 40.0},
          {"S0": 1.6, "RS": 1.2, "RP": 2.0, "W": 0.3, "delay_ms": 20.0})
#: Smallest threshold interval (% MVC) a recorded unit stands for (units recruited at the same force).
MIN_GAP_PERCENT_MVC = 0.25


@dataclass(frozen=True)
class SpeedBases:
    """Every unit's force per newton of P0 (1/1, shape (speeds, units, samples)) at each speed of ``speeds`` and
    sample times ``t_ms`` (ms)."""

    t_ms: np.ndarray
    speeds: tuple[float, ...]
    forces: np.ndarray

    def at(self, unit_speeds: np.ndarray) -> np.ndarray:
        """Each unit's force per newton (shape (units, samples)) at its own speed, linear in log speed between the
        two nearest grid speeds (clipped to the grid)."""
        ls = np.log(self.speeds)
        s = np.clip(np.log(np.asarray(unit_speeds, float)), ls[0], ls[-1])
        k = np.clip(np.searchsorted(ls, s, side="right") - 1, 0, len(ls) - 2)
        w = ((s - ls[k]) / (ls[k + 1] - ls[k]))[:, None]
        units = np.arange(self.forces.shape[1])
        return (1.0 - w) * self.forces[k, units] + w * self.forces[k + 1, units]

    def weighted_sum(self, unit_speeds: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """``weights @ self.at(unit_speeds)`` (shape (samples,)) as one product per grid speed, without forming
        every unit's interpolated force: the cost of a fit's evaluation."""
        ls = np.log(self.speeds)
        s = np.clip(np.log(np.asarray(unit_speeds, float)), ls[0], ls[-1])
        k = np.clip(np.searchsorted(ls, s, side="right") - 1, 0, len(ls) - 2)
        w = (s - ls[k]) / (ls[k + 1] - ls[k])
        units = np.arange(self.forces.shape[1])
        coef = np.zeros(self.forces.shape[:2])
        np.add.at(coef, (k, units), (1.0 - w) * weights)
        np.add.at(coef, (k + 1, units), w * weights)
        return np.einsum("su,sut->t", coef, self.forces, optimize=True)


def speed_bases(discharges_ms: Sequence[np.ndarray], duration_ms: float, muscle: ParameterSet, *,
                speeds: Sequence[float] = SPEED_GRID, dt_ms: float = 0.05, length_mm: float = -8.0) -> SpeedBases:
    """Simulate every unit under its discharges (ms) at every twitch speed of ``speeds`` (one pool run each, time
    step ``dt_ms``, length ``length_mm`` mm); forces sampled every 1 ms."""
    sp = tuple(sorted(float(s) for s in speeds))
    if len(sp) < 2:
        raise InputError(f"speed_bases needs at least two speeds, got {list(speeds)}")
    out, t = [], None
    for s in sp:
        t, g = unit_force_basis(discharges_ms, duration_ms, muscle, speed=s, length_mm=length_mm, dt_ms=dt_ms)
        out.append(g)
    return SpeedBases(np.asarray(t), sp, np.stack(out))


def represented_gaps(thresholds_percent_mvc: np.ndarray) -> np.ndarray:
    """The threshold interval (% MVC) each recorded unit stands for: from the midpoint to the next lower recorded
    threshold (0 for the lowest) to the midpoint to the next higher one (for the highest, as far above it as the
    lower midpoint is below), shared equally by units recruited at the same threshold; at least
    :data:`MIN_GAP_PERCENT_MVC`.  Any order of units."""
    th = np.asarray(thresholds_percent_mvc, float)
    u, inverse, counts = np.unique(th, return_inverse=True, return_counts=True)
    mids = np.concatenate([[0.0], 0.5 * (u[1:] + u[:-1])])
    gaps = np.diff(np.append(mids, u[-1] + (u[-1] - mids[-1])))
    return np.maximum(gaps[inverse] / counts[inverse], MIN_GAP_PERCENT_MVC)


def unit_properties(thresholds_percent_mvc: np.ndarray, s0: float, rs: float, rp: float, w: float = 0.0
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(speed, relative force) of units with these recruitment thresholds (% MVC): S0 * RS ** (th / 100) and
    RP ** (th / 100) * gap ** W (gap: :func:`represented_gaps`)."""
    th = np.asarray(thresholds_percent_mvc, float)
    x = th / 100.0
    return s0 * rs ** x, rp ** x * (represented_gaps(th) ** w if w else 1.0)


def _delayed(t_ms: np.ndarray, h: np.ndarray, delay_ms: float) -> np.ndarray:
    return np.interp(t_ms - delay_ms, t_ms, h)


@dataclass(frozen=True)
class HumanUnitFit(WindowScores):
    """The fitted threshold-based units: parameters (:data:`BOUNDS`) with 95 % intervals, scale and offset, each
    unit's speed and relative P0 (recruitment order); windows, NRMSE and prediction (% MVC)."""

    params: dict[str, float] = field(default_factory=dict)
    intervals: dict[str, tuple[float, float]] = field(default_factory=dict)
    scale: float = 1.0
    offset: float = 0.0
    speeds: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    p0: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def summary(self) -> dict[str, object]:
        """The fit as a JSON-ready dict."""
        return {**self.params, "intervals_95": {k: list(v) for k, v in self.intervals.items()},
                "scale": self.scale, "offset": self.offset, **self.scores()}


def relative_force(bases: SpeedBases, thresholds_percent_mvc: np.ndarray, params: dict[str, float]) -> np.ndarray:
    """The summed force (before scale and offset) of units with these thresholds (% MVC) under ``params``
    (:data:`BOUNDS` names), at ``bases.t_ms``."""
    th = np.asarray(thresholds_percent_mvc, float)
    p = params
    speeds, p0 = unit_properties(th, p["S0"], p["RS"], p["RP"], p["W"])
    return _delayed(bases.t_ms, bases.weighted_sum(speeds, p0), p["delay_ms"])


def _intervals(bases: SpeedBases, th: np.ndarray, y: np.ndarray, cal: np.ndarray, best: dict[str, float]
               ) -> dict[str, tuple[float, float]]:
    """95 % Gauss-Newton intervals of the nonlinear parameters (module docstring), scale and offset profiled."""
    def residual(p: dict[str, float]) -> np.ndarray:
        h = relative_force(bases, th, p)[cal]
        scale, offset = linear_scale_offset(h, y[cal])
        return scale * h + offset - y[cal]

    r0 = residual(best)
    n = r0.size
    r1 = float(np.corrcoef(r0[:-1], r0[1:])[0, 1]) if n > 2 else 0.0
    n_eff = max(n * (1.0 - r1) / (1.0 + r1), len(best) + 3.0)
    sigma2 = float(r0 @ r0) / (n_eff - len(best))
    cols = []
    for name, (lo, hi, _) in BOUNDS.items():
        step = 1e-3 * (hi - lo)
        up = dict(best, **{name: min(best[name] + step, hi)})
        dn = dict(best, **{name: max(best[name] - step, lo)})
        cols.append((residual(up) - residual(dn)) / (up[name] - dn[name]))
    jac = np.column_stack(cols)
    cov = sigma2 * np.linalg.pinv(jac.T @ jac)
    half = 1.96 * np.sqrt(np.maximum(np.diag(cov), 0.0))
    return {name: (max(best[name] - h, lo), min(best[name] + h, hi))
            for (name, (lo, hi, _)), h in zip(BOUNDS.items(), half)}


def fit_human_units(bases: SpeedBases, thresholds_percent_mvc: Sequence[float], target: Sequence[float], *,
                    calibration_ms: tuple[float, float], heldout_ms: tuple[float, float]) -> HumanUnitFit:
    """Fit S0, RS, RP, W, delay (within the priors), scale and offset (module docstring) to ``target`` (% MVC at
    ``bases.t_ms``) on ``calibration_ms``; NRMSE there and on ``heldout_ms`` ([start, end) ms)."""
    t = bases.t_ms
    y = finite_series("target force", target)
    th = finite_series("recruitment thresholds", thresholds_percent_mvc)
    if y.size != t.size or th.size != bases.forces.shape[1]:
        raise InputError(f"target ({y.size}) must match t ({t.size}) and thresholds ({th.size}) the units "
                         f"({bases.forces.shape[1]})")
    cal = window_mask(t, calibration_ms, "calibration")
    window_mask(t, heldout_ms, "held-out")

    def cost(p: dict[str, float]) -> float:
        h = relative_force(bases, th, p)[cal]
        scale, offset = linear_scale_offset(h, y[cal])
        return float(np.sum((scale * h + offset - y[cal]) ** 2))

    best = min((bounded_minimize(cost, s, BOUNDS) for s in STARTS), key=cost)
    h = relative_force(bases, th, best)
    scale, offset = linear_scale_offset(h[cal], y[cal])
    if scale <= 0:
        raise InputError("the calibration found no positive unit force: the force does not follow the discharges")
    speeds, p0 = unit_properties(th, best["S0"], best["RS"], best["RP"], best["W"])
    return HumanUnitFit(**window_scores(t, y, scale * h + offset, calibration_ms, heldout_ms), params=best,
                        intervals=_intervals(bases, th, y, cal, best), scale=scale, offset=offset, speeds=speeds,
                        p0=p0)
