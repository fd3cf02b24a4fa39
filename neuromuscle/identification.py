"""Identification tools of the seed: eqs 13-16 (Hill/Mashima coefficients), eq 18 (length compensation),
eq 17 (NRMSE), and the inverse of Module 3 that estimates activation A(t) from measured force and length.

Units: time ms, length mm, velocity mm/s, force N (see the spec's units section).
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np
from scipy import signal

from .validate import finite_number, positive_number
from .errors import InputError

#: Largest condition number accepted for the 2x2 systems of eqs 13-16.
MAX_CONDITION = 1e10

#: Module 3 parameters needed by inverse_activation.
MODULE3_KEYS = ("P0", "KSE", "g1", "g2", "a0", "b0", "c0", "d0")


# ---------------------------------------------------------------------------------------------- validation

def _points(name: str, points: object) -> np.ndarray:
    """``points`` as an (n, 2) float array of finite pairs."""
    try:
        arr = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a sequence of (x, y) number pairs") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InputError(f"{name} must be a sequence of (x, y) pairs, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite (point {int(np.flatnonzero(~np.isfinite(arr).all(1))[0])})")
    return arr


def _series(name: str, values: object) -> np.ndarray:
    """``values`` as a finite 1-D float array."""
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a 1-D array of numbers") from None
    if arr.ndim != 1:
        raise InputError(f"{name} must be 1-D, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} is not finite at sample {int(np.flatnonzero(~np.isfinite(arr))[0])}")
    return arr




def _solve_2x2(name: str, matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    if not np.isfinite(np.linalg.cond(matrix)) or np.linalg.cond(matrix) > MAX_CONDITION:
        raise InputError(f"{name}: the two points give a singular system (same point twice, or collinear "
                         "with the isometric point); choose two distinct velocities")
    return np.linalg.solve(matrix, rhs)


# ------------------------------------------------------------------------------------------- eqs 13-16

def hill_mashima_coefficients(points: Sequence[tuple[float, float]], P0_N: float) -> dict[str, float]:
    """Hill (a0 N, b0 mm/s) and Mashima (c0 N, d0 mm/s) coefficients from four (velocity mm/s, tension N)
    points at full activation and optimal length: two shortening (V < 0, 0 <= T < P0) and two lengthening
    (V > 0, T > P0).

    Solves V (T + a0) = -b0 (P0 - T) for the shortening pair and V (2 P0 - T + c0) = d0 (T - P0) for the
    lengthening pair.
    """
    pts = _points("points", points)
    p0 = positive_number("P0_N", P0_N)
    short, lengthen = pts[pts[:, 0] < 0.0], pts[pts[:, 0] > 0.0]
    if len(pts) != 4 or len(short) != 2 or len(lengthen) != 2:
        raise InputError("points must hold exactly two shortening (V < 0) and two lengthening (V > 0) "
                         f"(velocity mm/s, tension N) pairs; got {pts.tolist()}")
    if np.any(short[:, 1] < 0.0) or np.any(short[:, 1] >= p0):
        raise InputError(f"points: shortening tensions must lie in [0, P0_N = {p0}) N, got {short[:, 1]}")
    if np.any(lengthen[:, 1] <= p0):
        raise InputError(f"points: lengthening tensions must exceed P0_N = {p0} N, got {lengthen[:, 1]}")
    v_s, t_s = short[:, 0], short[:, 1]
    a0, b0 = _solve_2x2("points (shortening)", np.column_stack([v_s, p0 - t_s]), -v_s * t_s)
    v_l, t_l = lengthen[:, 0], lengthen[:, 1]
    c0, d0 = _solve_2x2("points (lengthening)", np.column_stack([v_l, p0 - t_l]), -v_l * (2.0 * p0 - t_l))
    return {"a0": float(a0), "b0": float(b0), "c0": float(c0), "d0": float(d0)}


# ------------------------------------------------------------------------------------------------ eq 18

def _line(name: str, pts: np.ndarray) -> tuple[float, float]:
    """Least-squares (slope, intercept) through (Xm mm, phi) points."""
    if np.unique(pts[:, 0]).size < 2:
        raise InputError(f"{name}: a line needs points at two or more distinct lengths, got {pts.tolist()}")
    slope, intercept = np.polyfit(pts[:, 0], pts[:, 1], 1)
    return float(slope), float(intercept)


def length_compensation_coefficients(points: Sequence[tuple[float, float]], x_opt_mm: float,
                                     split: bool = True) -> dict[str, float]:
    """Eq 18 coefficients phi1 (1/mm), phi2, phi3 (1/mm), phi4 from (Xm mm, phi) points.

    ``split=True``: one least-squares line through the points with Xm <= x_opt_mm (phi1, phi2) and one through
    those with Xm >= x_opt_mm (phi3, phi4); a point at the optimum belongs to both.  ``split=False``: one line
    through all points, returned as both halves.
    """
    pts = _points("points", points)
    x_opt = finite_number("x_opt_mm", x_opt_mm)
    if split:
        phi1, phi2 = _line(f"points at or below x_opt_mm = {x_opt}", pts[pts[:, 0] <= x_opt])
        phi3, phi4 = _line(f"points at or above x_opt_mm = {x_opt}", pts[pts[:, 0] >= x_opt])
    else:
        phi1, phi2 = phi3, phi4 = _line("points", pts)
    return {"phi1": phi1, "phi2": phi2, "phi3": phi3, "phi4": phi4}


# ------------------------------------------------------------------------------------------------ eq 17

def nrmse_percent(measured: Sequence[float], simulated: Sequence[float]) -> float:
    """Eq 17: 100 * RMS(measured - simulated) / (max(measured) - min(measured)), in % (any force unit)."""
    m = _series("measured", measured)
    s = _series("simulated", simulated)
    if m.shape != s.shape:
        raise InputError(f"simulated must match measured in shape, got {s.shape} and {m.shape}")
    if m.size == 0:
        raise InputError("measured is empty")
    span = float(m.max() - m.min())
    if span <= 0.0:
        raise InputError("measured has zero range (constant): NRMSE is undefined")
    return 100.0 * math.sqrt(float(np.mean((m - s) ** 2))) / span


# ------------------------------------------------------------------------------------ inverse Module 3

def _module3(params: Mapping[str, float]) -> dict[str, float]:
    missing = [k for k in MODULE3_KEYS if k not in params]
    if missing:
        raise InputError(f"params lacks {', '.join(missing)} (needs {', '.join(MODULE3_KEYS)})")
    positive = ("P0", "KSE", "g2", "b0", "d0")
    return {k: (positive_number if k in positive else finite_number)(f"params[{k!r}]", params[k]) for k in MODULE3_KEYS}


def _smooth(name: str, y: np.ndarray, t_ms: np.ndarray, smooth_ms: float) -> np.ndarray:
    """Zero-phase Savitzky-Golay smoothing (cubic) over a window of about ``smooth_ms`` (ms)."""
    dt = np.diff(t_ms)
    if np.ptp(dt) > 1e-6 * dt.mean():
        raise InputError("smooth_ms needs a uniform time base t_ms; resample first")
    window = 2 * int(round(smooth_ms / dt.mean() / 2.0)) + 1
    if window < 5 or window > y.size:
        raise InputError(f"smooth_ms ({smooth_ms} ms) must span 5 to {y.size} samples of {dt.mean()} ms "
                         f"(got {window}) for {name}")
    return signal.savgol_filter(y, window, 3, mode="interp")


def _contractile_force(force: np.ndarray, v_ce: np.ndarray, p: Mapping[str, float]) -> np.ndarray:
    """Fc (N) that makes the CE move at v_ce (mm/s) under force F (N): eqs 10/11 inverted.

    NaN where the velocity is at or beyond the Hill or Mashima asymptote (no finite Fc produces it).
    """
    short = v_ce <= 0.0
    num = np.where(short, force * (p["b0"] - v_ce), force * (p["d0"] + v_ce))
    den = np.where(short, p["b0"] + p["a0"] * v_ce / p["P0"], p["d0"] + v_ce * (2.0 + p["c0"] / p["P0"]))
    ok = den > 0.0
    return np.where(ok, num / np.where(ok, den, 1.0), np.nan)


def inverse_activation(t_ms: Sequence[float], force_N: Sequence[float], length_mm: Sequence[float],
                       params: Mapping[str, float], smooth_ms: float | None = None) -> np.ndarray:
    """Activation A(t) (dimensionless) estimated from measured force F (N) and length Xm (mm) at times t (ms).

    Inverts Module 3 (spec, "Inverse"): V_CE = dXm/dt - (dF/dt) / (P0 KSE) in mm/s; Fc from eq 10 (V_CE <= 0)
    or eq 11 (V_CE > 0); A = Fc / (P0 g(Xm)).  Derivatives use numpy.gradient on the given (possibly
    non-uniform) time base.  ``smooth_ms`` (ms) first applies a zero-phase cubic Savitzky-Golay filter to F
    and Xm (uniform time base only; the first and last half-window are the least reliable).  ``params`` maps
    P0, KSE, g1, g2, a0, b0, c0, d0 to values in the model's units (e.g. a ParameterSet).  Samples at or
    beyond a velocity asymptote (no finite Fc gives that V_CE) come out NaN.
    """
    t = _series("t_ms", t_ms)
    force = _series("force_N", force_N)
    xm = _series("length_mm", length_mm)
    if force.shape != t.shape or xm.shape != t.shape:
        raise InputError(f"force_N {force.shape} and length_mm {xm.shape} must match t_ms {t.shape}")
    if t.size < 3:
        raise InputError("t_ms needs at least 3 samples")
    if np.any(np.diff(t) <= 0.0):
        bad = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
        raise InputError(f"t_ms must be strictly increasing (sample {bad})")
    p = _module3(params)
    if smooth_ms is not None:
        width = positive_number("smooth_ms", smooth_ms)
        force, xm = _smooth("force_N", force, t, width), _smooth("length_mm", xm, t, width)
    per_s = 1000.0  # d/dt in 1/ms -> 1/s
    dxm_dt = np.gradient(xm, t, edge_order=2)  # mm/ms
    dforce_dt = np.gradient(force, t, edge_order=2)  # N/ms
    v_ce = per_s * (dxm_dt - dforce_dt / (p["P0"] * p["KSE"]))  # mm/s
    g = np.exp(-(((xm - p["g1"]) / p["g2"]) ** 2))
    return _contractile_force(force, v_ce, p) / (p["P0"] * g)
