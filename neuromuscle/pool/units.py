"""Muscle-unit parameters across a pool: P0 spread exponentially (Fuglevand, Winter & Patla 1993), twitch speed by
type (a time scaling of Modules 1-2 and of the force-velocity speeds).

    params_i = unit_muscle_parameters(base, p0_N=..., speed=TWITCH_SPEED["FF"])

Time scaling by a factor k: every rate constant of Modules 1-2 (1/ms, 1/(M ms), M/ms) times k, every time
constant (ms) divided by k, the Mashima velocity constants b0, d0 (mm/s) times k.  Modules 1-2 then run exactly k
times faster (the twitch's time to peak and half relaxation shrink by about 1/k); the force-length curve and the
calcium levels are unchanged.  The Hill force constants a0, c0 (N) follow P0 so the force-velocity curve
keeps its shape.  Units: N, ms.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..parameters import ParameterSet
from ..validate import positive_number

#: Twitch speed factors by type relative to the base set (CT09: a cat soleus S unit, time to peak ~81 ms at
#: -8 mm): FR and FF units of cat medial gastrocnemius twitch in roughly 45 and 35 ms (Burke et al. 1973).
TWITCH_SPEED = {"S": 1.0, "FR": 1.8, "FF": 2.3}

_RATES = ("K1", "K2", "K3", "K4", "K5i", "K6i", "Rmax", "Umax", "b0", "d0")
_TIMES = ("tau1", "tau2", "C3", "alpha2", "alpha3")
_FORCES = ("a0", "c0")


def p0_spread_N(n_units: int, smallest_N: float, range_ratio: float) -> np.ndarray:
    """P0 (N) of units 0..n-1 in recruitment order: smallest_N * range_ratio ** (i / (n - 1)) (Fuglevand et al.
    1993, eq 1, with the largest unit range_ratio times the smallest)."""
    if isinstance(n_units, bool) or not isinstance(n_units, (int, np.integer)) or n_units < 1:
        raise InputError(f"n_units must be an integer >= 1, got {n_units!r}")
    positive_number("smallest P0 (N)", smallest_N)
    if positive_number("P0 range ratio", range_ratio) < 1.0:
        raise InputError(f"P0 range ratio must be >= 1 (largest / smallest), got {range_ratio}")
    i = np.arange(n_units, dtype=float)
    return smallest_N * range_ratio ** (i / max(n_units - 1, 1))


def unit_muscle_parameters(base: ParameterSet, p0_N: float, speed: float = 1.0, name: str | None = None
                           ) -> ParameterSet:
    """``base`` with P0 = p0_N (N; a0, c0 scaled with it) and Modules 1-2 run ``speed`` times faster; values
    outside their physiological range raise InputError naming them."""
    positive_number("P0 (N)", p0_N)
    positive_number("twitch speed factor", speed)
    scale = p0_N / base["P0"]
    changes = {"P0": p0_N, **{k: base[k] * scale for k in _FORCES}}
    changes.update({k: base[k] * speed for k in _RATES})
    changes.update({k: base[k] / speed for k in _TIMES})
    p = base.with_values(changes)
    return ParameterSet(name or base.name, p.values, f"{base.source}; P0 {p0_N:.4g} N, speed x{speed:g}")
