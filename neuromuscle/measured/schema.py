"""The measured-data layout of docs/reference/data-format.md: names, units and the in-memory objects.

Units: time in **seconds** (never ms), force in N (or N*m for a joint moment), length in mm (or rad for a joint
angle), as a trial's ``force_unit`` / ``length_unit`` say.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

import h5py
import numpy as np

from ..errors import InputError

SCHEMA = "neuromuscle.measured/1"
FORCE_UNITS = ("N", "N*m")
LENGTH_UNITS = ("mm", "rad")
ROOT_STRING_ATTRS = ("species", "muscle", "preparation", "source", "licence")
TRIAL_RESERVED_ATTRS = ("protocol", "force_unit", "length_unit", "length")
TRIAL_DATASETS = ("time", "force", "length", "stimulus_times")

PathLike = str | os.PathLike


@dataclass(kw_only=True, eq=False)
class Trial:
    """One trial: force (force_unit) and length (length_unit) sampled at time_s (s), plus stimulus times (s).

    ``length`` is the sampled length (same size as time_s) or None; ``length_const`` a constant length for an
    isometric trial, or None. ``attrs`` holds the trial group's extra HDF5 attributes.
    """

    trial_id: str
    protocol: str
    time_s: np.ndarray
    force: np.ndarray
    force_unit: str
    length_unit: str
    length: np.ndarray | None = None
    length_const: float | None = None
    stimulus_times_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def n_samples(self) -> int:
        """Number of samples."""
        return int(np.size(self.time_s))

    @property
    def duration_s(self) -> float:
        """time_s[-1] - time_s[0] (s)."""
        return float(self.time_s[-1] - self.time_s[0])

    def length_at(self, t_s: Iterable[float] | np.ndarray | None = None) -> np.ndarray:
        """Length (length_unit) at times t_s (s); at the trial's own samples when t_s is None.

        The sampled length is linearly interpolated; a constant length is broadcast. Times outside
        [time_s[0], time_s[-1]] raise InputError.
        """
        t = np.asarray(self.time_s if t_s is None else t_s, dtype=np.float64)
        if t.size and (np.min(t) < self.time_s[0] or np.max(t) > self.time_s[-1]):
            raise InputError(f"trial '{self.trial_id}': length_at asked for times outside "
                             f"[{self.time_s[0]:g}, {self.time_s[-1]:g}] s")
        if self.length is not None:
            return np.interp(t, self.time_s, self.length)
        if self.length_const is None:
            raise InputError(f"trial '{self.trial_id}': field 'length' has neither a dataset nor a constant")
        return np.full(t.shape, float(self.length_const))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Trial):
            return NotImplemented
        return all(_values_equal(getattr(self, name), getattr(other, name)) for name in _TRIAL_FIELDS)


_TRIAL_FIELDS = ("trial_id", "protocol", "time_s", "force", "force_unit", "length_unit", "length",
                 "length_const", "stimulus_times_s", "attrs")


@dataclass(kw_only=True, eq=False)
class MeasuredData:
    """One preparation: trials (in file order), root attributes and optional motor-unit spike times (s).

    ``attrs`` holds the root attributes except ``schema`` (species, muscle, preparation, source, licence and any
    extra). ``path`` is the file (or folder) the data were read from, None for data built in memory.
    """

    trials: dict[str, Trial]
    attrs: dict[str, Any] = field(default_factory=dict)
    motor_units: dict[str, np.ndarray] = field(default_factory=dict)
    path: Path | None = None
    extra_datasets: dict[str, np.ndarray] = field(default_factory=dict)
    extra_attrs: dict[str, dict[str, Any]] = field(default_factory=dict)

    def __eq__(self, other: object) -> bool:
        """Equal content (the ``path`` is not compared)."""
        if not isinstance(other, MeasuredData):
            return NotImplemented
        names = ("trials", "attrs", "motor_units", "extra_datasets", "extra_attrs")
        return all(_values_equal(getattr(self, n), getattr(other, n)) for n in names)


def _values_equal(a: Any, b: Any) -> bool:
    """Deep equality that understands numpy arrays, dicts (order-insensitive) and NaN-free scalars."""
    if isinstance(a, dict) or isinstance(b, dict):
        return (isinstance(a, dict) and isinstance(b, dict) and a.keys() == b.keys()
                and all(_values_equal(a[k], b[k]) for k in a))
    if isinstance(a, (np.ndarray, list, tuple)) or isinstance(b, (np.ndarray, list, tuple)):
        try:
            return bool(np.array_equal(np.asarray(a), np.asarray(b)))
        except (TypeError, ValueError):
            return False
    return bool(a == b)


def to_h5_attr(value: Any) -> Any:
    """The HDF5-storable form of an attribute value (strings, numbers, bools, numeric/string arrays), or None
    when it has none."""
    if isinstance(value, (str, bool, int, float, np.number, np.bool_)):
        return value
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, (list, tuple, np.ndarray)):
        arr = np.asarray(value)
        if arr.dtype.kind in "biuf":
            return arr
        if arr.dtype.kind in "UO" and all(isinstance(v, str) for v in arr.ravel()):
            return np.array(arr.ravel().tolist(), dtype=h5py.string_dtype()).reshape(arr.shape)
    return None
