"""Closed-form identification of Module 3 coefficients: eqs 13-16 (Hill a0, b0 and Mashima c0, d0 from four
velocity-tension points) and eq 18 (length compensation phi1..phi4 from (Xm, phi) points).

Units: length mm, velocity mm/s, force N (see the spec's units section).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import InputError
from ..validate import finite_number, positive_number

#: Largest condition number accepted for the 2x2 systems of eqs 13-16.
MAX_CONDITION = 1e10


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


def _solve_2x2(name: str, matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """The solution of a well-conditioned 2x2 system; InputError naming ``name`` when it is (nearly) singular."""
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
