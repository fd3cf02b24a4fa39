"""Argument checks shared by the modules: each failure is an InputError naming the argument."""

from __future__ import annotations

import math
from numbers import Integral

import numpy as np

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


def nonnegative_number(name: str, value: object) -> float:
    """``value`` as a float >= 0; InputError naming ``name`` otherwise."""
    x = finite_number(name, value)
    if x < 0.0:
        raise InputError(f"{name} must be >= 0, got {x}")
    return x


def seed_value(value: object) -> int:
    """A random seed: a non-negative integer (numpy integers accepted); InputError otherwise."""
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 0:
        raise InputError(f"seed must be a non-negative integer, got {value!r}")
    return int(value)


def check_spike_times(times: object, where: str = "spike times", unit: str = "ms") -> np.ndarray:
    """Spike or stimulus times as float64: 1-D, finite, >= 0 and strictly increasing (the one rule of the
    package: unsorted or repeated times are refused, never sorted or merged silently).  InputError names
    ``where``, the index and the value."""
    try:
        s = np.asarray(times if isinstance(times, np.ndarray) else list(times), dtype=float)  # type: ignore
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected a sequence of numbers ({unit}), got {times!r}") from None
    if s.ndim != 1:
        raise InputError(f"{where}: expected a 1-D sequence of times in {unit}, got shape {s.shape}")
    if not np.all(np.isfinite(s)):
        i = int(np.flatnonzero(~np.isfinite(s))[0])
        raise InputError(f"{where}: non-finite value {s[i]} at index {i}")
    if np.any(s < 0):
        i = int(np.flatnonzero(s < 0)[0])
        raise InputError(f"{where}: negative time {s[i]} {unit} at index {i}")
    d = np.diff(s)
    if np.any(d < 0):
        i = int(np.flatnonzero(d < 0)[0]) + 1
        raise InputError(f"{where}: not sorted: {s[i]} {unit} at index {i} comes after {s[i - 1]} {unit}; "
                         "sort the times")
    if np.any(d == 0):
        i = int(np.flatnonzero(d == 0)[0]) + 1
        raise InputError(f"{where}: two spikes at the same time {s[i]} {unit} (index {i - 1} and {i}); give "
                         "each spike once (a NetCon weight of 2 delivers a double spike)")
    return s
