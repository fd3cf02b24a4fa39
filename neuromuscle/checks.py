"""Argument checks shared by the modules: each failure is an InputError naming the argument."""

from __future__ import annotations

import math

from .errors import InputError


def finite_number(name: str, value: object) -> float:
    """``value`` as a float; InputError naming ``name`` unless it is a finite real number."""
    if isinstance(value, bool):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(x):
        raise InputError(f"{name} must be a finite number, got {x}")
    return x


def positive_number(name: str, value: object) -> float:
    """``value`` as a float > 0; InputError naming ``name`` otherwise."""
    x = finite_number(name, value)
    if x <= 0.0:
        raise InputError(f"{name} must be > 0, got {x}")
    return x
