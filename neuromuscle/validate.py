"""Argument checks shared by the modules: each failure is an InputError naming the argument.

Spike and stimulus times follow one rule everywhere (:func:`check_spike_times`): 1-D, finite, >= 0 and strictly
increasing. Unsorted times are refused, never sorted silently; two equal times are refused too.
"""

from __future__ import annotations

import math
from numbers import Integral

import numpy as np
from numpy.typing import ArrayLike

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


def finite_series(name: str, values: object) -> np.ndarray:
    """``values`` as a finite 1-D float array; InputError naming ``name`` otherwise."""
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a 1-D array of numbers") from None
    if arr.ndim != 1:
        raise InputError(f"{name} must be 1-D, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} is not finite at sample {int(np.flatnonzero(~np.isfinite(arr))[0])}")
    return arr


def time_order_problem(times: np.ndarray, where: str, unit: str, *, strict: bool = True) -> str | None:
    """The first step of the finite 1-D array ``times`` (``unit``) that breaks strictly increasing order
    (``strict``) or non-decreasing order, as a message naming ``where``, the index and the value; None if none."""
    step = np.diff(times)
    bad = np.flatnonzero(step <= 0.0 if strict else step < 0.0)
    if not bad.size:
        return None
    i = int(bad[0]) + 1
    if step[i - 1] == 0.0:
        found = f"index {i} repeats {times[i]:g} {unit} of index {i - 1} (two equal times)"
    else:
        found = (f"index {i} holds {times[i]:g} {unit} after {times[i - 1]:g} {unit} "
                 "(not sorted: unsorted times are refused, never sorted silently)")
    more = f"; {bad.size} such steps in all" if bad.size > 1 else ""
    return f"{where} must be {'strictly increasing' if strict else 'non-decreasing'}: {found}{more}"


def check_spike_times(times: ArrayLike, where: str = "spike times", unit: str = "ms") -> np.ndarray:
    """Spike or stimulus times (``unit``) as a new float64 array: 1-D, finite, >= 0 and strictly increasing.

    Anything else raises InputError naming ``where``, the index and the value: unsorted input is refused (never
    sorted silently), and so are two equal times.
    """
    try:
        s = np.array(times if isinstance(times, np.ndarray) else list(times), dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{where} must be a sequence of numbers ({unit}), got {times!r}") from None
    if s.ndim != 1:
        raise InputError(f"{where} must be a 1-D sequence of times in {unit}, got shape {s.shape}")
    bad = np.flatnonzero(~np.isfinite(s))
    if bad.size:
        raise InputError(f"{where} contains non-finite values: index {bad[0]} holds {s[bad[0]]}")
    negative = np.flatnonzero(s < 0.0)
    if negative.size:
        i = negative[0]
        raise InputError(f"{where} must lie in [0, inf) {unit}: index {i} holds {s[i]:g} {unit} (negative time)")
    problem = time_order_problem(s, where, unit)
    if problem is not None:
        raise InputError(problem)
    return s


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
