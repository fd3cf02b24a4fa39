"""The inverse of Module 3: activation A(t) estimated from measured force F and length Xm (spec, "Inverse").

Units: time ms, length mm, velocity mm/s, force N.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
from scipy import signal

from ..errors import InputError
from ..validate import finite_number, finite_series, positive_number
from .module3 import MODULE3_KEYS, contractile_force, force_length


def _module3(params: Mapping[str, float]) -> dict[str, float]:
    """The Module 3 values of ``params`` as floats; InputError naming a missing or invalid one."""
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
    t = finite_series("t_ms", t_ms)
    force = finite_series("force_N", force_N)
    xm = finite_series("length_mm", length_mm)
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
    g = force_length(xm, p["g1"], p["g2"])
    return contractile_force(force, v_ce, p) / (p["P0"] * g)
