"""The search space of a fit: each free parameter p is searched as a dimensionless z with z = 0 at its start.

A free parameter whose admissible range (``SPECS``) is non-negative, with a positive start and lower bound, is
searched as z = ln(p / p_start); any other as z = (p - p_start) / scale with
scale = max(|p_start|, (upper - lower) / 10).  Equal steps in z are then equal relative changes: finite
differences and trust regions behave the same for C3 (ms, ~60) and C1 (~0.1).

Default bounds (:func:`default_bounds`): [p/10, 10 p] for parameters that cannot be negative, p +/- max(|p|, 1)
for the others, clipped to the admissible range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..parameters import SPECS


@dataclass(frozen=True)
class Transform:
    """z <-> p for one free parameter: ``ref`` is p at z = 0 (parameter units); ``log`` chooses
    z = ln(p / ref), otherwise z = (p - ref) / ``scale`` (scale in parameter units).  ``lower`` and ``upper`` are
    the bounds searched (parameter units): p never leaves them (ref exp(ln(upper / ref)) can round past upper, and
    a parameter set refuses a value outside its range)."""

    name: str
    ref: float
    log: bool
    scale: float
    lower: float = -math.inf
    upper: float = math.inf

    @classmethod
    def for_parameter(cls, name: str, start: float, lower: float, upper: float) -> Transform:
        """The transform of parameter ``name`` started at ``start`` within [lower, upper] (parameter units)."""
        log = SPECS[name].lower >= 0 and lower > 0 and start > 0
        return cls(name, start, log, 1.0 if log else max(abs(start), (upper - lower) / 10.0), lower, upper)

    def to_z(self, p: float) -> float:
        return math.log(p / self.ref) if self.log else (p - self.ref) / self.scale

    def to_p(self, z: float) -> float:
        p = self.ref * math.exp(z) if self.log else self.ref + z * self.scale
        return min(max(p, self.lower), self.upper)

    def dp_dz(self, p: float) -> float:
        """dp/dz at p (parameter units per unit of z)."""
        return p if self.log else self.scale


def default_bounds(name: str, p: float) -> tuple[float, float]:
    """Default (lower, upper) bounds (parameter units) of parameter ``name`` started at p: a decade either side
    (or +-max(|p|, 1) for a parameter that may be negative), never beyond the parameter's physiological range
    (``neuromuscle.parameters.SPECS``, the bounds every parameter file is checked against)."""
    spec = SPECS[name]
    if spec.lower >= 0 and p > 0:
        lo, hi = p / 10.0, p * 10.0
    else:
        half = max(abs(p), 1.0)
        lo, hi = p - half, p + half
    lo = max(lo, spec.lower) if spec.lower_inclusive or spec.lower <= 0 else max(lo, spec.lower * (1 + 1e-12))
    return lo, min(hi, spec.upper)
