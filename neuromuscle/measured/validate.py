"""The validator of measured data (docs/reference/data-format.md): every rule, all problems at once.

:func:`find_problems` checks the in-memory objects; the reader (after its file-level checks), the writer, CSV
import and the literature loaders all go through it. Every problem names the file (``source``), the trial and
the field. Times are in s.

Decisions where the spec leaves room (documented here once):

* A trial needs a length: either the ``length`` dataset or the ``length`` attribute (a constant). Both together
  are refused unless every sample of the dataset equals the attribute.
* ``stimulus_times`` must be present in every trial (it may be empty, for a passive trial).
* A trial needs at least 2 samples. Time, force, length, stimulus and spike arrays must be 1-D floating-point
  arrays (any float width is read; everything is returned and written as float64).
* Stimulus times must lie within the closed interval [time[0], time[-1]]. They are non-decreasing as the spec
  says (the order rule and its message are :func:`neuromuscle.validate.time_order_problem`, shared with
  :func:`neuromuscle.validate.check_spike_times`); unlike a simulation's input, two equal times are accepted.
* Extra attributes (root, trial) are kept in ``attrs``; extra datasets anywhere are kept in
  ``MeasuredData.extra_datasets`` and attributes of other groups/datasets in ``MeasuredData.extra_attrs``,
  both keyed by absolute HDF5 path, and written back by the writer.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np

from ..errors import InputError
from ..validate import time_order_problem
from .schema import (FORCE_UNITS, LENGTH_UNITS, ROOT_STRING_ATTRS, SCHEMA, TRIAL_DATASETS, TRIAL_RESERVED_ATTRS,
                     MeasuredData, Trial, to_h5_attr)

MAX_LISTED_PROBLEMS = 30


def find_problems(data: MeasuredData, source: str = "<memory>", *, allow_no_trials: bool = False) -> list[str]:
    """Every rule of measured_data.md that ``data`` breaks, as messages prefixed with ``source``.

    ``allow_no_trials`` leaves out the "no trials" problem (for a reader that has already reported why it
    skipped every trial)."""
    out = [f"{source}: {p}" for p in _root_problems(data.attrs)]
    if not data.trials and not allow_no_trials:
        out.append(f"{source}: group '/trials' holds no trials (at least one is required)")
    for key, trial in data.trials.items():
        where = f"{source}: trial '{key}'"
        if key != trial.trial_id:
            out.append(f"{where}: key differs from trial_id '{trial.trial_id}'")
        out.extend(f"{where}: {p}" for p in trial_problems(trial))
    for uid, spikes in data.motor_units.items():
        out.extend(f"{source}: motor unit '{uid}': {p}" for p in _spike_problems(uid, spikes))
    out.extend(f"{source}: {p}" for p in _extras_problems(data))
    return out


def validate_measured(data: MeasuredData, source: str = "<memory>") -> None:
    """Raise InputError listing every problem of ``data`` (see find_problems); return None if it is valid."""
    raise_problems(find_problems(data, source), source)


def raise_problems(problems: Sequence[str], source: str) -> None:
    """Raise one InputError carrying all problems (the message is the problem itself when there is one)."""
    if not problems:
        return
    if len(problems) == 1:
        raise InputError(problems[0])
    listed = "\n  - ".join(problems[:MAX_LISTED_PROBLEMS])
    more = len(problems) - MAX_LISTED_PROBLEMS
    tail = f"\n  ... and {more} more" if more > 0 else ""
    raise InputError(f"{source}: {len(problems)} problems:\n  - {listed}{tail}")


def _root_problems(attrs: Mapping[str, Any]) -> list[str]:
    """Root attributes: schema (if present) must match, the descriptive ones must be strings, all storable."""
    out = []
    if "schema" in attrs and attrs["schema"] != SCHEMA:
        out.append(f"root attribute 'schema' is {attrs['schema']!r}, expected {SCHEMA!r}")
    for name in ROOT_STRING_ATTRS:
        if name in attrs and not isinstance(attrs[name], str):
            out.append(f"root attribute '{name}' must be a string, got {type(attrs[name]).__name__}")
    out.extend(f"root {p}" for p in _storable_problems(attrs))
    return out


def trial_problems(trial: Trial) -> list[str]:
    """Every rule a single trial breaks (messages name the field, without the file/trial prefix)."""
    out = _name_problems(trial.trial_id, "trial id")
    if not isinstance(trial.protocol, str) or not trial.protocol.strip():
        out.append(f"attribute 'protocol' must be a non-empty string, got {trial.protocol!r}")
    out.extend(_unit_problems(trial.force_unit, "force_unit", FORCE_UNITS))
    out.extend(_unit_problems(trial.length_unit, "length_unit", LENGTH_UNITS))
    time_bad = _array_problems(trial.time_s, "time", "s")
    out.extend(time_bad)
    time = None if time_bad else np.asarray(trial.time_s)
    if time is not None:
        if time.size < 2:
            out.append(f"field 'time' has {time.size} samples; at least 2 are needed")
        out.extend(_order_problems(time, "time", strict=True))
    out.extend(_sampled_problems(trial.force, "force", time))
    if trial.length is not None:
        out.extend(_sampled_problems(trial.length, "length", time))
    out.extend(_length_const_problems(trial))
    out.extend(_stimulus_problems(trial.stimulus_times_s, time))
    reserved = sorted(set(trial.attrs) & set(TRIAL_RESERVED_ATTRS))
    if reserved:
        out.append(f"attrs holds reserved attribute(s) {reserved}; use the Trial fields instead")
    out.extend(_storable_problems(trial.attrs))
    return out


def _spike_problems(uid: Any, spikes: Any) -> list[str]:
    """A motor unit: HDF5-safe id; spike times (s) finite and non-decreasing (may be empty)."""
    out = _name_problems(uid, "unit id")
    arr = np.asarray(spikes) if spikes is not None else None
    if arr is not None and arr.ndim == 1 and arr.size == 0:
        return out
    bad = _array_problems(spikes, "spike_times", "s")
    return out + (bad or _order_problems(arr, "spike_times", strict=False))


def _name_problems(name: Any, what: str) -> list[str]:
    """An HDF5-safe group name: a non-empty string without '/' that is not '.'."""
    if not isinstance(name, str) or not name or "/" in name or name == ".":
        return [f"{what} {name!r} is not an HDF5-safe name (non-empty, no '/', not '.')"]
    return []


def _unit_problems(unit: Any, attr: str, allowed: Sequence[str]) -> list[str]:
    """A unit attribute must be one of the allowed strings."""
    if unit not in allowed:
        options = ", ".join(repr(u) for u in allowed)
        return [f"attribute '{attr}' is {unit!r}, expected one of {options}"]
    return []


def _array_problems(values: Any, name: str, unit: str) -> list[str]:
    """A 1-D floating-point array of finite values (unit only used in messages)."""
    if values is None:
        return [f"field '{name}' is missing"]
    arr = np.asarray(values)
    if arr.ndim != 1:
        return [f"field '{name}' must be a 1-D array{unit and f' ({unit})'}, got shape {arr.shape}"]
    if arr.dtype.kind != "f":
        return [f"field '{name}' must hold floating-point values{unit and f' ({unit})'}, got dtype {arr.dtype}"]
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        return [f"field '{name}' has {bad.size} non-finite samples (first at index {bad[0]})"]
    return []


def _order_problems(times: np.ndarray, name: str, strict: bool) -> list[str]:
    """Field ``name`` (s) strictly increasing (strict) or non-decreasing: the package's order rule."""
    problem = time_order_problem(times, f"field '{name}'", "s", strict=strict)
    return [] if problem is None else [problem]


def _sampled_problems(values: Any, name: str, time: np.ndarray | None) -> list[str]:
    """A finite float array sampled on the time axis: same size as time (when time itself is valid)."""
    out = _array_problems(values, name, "")
    if not out and time is not None and np.size(values) != time.size:
        out.append(f"field '{name}' has {np.size(values)} samples but field 'time' has {time.size}")
    return out


def _length_const_problems(trial: Trial) -> list[str]:
    """Exactly one length source: dataset or constant attribute (both only when they agree exactly)."""
    const = trial.length_const
    if const is not None:
        if isinstance(const, (bool, np.bool_)) or not isinstance(const, (int, float, np.integer, np.floating)):
            return [f"attribute 'length' must be a finite number, got {const!r}"]
        if not np.isfinite(const):
            return [f"attribute 'length' must be finite, got {const!r}"]
    if trial.length is None and const is None:
        return ["field 'length' is missing: give the 'length' dataset or a constant 'length' attribute"]
    if trial.length is not None and const is not None:
        if np.size(trial.length) == 0 or not np.all(np.asarray(trial.length) == const):
            return [f"field 'length' is given both as a dataset and as attribute 'length' = {const!r}, "
                    "and they differ: keep only one"]
    return []


def _stimulus_problems(values: Any, time: np.ndarray | None) -> list[str]:
    """Stimulus times (s): finite, non-decreasing, inside [time[0], time[-1]]; may be empty."""
    arr = np.asarray(values) if values is not None else None
    if arr is not None and arr.ndim == 1 and arr.size == 0:
        return []
    out = _array_problems(values, "stimulus_times", "s")
    if out:
        return out
    out = _order_problems(arr, "stimulus_times", strict=False)
    if time is not None and time.size:
        outside = np.flatnonzero((arr < time[0]) | (arr > time[-1]))
        if outside.size:
            i = int(outside[0])
            out.append(f"field 'stimulus_times' has {outside.size} times outside the trial's time range "
                       f"[{time[0]:g}, {time[-1]:g}] s (first: {arr[i]:g} s at index {i})")
    return out


def _storable_problems(attrs: Mapping[str, Any]) -> list[str]:
    """Attribute values HDF5 can store: strings, numbers, bools and numeric/string arrays."""
    out = []
    for key, value in attrs.items():
        if not isinstance(key, str) or not key:
            out.append(f"attribute name {key!r} is not a non-empty string")
        elif to_h5_attr(value) is None:
            out.append(f"attribute '{key}' has a type HDF5 cannot store ({type(value).__name__})")
    return out


def _extras_problems(data: MeasuredData) -> list[str]:
    """Extra datasets/attributes must not collide with, or invent, trials and motor units."""
    out = []
    for path in data.extra_datasets:
        out.extend(_extra_path_problems(data, path, is_dataset=True))
    for path, attrs in data.extra_attrs.items():
        out.extend(_extra_path_problems(data, path, is_dataset=False))
        out.extend(f"'{path}': {p}" for p in _storable_problems(attrs))
    return out


def _extra_path_problems(data: MeasuredData, path: str, is_dataset: bool) -> list[str]:
    """An extra node lives outside the core layout, or inside an existing trial/unit under a non-core name."""
    parts = [p for p in str(path).split("/") if p]
    if not str(path).startswith("/") or not parts:
        return [f"extra path {path!r} must be an absolute HDF5 path below '/'"]
    if parts[0] == "trials":
        return _container_extra_problems(path, parts, data.trials, TRIAL_DATASETS, is_dataset, "trial")
    if parts[0] == "motor_units":
        return _container_extra_problems(path, parts, data.motor_units, ("spike_times",), is_dataset, "unit")
    return []


def _container_extra_problems(path: str, parts: list[str], members: Mapping[str, Any], core: Sequence[str],
                              is_dataset: bool, what: str) -> list[str]:
    """Rules for extras below /trials or /motor_units."""
    if len(parts) == 1:
        return [f"extra dataset {path!r} collides with the core group"] if is_dataset else []
    if parts[1] not in members:
        return [f"extra path {path!r} names {what} '{parts[1]}', which does not exist"]
    if len(parts) == 2:
        return [f"extra dataset {path!r} collides with {what} '{parts[1]}'"] if is_dataset else []
    if parts[2] in core and is_dataset:
        return [f"extra dataset {path!r} collides with core field '{parts[2]}'"]
    return []

