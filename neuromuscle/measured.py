"""Measured muscle data: the HDF5 layout of shared/spec/measured_data.md, CSV import and real-data loaders.

Units throughout this module: time in **seconds** (never ms), force in N (or N*m for a joint moment), length in
mm (or rad for a joint angle), as the file's ``force_unit`` / ``length_unit`` attributes say.

One validator (:func:`find_problems`) checks the in-memory objects; :func:`read_measured` (after its file-level
checks), :func:`write_measured`, :func:`import_csv` and the real-data loaders all go through it. Every problem
is reported as an :class:`~neuromuscle.errors.InputError` naming the file, the trial and the field.

Decisions where the spec leaves room (documented here once):

* A trial needs a length: either the ``length`` dataset or the ``length`` attribute (a constant). Both together
  are refused unless every sample of the dataset equals the attribute.
* ``stimulus_times`` must be present in every trial (it may be empty, for a passive trial).
* A trial needs at least 2 samples. Time, force, length, stimulus and spike arrays must be 1-D floating-point
  arrays (any float width is read; everything is returned and written as float64).
* Stimulus times must lie within the closed interval [time[0], time[-1]].
* Extra attributes (root, trial) are kept in ``attrs``; extra datasets anywhere are kept in
  ``MeasuredData.extra_datasets`` and attributes of other groups/datasets in ``MeasuredData.extra_attrs``,
  both keyed by absolute HDF5 path, and written back by :func:`write_measured`.
"""

from __future__ import annotations

import csv
import os
import uuid
from dataclasses import dataclass, field, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any, Iterable, Mapping, Sequence

import h5py
import numpy as np

from .errors import InputError

SCHEMA = "neuromuscle.measured/1"
FORCE_UNITS = ("N", "N*m")
LENGTH_UNITS = ("mm", "rad")
ROOT_STRING_ATTRS = ("species", "muscle", "preparation", "source", "licence")
TRIAL_RESERVED_ATTRS = ("protocol", "force_unit", "length_unit", "length")
TRIAL_DATASETS = ("time", "force", "length", "stimulus_times")
MAX_LISTED_PROBLEMS = 30

PathLike = str | os.PathLike


# ----------------------------------------------------------------------------------------------- data objects


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


# ------------------------------------------------------------------------------------------------- validator


def find_problems(data: MeasuredData, source: str = "<memory>") -> list[str]:
    """Every rule of measured_data.md that ``data`` breaks, as messages prefixed with ``source``."""
    return _problems(data, source, allow_no_trials=False)


def validate_measured(data: MeasuredData, source: str = "<memory>") -> None:
    """Raise InputError listing every problem of ``data`` (see find_problems); return None if it is valid."""
    _raise_problems(find_problems(data, source), source)


def _problems(data: MeasuredData, source: str, allow_no_trials: bool) -> list[str]:
    """The validator proper: root attributes, trials, motor units and extras."""
    out = [f"{source}: {p}" for p in _root_problems(data.attrs)]
    if not data.trials and not allow_no_trials:
        out.append(f"{source}: group '/trials' holds no trials (at least one is required)")
    for key, trial in data.trials.items():
        where = f"{source}: trial '{key}'"
        if key != trial.trial_id:
            out.append(f"{where}: key differs from trial_id '{trial.trial_id}'")
        out.extend(f"{where}: {p}" for p in _trial_problems(trial))
    for uid, spikes in data.motor_units.items():
        out.extend(f"{source}: motor unit '{uid}': {p}" for p in _spike_problems(uid, spikes))
    out.extend(f"{source}: {p}" for p in _extras_problems(data))
    return out


def _raise_problems(problems: Sequence[str], source: str) -> None:
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


def _trial_problems(trial: Trial) -> list[str]:
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


def _order_problems(arr: np.ndarray, name: str, strict: bool) -> list[str]:
    """Strictly increasing (strict) or non-decreasing values; names the first offending index."""
    step = np.diff(arr)
    bad = np.flatnonzero(step <= 0 if strict else step < 0)
    if not bad.size:
        return []
    i = int(bad[0]) + 1
    kind = "strictly increasing" if strict else "non-decreasing"
    return [f"field '{name}' is not {kind}: {name}[{i}] = {arr[i]:g} after {name}[{i - 1}] = {arr[i - 1]:g} "
            f"({bad.size} such steps)"]


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
        elif _to_h5_attr(value) is None:
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


# -------------------------------------------------------------------------------------------------- reading


def read_measured(path: PathLike) -> MeasuredData:
    """Read and validate a measured-data HDF5 file (opened read-only; the file is never modified).

    Raises InputError naming the file (and trial and field) for a missing file, a file that is not HDF5, and
    every broken rule of measured_data.md (all problems in one message).
    """
    source = str(path)
    with _open_read_only(Path(path)) as h5:
        _check_schema(h5, source)
        if "trials" not in h5 or not isinstance(h5["trials"], h5py.Group):
            raise InputError(f"{source}: group '/trials' is missing")
        structural: list[str] = []
        trials = _read_trials(h5["trials"], source, structural)
        units = _read_units(h5, source, structural)
        root_attrs = {k: _attr_value(v) for k, v in h5.attrs.items() if k != "schema"}
        extra_datasets, extra_attrs = _read_extras(h5)
    data = MeasuredData(trials=trials, attrs=root_attrs, motor_units=units, path=Path(path),
                        extra_datasets=extra_datasets, extra_attrs=extra_attrs)
    problems = structural + _problems(data, source, allow_no_trials=bool(structural))
    _raise_problems(problems, source)
    return _as_float64(data)


def _open_read_only(path: Path) -> h5py.File:
    """Open an HDF5 file with mode 'r', turning OS/HDF5 failures into InputError naming the file."""
    if not path.exists():
        raise InputError(f"{path}: file not found")
    if not path.is_file():
        raise InputError(f"{path}: not a regular file")
    if not h5py.is_hdf5(path):
        raise InputError(f"{path}: not an HDF5 file")
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"{path}: cannot open as HDF5 ({exc})") from exc


def _check_schema(h5: h5py.File, source: str) -> None:
    """The root 'schema' attribute must be present and equal SCHEMA."""
    if "schema" not in h5.attrs:
        raise InputError(f"{source}: root attribute 'schema' is missing (expected {SCHEMA!r}); "
                         "not a neuromuscle measured-data file")
    schema = _attr_value(h5.attrs["schema"])
    if schema != SCHEMA:
        raise InputError(f"{source}: root attribute 'schema' is {schema!r}, expected {SCHEMA!r}")


def _read_trials(group: h5py.Group, source: str, problems: list[str]) -> dict[str, Trial]:
    """Trials in file order; trials with missing members are reported in problems and skipped."""
    trials = {}
    for name in group.keys():
        node = group[name]
        where = f"{source}: trial '{name}'"
        if not isinstance(node, h5py.Group):
            problems.append(f"{where}: '/trials/{name}' is a dataset, expected a trial group")
            continue
        missing = _missing_members(node, ("protocol", "force_unit", "length_unit"),
                                   ("time", "force", "stimulus_times"))
        if "length" in node and not isinstance(node["length"], h5py.Dataset):
            missing.append("field 'length' is a group, expected a dataset")
        if missing:
            problems.extend(f"{where}: {m}" for m in missing)
            continue
        trials[name] = _trial_from_group(name, node)
    return trials


def _missing_members(node: h5py.Group, attrs: Sequence[str], datasets: Sequence[str]) -> list[str]:
    """Messages for required attributes and datasets that are absent (or are groups)."""
    out = [f"attribute '{a}' is missing" for a in attrs if a not in node.attrs]
    for d in datasets:
        if d not in node:
            out.append(f"field '{d}' is missing")
        elif not isinstance(node[d], h5py.Dataset):
            out.append(f"field '{d}' is a group, expected a dataset")
    return out


def _trial_from_group(name: str, node: h5py.Group) -> Trial:
    """Build a Trial from a trial group whose required members exist (values are checked by the validator)."""
    attrs = {k: _attr_value(v) for k, v in node.attrs.items()}
    return Trial(
        trial_id=name,
        protocol=attrs.pop("protocol"),
        time_s=node["time"][()],
        force=node["force"][()],
        force_unit=attrs.pop("force_unit"),
        length_unit=attrs.pop("length_unit"),
        length=node["length"][()] if "length" in node else None,
        length_const=_scalar_attr(attrs.pop("length", None)),
        stimulus_times_s=node["stimulus_times"][()],
        attrs=attrs,
    )


def _read_units(h5: h5py.File, source: str, problems: list[str]) -> dict[str, np.ndarray]:
    """Motor-unit spike times (s) from /motor_units/<id>/spike_times, if the group exists."""
    if "motor_units" not in h5:
        return {}
    group = h5["motor_units"]
    if not isinstance(group, h5py.Group):
        problems.append(f"{source}: '/motor_units' is a dataset, expected a group")
        return {}
    units = {}
    for uid in group.keys():
        node = group[uid]
        if not isinstance(node, h5py.Group) or not isinstance(node.get("spike_times"), h5py.Dataset):
            problems.append(f"{source}: motor unit '{uid}': field 'spike_times' is missing")
            continue
        units[uid] = node["spike_times"][()]
    return units


def _is_core_path(path: str) -> bool:
    """True for the nodes of the layout itself (read into Trial / motor_units, not into extras)."""
    parts = path.strip("/").split("/")
    if parts[0] == "trials":
        return len(parts) <= 2 or (len(parts) == 3 and parts[2] in TRIAL_DATASETS)
    if parts[0] == "motor_units":
        return len(parts) <= 2 or (len(parts) == 3 and parts[2] == "spike_times")
    return False


def _read_extras(h5: h5py.File) -> tuple[dict[str, np.ndarray], dict[str, dict[str, Any]]]:
    """Datasets outside the core layout, and attributes of every node other than the root and trial groups."""
    datasets: dict[str, np.ndarray] = {}
    attrs: dict[str, dict[str, Any]] = {}

    def visit(name: str, node: h5py.HLObject) -> None:
        path = "/" + name
        core = _is_core_path(path)
        is_trial_group = path.count("/") == 2 and path.startswith("/trials/")
        if isinstance(node, h5py.Dataset) and not core:
            datasets[path] = node[()]
        if node.attrs and not is_trial_group:
            attrs[path] = {k: _attr_value(v) for k, v in node.attrs.items()}
        elif not core and isinstance(node, h5py.Group) and path not in attrs and not len(node):
            attrs[path] = {}  # keep empty extra groups

    h5.visititems(visit)
    return datasets, attrs


def _scalar_attr(value: Any) -> Any:
    """A one-element numeric array attribute as its scalar; anything else unchanged (checked later)."""
    if isinstance(value, np.ndarray) and value.size == 1 and value.dtype.kind in "iuf":
        return value.item()
    return value


def _attr_value(value: Any) -> Any:
    """An HDF5 attribute as a plain Python value: bytes decoded, numpy scalars unwrapped."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode("utf-8", errors="replace")
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray) and value.dtype.kind in "OS":
        return np.array([_attr_value(v) for v in value.ravel()], dtype=object).reshape(value.shape)
    return value


def _as_float64(data: MeasuredData) -> MeasuredData:
    """The same data with every time/force/length/stimulus/spike array as float64."""
    def f64(a: Any) -> Any:
        return None if a is None else np.asarray(a, dtype=np.float64)

    trials = {k: replace(t, time_s=f64(t.time_s), force=f64(t.force), length=f64(t.length),
                         length_const=None if t.length_const is None else float(t.length_const),
                         stimulus_times_s=f64(t.stimulus_times_s))
              for k, t in data.trials.items()}
    units = {k: f64(v) for k, v in data.motor_units.items()}
    return replace(data, trials=trials, motor_units=units)


# -------------------------------------------------------------------------------------------------- writing


def write_measured(path: PathLike, data: MeasuredData, overwrite: bool = False) -> Path:
    """Validate ``data`` and write it in the measured-data layout; return the path written.

    Refuses an existing file unless overwrite=True, and always refuses the file ``data`` was read from. The
    file is written to a temporary name beside ``path`` and moved into place, so a failure leaves no half file.
    """
    out = Path(path)
    validate_measured(data, source=str(out))
    if out.exists() and not overwrite:
        raise InputError(f"{out}: file exists; pass overwrite=True to replace it")
    if data.path is not None and out.exists() and _same_file(out, data.path):
        raise InputError(f"{out}: is the input file these data were read from; write to another path")
    if out.exists() and not out.is_file():
        raise InputError(f"{out}: exists and is not a regular file")
    if not out.parent.is_dir():
        raise InputError(f"{out}: directory '{out.parent}' does not exist")
    tmp_name = out.parent / f".{out.name}.{uuid.uuid4().hex}.tmp"
    try:
        with h5py.File(tmp_name, "x") as h5:
            _write_layout(h5, data)
        os.replace(tmp_name, out)
    finally:
        if os.path.exists(tmp_name):
            os.unlink(tmp_name)
    return out


def _same_file(a: Path, b: Path) -> bool:
    """True when both paths name the same existing file."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == Path(b).resolve()


def _write_layout(h5: h5py.File, data: MeasuredData) -> None:
    """Write root attributes, trials (in order), motor units and extras into an open, empty file."""
    h5.attrs["schema"] = SCHEMA
    _set_attrs(h5, {k: v for k, v in data.attrs.items() if k != "schema"})
    trials = h5.create_group("trials", track_order=True)
    for trial in data.trials.values():
        _write_trial(trials.create_group(trial.trial_id), trial)
    if data.motor_units:
        units = h5.create_group("motor_units", track_order=True)
        for uid, spikes in data.motor_units.items():
            units.create_group(uid).create_dataset("spike_times", data=np.asarray(spikes, dtype=np.float64))
    for path, values in data.extra_datasets.items():
        h5.create_dataset(path, data=values)
    for path, attrs in data.extra_attrs.items():
        node = h5[path] if path in h5 else h5.require_group(path)
        _set_attrs(node, attrs)


def _write_trial(group: h5py.Group, trial: Trial) -> None:
    """One trial group: attributes and float64 datasets."""
    group.attrs["protocol"] = trial.protocol
    group.attrs["force_unit"] = trial.force_unit
    group.attrs["length_unit"] = trial.length_unit
    if trial.length_const is not None:
        group.attrs["length"] = float(trial.length_const)
    _set_attrs(group, trial.attrs)
    group.create_dataset("time", data=np.asarray(trial.time_s, dtype=np.float64))
    group.create_dataset("force", data=np.asarray(trial.force, dtype=np.float64))
    if trial.length is not None:
        group.create_dataset("length", data=np.asarray(trial.length, dtype=np.float64))
    group.create_dataset("stimulus_times", data=np.asarray(trial.stimulus_times_s, dtype=np.float64))


def _set_attrs(node: h5py.HLObject, attrs: Mapping[str, Any]) -> None:
    """Store attributes, converting strings and string arrays to HDF5 variable-length strings."""
    for key, value in attrs.items():
        node.attrs[key] = _to_h5_attr(value)


def _to_h5_attr(value: Any) -> Any:
    """The HDF5-storable form of an attribute value, or None when it has none."""
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


# ------------------------------------------------------------------------------------------------ CSV import


@dataclass(frozen=True)
class _CsvTable:
    """Numeric columns of a CSV file with a header row (values as read, no unit conversion)."""

    path: Path
    columns: dict[str, np.ndarray]


def _read_csv_table(path: Path, wanted: Sequence[str], optional: Sequence[str] = ()) -> _CsvTable:
    """Read the named columns of a headed CSV; errors name the file, the line and the column."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    with open(path, newline="", encoding="utf-8-sig") as fh:
        rows = [(n, row) for n, row in enumerate(csv.reader(fh), start=1) if any(c.strip() for c in row)]
    if not rows:
        raise InputError(f"{path}: empty file (a header line is needed)")
    header = [c.strip() for c in rows[0][1]]
    missing = [c for c in wanted if c not in header]
    if missing:
        raise InputError(f"{path}: line {rows[0][0]}: column(s) {missing} not in the header {header}")
    names = list(wanted) + [c for c in optional if c in header]
    index = {c: header.index(c) for c in names}
    values = {c: np.empty(len(rows) - 1) for c in names}
    for k, (line, row) in enumerate(rows[1:]):
        if len(row) != len(header):
            raise InputError(f"{path}: line {line}: {len(row)} cells, the header has {len(header)}")
        for c in names:
            values[c][k] = _parse_cell(path, line, c, row[index[c]])
    return _CsvTable(path, values)


def _parse_cell(path: Path, line: int, column: str, cell: str) -> float:
    """A finite float from one CSV cell, or InputError naming file, line and column."""
    try:
        value = float(cell)
    except ValueError:
        raise InputError(f"{path}: line {line}, column '{column}': cannot read {cell.strip()!r} as a number") \
            from None
    if not np.isfinite(value):
        raise InputError(f"{path}: line {line}, column '{column}': value {cell.strip()!r} is not finite")
    return value


def _read_stimulus_list(path: Path, to_s: float) -> np.ndarray:
    """Stimulus times from a one-time-per-line file (blank lines and '#' comments skipped), converted to s."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    times = []
    with open(path, encoding="utf-8-sig") as fh:
        for line_no, line in enumerate(fh, start=1):
            text = line.split("#", 1)[0].strip().rstrip(",")
            if text:
                times.append(_parse_cell(path, line_no, "stimulus time", text))
    return np.asarray(times, dtype=np.float64) * to_s


_TIME_SCALE_S = MappingProxyType({"s": 1.0, "ms": 1e-3})


def import_csv(trial_csv_paths: Sequence[PathLike], stimulus_paths: Sequence[PathLike | None],
               out_path: PathLike, *, protocol: str | Sequence[str], force_unit: str, length_unit: str,
               time_unit: str = "s", time_column: str = "time", force_column: str = "force",
               length_column: str = "length", length_const: float | None = None,
               trial_ids: Sequence[str] | None = None, attrs: Mapping[str, Any] | None = None,
               overwrite: bool = False) -> MeasuredData:
    """Convert one CSV per trial (+ one stimulus list per trial) into a measured-data HDF5 file at out_path.

    Each CSV has a header naming ``time_column`` (in ``time_unit``, "s" or "ms"), ``force_column`` (force_unit)
    and, optionally, ``length_column`` (length_unit); without a length column the trial gets the constant
    ``length_const`` (length_unit). A stimulus file holds one time per line in ``time_unit`` ('#' starts a
    comment); a None entry means no stimuli. Trial ids default to the CSV file stems. ``protocol`` is one string
    for all trials or one per trial; ``attrs`` become root attributes. Returns the data as written.
    """
    if time_unit not in _TIME_SCALE_S:
        raise InputError(f"import_csv: time_unit {time_unit!r} must be 's' or 'ms'")
    csvs = [Path(p) for p in trial_csv_paths]
    stims = list(stimulus_paths)
    ids = list(trial_ids) if trial_ids is not None else [p.stem for p in csvs]
    protocols = [protocol] * len(csvs) if isinstance(protocol, str) else list(protocol)
    for name, seq in (("stimulus_paths", stims), ("trial_ids", ids), ("protocol", protocols)):
        if len(seq) != len(csvs):
            raise InputError(f"import_csv: {name} has {len(seq)} entries for {len(csvs)} CSV files")
    if len(set(ids)) != len(ids):
        raise InputError(f"import_csv: trial ids {ids} are not unique (pass trial_ids)")
    trials = {}
    for csv_path, stim, tid, prot in zip(csvs, stims, ids, protocols):
        trial = _trial_from_csv(csv_path, None if stim is None else Path(stim), tid, prot, force_unit,
                                length_unit, _TIME_SCALE_S[time_unit], (time_column, force_column, length_column),
                                length_const)
        _raise_problems([f"{csv_path}: trial '{tid}': {p}" for p in _trial_problems(trial)], str(csv_path))
        trials[tid] = trial
    data = MeasuredData(trials=trials, attrs=dict(attrs or {}))
    write_measured(out_path, data, overwrite=overwrite)
    return data


def _trial_from_csv(csv_path: Path, stim_path: Path | None, trial_id: str, protocol: str, force_unit: str,
                    length_unit: str, to_s: float, columns: tuple[str, str, str],
                    length_const: float | None) -> Trial:
    """One Trial from a CSV (time in time units * to_s = s) and an optional stimulus list."""
    time_col, force_col, length_col = columns
    table = _read_csv_table(csv_path, (time_col, force_col), optional=(length_col,))
    length = table.columns.get(length_col)
    if length is None and length_const is None:
        raise InputError(f"{csv_path}: no column '{length_col}' in the header and no length_const given")
    stimuli = np.zeros(0) if stim_path is None else _read_stimulus_list(stim_path, to_s)
    return Trial(trial_id=trial_id, protocol=protocol, time_s=table.columns[time_col] * to_s,
                 force=table.columns[force_col], force_unit=force_unit, length_unit=length_unit,
                 length=length, length_const=None if length is not None else length_const,
                 stimulus_times_s=stimuli, attrs={"imported_from": str(csv_path)})


# ------------------------------------------------------------------------------------------ summary / check


def summarize(data: MeasuredData) -> str:
    """Human-readable summary: a header line, then one line per trial (times in s, rates in Hz)."""
    a = data.attrs
    what = ", ".join(str(a[k]) for k in ("species", "muscle", "preparation") if k in a) or "no description"
    head = (f"{data.path if data.path is not None else '<memory>'}: {what}; {len(data.trials)} trial(s), "
            f"{len(data.motor_units)} motor unit(s)")
    return "\n".join([head] + [_trial_line(t) for t in data.trials.values()])


def _trial_line(t: Trial) -> str:
    """One summary line for a trial."""
    f = np.asarray(t.force)
    if t.length is not None:
        length = f"length {np.min(t.length):.4g}..{np.max(t.length):.4g} {t.length_unit}"
    else:
        length = f"length const {t.length_const:.4g} {t.length_unit}"
    return (f"  {t.trial_id}: {t.protocol}, {t.n_samples} samples, {t.duration_s:.4g} s, "
            f"{_sampling_text(np.asarray(t.time_s))}, force {f.min():.4g}..{f.max():.4g} {t.force_unit}, "
            f"{length}, {np.size(t.stimulus_times_s)} stimuli{_rate_text(np.asarray(t.stimulus_times_s))}")


def _sampling_text(time_s: np.ndarray) -> str:
    """'100 Hz' for uniform sampling, else the range of sampling intervals in ms."""
    dt = np.diff(time_s)
    if np.ptp(dt) <= 1e-6 * np.median(dt):
        return f"{1.0 / np.median(dt):.4g} Hz"
    return f"non-uniform dt {dt.min() * 1e3:.4g}-{dt.max() * 1e3:.4g} ms"


def _rate_text(stimuli_s: np.ndarray) -> str:
    """Mean stimulus rate (Hz) = (k - 1) / (last - first), when there are at least two distinct times."""
    if stimuli_s.size < 2 or stimuli_s[-1] <= stimuli_s[0]:
        return ""
    return f" (mean {(stimuli_s.size - 1) / (stimuli_s[-1] - stimuli_s[0]):.4g} Hz)"


def check_file(path: PathLike) -> str:
    """The summary of a valid measured-data file, or InputError listing all of its problems."""
    return summarize(read_measured(path))


# ------------------------------------------------------------------------------ real data: Herzog & Leonard


#: (figure label, file name, nominal stretch speed mm/s from the README or None when it gives none)
HERZOG_LEONARD_FILES = (
    ("Figure5", "dataHerzogLeonard2002Figure5.csv", None),
    ("Figure7A", "dataHerzogLeonard2002Figure7A.csv", 3.0),
    ("Figure7B", "dataHerzogLeonard2002Figure7B.csv", 9.0),
    ("Figure7C", "dataHerzogLeonard2002Figure7C.csv", 27.0),
)

#: Trial roles from the README table: trial number -> (protocol, start length mm, end length mm).
HERZOG_LEONARD_ROLES = MappingProxyType({
    **{n: ("isometric", 0.0, 0.0) for n in (31, 43, 51, 59)},
    **{n: ("isometric", 9.0, 9.0) for n in (32, 44, 52, 60)},
    **{n: ("stretch", 6.0, 9.0) for n in (45, 53, 61)},
    **{n: ("stretch", 3.0, 9.0) for n in (47, 55, 63)},
    **{n: ("stretch", 0.0, 9.0) for n in (37, 50, 57, 65)},
    **{n: ("passive", 0.0, 9.0) for n in (49, 58, 66)},
})

HERZOG_LEONARD_SOURCE = (
    "Herzog W, Leonard TR (2002) Force enhancement following stretching of skeletal muscle: a new mechanism. "
    "J Exp Biol 205:1275-1283. Traces from github.com/mjhmilla/DigitizedMusculotendonData commit "
    "3ef51196587a77e4059328f1db5320500de91ad8, data/cat/forceVelocity/dataHerzogLeonard2002Figure{5,7A,7B,7C}.dat")

HERZOG_LEONARD_LENGTH_REFERENCE = (
    "0 mm = the reference length of Herzog & Leonard 2002 (the length of the 0 mm isometric trials); NOT the "
    "model's reference (Xm relative to the physiological maximum): shift before simulating")

_PADDING_MIN_SAMPLES = 10
_ROLE_TOLERANCE_MM = 0.5


def load_herzog_leonard_2002(folder: PathLike) -> MeasuredData:
    """Cat soleus force (N) and length (mm, re the paper's 0 mm) traces of Herzog & Leonard 2002, one trial per
    F/L column pair (ids like 'Figure7A_F43'), time in s (100 Hz).

    Protocols: "isometric" (0 or 9 mm), "stretch" (active ramp to 9 mm) and "passive" (unstimulated ramp
    0 -> 9 mm). stimulus_times is EMPTY for every trial: the files carry no stimulus times (the paper used a
    supramaximal constant-rate nerve train, rate believed to be 30 Hz but not verified); attrs say so. Runs of
    >= 10 exact-zero force samples at the start/end of a trace (Figure5 F31/F32) are zero padding, not
    measurement: they are cut off and counted in attrs['trimmed_zero_padding_samples']. Millard's key points
    (digitizedKeyPointsHerzogLeonard2002.csv) are attached to the Figure7 trials they match.
    """
    root = Path(folder)
    trials: dict[str, Trial] = {}
    for figure, file_name, speed in HERZOG_LEONARD_FILES:
        for trial in _herzog_leonard_file(root / file_name, figure, speed):
            trials[trial.trial_id] = trial
    _attach_keypoints(root / "digitizedKeyPointsHerzogLeonard2002.csv", trials)
    data = MeasuredData(trials=trials, path=root, attrs={
        "species": "cat", "muscle": "soleus",
        "preparation": "in situ, soleus tendon attached to a servo motor, supramaximal nerve stimulation",
        "source": HERZOG_LEONARD_SOURCE, "licence": "MIT (copyright 2024 mjhmilla); cite the original paper",
        "length_reference": HERZOG_LEONARD_LENGTH_REFERENCE})
    validate_measured(data, source=str(root))
    return data


def _herzog_leonard_file(path: Path, figure: str, speed_mm_s: float | None) -> list[Trial]:
    """The trials of one Herzog-Leonard CSV ('Time (s)', then 'F<n> (N)', 'L<n> (mm)' pairs)."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    with open(path, encoding="utf-8-sig") as fh:
        header = [c.strip() for c in fh.readline().split(",")]
    numbers = [int(c[1:].split()[0]) for c in header if c.startswith("F") and c.endswith("(N)")]
    wanted = ["Time (s)"] + [c for n in numbers for c in (f"F{n} (N)", f"L{n} (mm)")]
    table = _read_csv_table(path, wanted)
    time_s = table.columns["Time (s)"]
    return [_herzog_leonard_trial(path, figure, n, time_s, table.columns[f"F{n} (N)"],
                                  table.columns[f"L{n} (mm)"], speed_mm_s) for n in numbers]


def _herzog_leonard_trial(path: Path, figure: str, number: int, time_s: np.ndarray, force_n: np.ndarray,
                          length_mm: np.ndarray, speed_mm_s: float | None) -> Trial:
    """One trial, with zero padding trimmed and its role (from the README table) checked against the data."""
    if number not in HERZOG_LEONARD_ROLES:
        raise InputError(f"{path}: column 'F{number} (N)': trial {number} is not in the README's role table")
    protocol, start_mm, end_mm = HERZOG_LEONARD_ROLES[number]
    lead, trail = _zero_padding(force_n)
    keep = slice(lead, force_n.size - trail)
    t, f, x = time_s[keep], force_n[keep], length_mm[keep]
    _check_role(path, number, x, start_mm, end_mm)
    attrs: dict[str, Any] = {
        "figure": figure, "source_file": path.name, "source_columns": [f"F{number} (N)", f"L{number} (mm)"],
        "start_length_mm": start_mm, "end_length_mm": end_mm,
        "trimmed_zero_padding_samples": np.array([lead, trail]),
        "length_reference": HERZOG_LEONARD_LENGTH_REFERENCE,
        "stimulus_times_known": False,
        "stimulation": ("none (passive stretch)" if protocol == "passive" else
                        "supramaximal nerve stimulation, constant-rate train (rate believed 30 Hz, unverified); "
                        "activation from ~1 s to ~10-12 s; times not in the source file, stimulus_times empty"),
    }
    if protocol != "isometric":
        attrs["ramp_speed_estimated_mm_s"] = _ramp_speed(t, x, start_mm, end_mm)
        if speed_mm_s is not None:
            attrs["stretch_speed_nominal_mm_s"] = speed_mm_s
    return Trial(trial_id=f"{figure}_F{number}", protocol=protocol, time_s=t, force=f, force_unit="N",
                 length_unit="mm", length=x, stimulus_times_s=np.zeros(0), attrs=attrs)


def _zero_padding(force: np.ndarray) -> tuple[int, int]:
    """Lengths of the leading and trailing runs of exact 0.0 (counted only when >= _PADDING_MIN_SAMPLES)."""
    nonzero = np.flatnonzero(force != 0.0)
    if not nonzero.size:
        return 0, 0
    lead, trail = int(nonzero[0]), int(force.size - 1 - nonzero[-1])
    return (lead if lead >= _PADDING_MIN_SAMPLES else 0), (trail if trail >= _PADDING_MIN_SAMPLES else 0)


def _check_role(path: Path, number: int, length_mm: np.ndarray, start_mm: float, end_mm: float) -> None:
    """The trace must start and end at the README's lengths (median of 20 samples, within 0.5 mm)."""
    first, last = np.median(length_mm[:20]), np.median(length_mm[-20:])
    if abs(first - start_mm) > _ROLE_TOLERANCE_MM or abs(last - end_mm) > _ROLE_TOLERANCE_MM:
        raise InputError(f"{path}: column 'L{number} (mm)': runs {first:.2f} -> {last:.2f} mm, but the README "
                         f"gives {start_mm:g} -> {end_mm:g} mm for trial {number}")


def _ramp_speed(t_s: np.ndarray, x_mm: np.ndarray, start_mm: float, end_mm: float) -> float:
    """Ramp speed (mm/s) between the first crossings of 10 % and 90 % of the start->end excursion."""
    lo = start_mm + 0.1 * (end_mm - start_mm)
    hi = start_mm + 0.9 * (end_mm - start_mm)
    i_lo, i_hi = int(np.argmax(x_mm > lo)), int(np.argmax(x_mm > hi))
    return float((hi - lo) / (t_s[i_hi] - t_s[i_lo])) if t_s[i_hi] > t_s[i_lo] else float("nan")


_KEYPOINT_FIGURE = MappingProxyType({3.0: "Figure7A", 9.0: "Figure7B", 27.0: "Figure7C"})
_KEYPOINT_MAX_ERROR_N = 0.5


def _attach_keypoints(path: Path, trials: dict[str, Trial]) -> None:
    """Attach each key-point row (velocity mm/s, lengthA, lengthB, t0,f0..t5,f5) to the Figure7 trial of the
    same figure and start/end lengths whose force at the key times matches best (within 0.5 N); rows that
    match no trial are skipped. Adds attrs keypoints_time_s, keypoints_force_N, keypoints_max_error_N."""
    if not path.is_file():
        return
    with open(path, newline="", encoding="utf-8-sig") as fh:
        rows = list(enumerate(csv.reader(fh), start=1))
    for line, row in rows[1:]:
        if not any(c.strip() for c in row):
            continue
        cells = [_parse_cell(path, line, f"column {i + 1}", c) if c.strip() else np.nan for i, c in enumerate(row)]
        speed, start, end = cells[0], cells[1], cells[2]
        pairs = np.array(cells[3:15], dtype=float).reshape(6, 2)
        pairs = pairs[np.isfinite(pairs).all(axis=1)]
        best = _best_keypoint_trial(trials, _KEYPOINT_FIGURE.get(speed), start, end, pairs)
        if best is not None:
            trial, err = best
            trial.attrs.update(keypoints_time_s=pairs[:, 0], keypoints_force_N=pairs[:, 1],
                               keypoints_max_error_N=err, keypoints_source=f"{path.name} line {line}")


def _best_keypoint_trial(trials: Mapping[str, Trial], figure: str | None, start: float, end: float,
                         pairs: np.ndarray) -> tuple[Trial, float] | None:
    """The trial of ``figure`` with matching start/end lengths whose force best matches the key points."""
    best = None
    for trial in trials.values():
        a = trial.attrs
        if a.get("figure") != figure or (a.get("start_length_mm"), a.get("end_length_mm")) != (start, end):
            continue
        t = np.clip(pairs[:, 0], trial.time_s[0], trial.time_s[-1])
        err = float(np.max(np.abs(np.interp(t, trial.time_s, trial.force) - pairs[:, 1])))
        if err <= _KEYPOINT_MAX_ERROR_N and (best is None or err < best[1]):
            best = (trial, err)
    return best


# --------------------------------------------------------------------------- real data: Scott, Brown & Loeb


@dataclass(frozen=True, eq=False)
class ForceLengthVelocityPoints:
    """Digitized cat soleus points of Scott, Brown & Loeb (1996) J Muscle Res Cell Motil 17:207.

    Lengths in L0 (optimal fascicle length), velocities in L0/s (negative = shortening), forces in F0 (maximal
    isometric tetanic force). Fig 3A: tetanic active force-length (``active_*``) and passive force-length
    (``passive_*``) per specimen ('S8'..'S12' in ``*_specimen``); Fig 4: force-velocity (``velocity_*``).
    Points are in digitizing order (not sorted); digitizing error ~1-2 % of the axis range.
    """

    active_length_L0: np.ndarray
    active_force_F0: np.ndarray
    active_specimen: np.ndarray
    passive_length_L0: np.ndarray
    passive_force_F0: np.ndarray
    passive_specimen: np.ndarray
    velocity_L0_per_s: np.ndarray
    velocity_force_F0: np.ndarray
    source: str


SCOTT_BROWN_LOEB_FILES = ("fig_ScottBrownLoeb1996_fig3.csv", "fig_ScottBrownLoeb1996_fig4.csv")


def load_scott_brown_loeb_1996(folder: PathLike) -> ForceLengthVelocityPoints:
    """Read fig_ScottBrownLoeb1996_fig3.csv (series fl08..fl12 active, fp08..fp12 passive F-L) and
    fig_ScottBrownLoeb1996_fig4.csv (series fv) from ``folder`` (cat_digitized_literature)."""
    root = Path(folder)
    fig3 = _read_blocks(root / SCOTT_BROWN_LOEB_FILES[0])
    fig4 = _read_blocks(root / SCOTT_BROWN_LOEB_FILES[1])
    active = _stack_series(fig3, "fl", root / SCOTT_BROWN_LOEB_FILES[0])
    passive = _stack_series(fig3, "fp", root / SCOTT_BROWN_LOEB_FILES[0])
    if "fv" not in fig4:
        raise InputError(f"{root / SCOTT_BROWN_LOEB_FILES[1]}: no series 'fv'")
    fv = fig4["fv"]
    return ForceLengthVelocityPoints(
        active_length_L0=active[0], active_force_F0=active[1], active_specimen=active[2],
        passive_length_L0=passive[0], passive_force_F0=passive[1], passive_specimen=passive[2],
        velocity_L0_per_s=fv[:, 0].copy(), velocity_force_F0=fv[:, 1].copy(),
        source="Scott SH, Brown IE, Loeb GE (1996) J Muscle Res Cell Motil 17:207, Figs 3A and 4, digitized by "
               "M. Millard (github.com/mjhmilla/DigitizedMusculotendonData 3ef51196), MIT licence")


def _read_blocks(path: Path) -> dict[str, np.ndarray]:
    """Blocks 'x,<series>' followed by 'x,y' rows -> {series: (n, 2) array}; errors name file and line."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    blocks: dict[str, list[tuple[float, float]]] = {}
    name = None
    with open(path, encoding="utf-8-sig") as fh:
        for line_no, line in enumerate(fh, start=1):
            cells = [c.strip() for c in line.strip().split(",")]
            if not cells[0]:
                continue
            if len(cells) < 2:
                raise InputError(f"{path}: line {line_no}: expected two comma-separated values")
            if cells[0] == "x":
                name = cells[1]
                blocks[name] = []
                continue
            if name is None:
                raise InputError(f"{path}: line {line_no}: data before the first 'x,<series>' header")
            blocks[name].append((_parse_cell(path, line_no, "x", cells[0]), _parse_cell(path, line_no, "y", cells[1])))
    return {k: np.asarray(v, dtype=np.float64).reshape(-1, 2) for k, v in blocks.items()}


def _stack_series(blocks: Mapping[str, np.ndarray], prefix: str, path: Path) -> tuple[np.ndarray, np.ndarray,
                                                                                       np.ndarray]:
    """Concatenate series '<prefix>NN' into (x, y, specimen label 'SNN') arrays."""
    names = [k for k in blocks if k.startswith(prefix) and k[len(prefix):].isdigit()]
    if not names:
        raise InputError(f"{path}: no series named '{prefix}NN'")
    x = np.concatenate([blocks[k][:, 0] for k in names])
    y = np.concatenate([blocks[k][:, 1] for k in names])
    labels = np.concatenate([[f"S{int(k[len(prefix):])}"] * len(blocks[k]) for k in names]).astype(str)
    return x, y, labels
