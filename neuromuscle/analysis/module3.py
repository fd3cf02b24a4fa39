"""Module 3 of the Kim model (eqs 9-12): the one Python statement of its equations.

Force-length g(Xm) (eq 12), the contractile-element (CE) velocity of the Hill shortening branch (eq 10) and of
the Mashima lengthening branch (eq 11) as a function of the series-element force F and the CE capacity
Fc = P0 g(Xm) A, and their inverse forms: the tension at a velocity (full activation, optimum length) and the
capacity Fc that makes the CE move at a velocity under F. The NMODL twin is KimForce (mod/).

Units: length mm, force N, velocity mm/s (positive = lengthening); a0, c0 in N, b0, d0 in mm/s. ``params``
is any mapping holding P0, a0, b0, c0, d0 (a ParameterSet or a dict).
"""

from __future__ import annotations

from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike

#: The parameters of Module 3: P0 (N), KSE (1/mm), g1 (mm), g2 (mm), a0 (N), b0 (mm/s), c0 (N), d0 (mm/s).
MODULE3_KEYS = ("P0", "KSE", "g1", "g2", "a0", "b0", "c0", "d0")


def force_length(xm_mm: ArrayLike, g1_mm: float, g2_mm: float, P0_N: float = 1.0) -> np.ndarray:
    """Eq 12 at full activation: P0 exp(-((Xm - g1)/g2)^2) in N; with the default P0_N = 1, g(Xm) itself
    (dimensionless)."""
    return P0_N * np.exp(-(((np.asarray(xm_mm, dtype=float) - g1_mm) / g2_mm) ** 2))


def hill_velocity(F: ArrayLike, Fc: ArrayLike, a0: float, b0: float, P0: float) -> ArrayLike:
    """Eq 10, shortening (F <= Fc): dXCE/dt = -b0 (Fc - F) / (F + a0 Fc/P0) in mm/s."""
    return -b0 * (Fc - F) / (F + a0 * Fc / P0)


def mashima_velocity(F: ArrayLike, Fc: ArrayLike, c0: float, d0: float, P0: float) -> ArrayLike:
    """Eq 11, lengthening (F > Fc): dXCE/dt = -d0 (Fc - F) / (2 Fc - F + c0 Fc/P0) in mm/s; the denominator
    vanishes at the asymptote F = (2 + c0/P0) Fc."""
    return -d0 * (Fc - F) / (2.0 * Fc - F + c0 * Fc / P0)


#: Module 3's floor on a positive CE capacity, in P0 (mod/kim_m3_force.mod RANGE fcmin): a regularisation below
#: any measurable force.  The CE-SE loop's stiffness grows as 1/Fc and its nonlinear region shrinks as
#: Fc/(P0 KSE); with Fc -> 0 (a nearly silent unit; sweep draws with a resting A of 1e-9) no integrator resolves it.
FC_FLOOR = 1e-4


def floored_capacity(Fc: float, P0: float) -> float:
    """Fc (N) with Module 3's floor: a positive Fc below FC_FLOOR P0 is taken as FC_FLOOR P0; 0 stays 0."""
    return FC_FLOOR * P0 if 0.0 < Fc < FC_FLOOR * P0 else Fc


def ce_velocity(F: float, Fc: float, params: Mapping[str, float], vmax: float = 1e5) -> float:
    """CE velocity (mm/s) of eqs 10-11 at SE force F (N) and CE capacity Fc (N): Hill below Fc, Mashima above
    it up to its asymptote Fa = (2 + c0/P0) Fc, the velocity capped at vmax (mm/s) and vmax from Fa on (as
    documented in mod/kim_m3_force.mod)."""
    if Fc <= 0.0:
        return vmax if F > 0.0 else 0.0
    if F <= Fc:
        return hill_velocity(F, Fc, params["a0"], params["b0"], params["P0"])
    Fa = (2.0 + params["c0"] / params["P0"]) * Fc
    if F >= Fa:
        return vmax
    return min(mashima_velocity(F, Fc, params["c0"], params["d0"], params["P0"]), vmax)


def hill_tension(v: ArrayLike, a0: float, b0: float, P0: float) -> ArrayLike:
    """Eq 10 at Fc = P0 solved for the tension (N) at shortening velocity v (mm/s, < 0)."""
    return (b0 * P0 + a0 * v) / (b0 - v)


#: The most negative c0/P0 a fit or a calibration may reach: eq 11's lengthening asymptote (2 + c0/P0) Fc must stay
#: above Fc, so c0 > -P0 (KimForce refuses c0 <= -P0).
C0_OVER_P0_MIN = 0.999


def mashima_tension(v: ArrayLike, c0: float, d0: float, P0: float) -> ArrayLike:
    """Eq 11 at Fc = P0 solved for the tension (N) at lengthening velocity v (mm/s, > 0)."""
    return (d0 * P0 + (2.0 * P0 + c0) * v) / (d0 + v)


def contractile_force(force: np.ndarray, v_ce: np.ndarray, params: Mapping[str, float]) -> np.ndarray:
    """Fc (N) that makes the CE move at v_ce (mm/s) under force F (N): eqs 10/11 inverted (eq 10 for
    v_ce <= 0, eq 11 above).

    NaN where the velocity is at or beyond the Hill or Mashima asymptote (no finite Fc produces it).
    """
    p = params
    short = v_ce <= 0.0
    num = np.where(short, force * (p["b0"] - v_ce), force * (p["d0"] + v_ce))
    den = np.where(short, p["b0"] + p["a0"] * v_ce / p["P0"], p["d0"] + v_ce * (2.0 + p["c0"] / p["P0"]))
    ok = den > 0.0
    return np.where(ok, num / np.where(ok, den, 1.0), np.nan)
