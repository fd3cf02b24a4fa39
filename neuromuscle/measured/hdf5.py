"""Reading and writing measured-data HDF5 files (layout: docs/reference/data-format.md; times in s).

A file is opened read-only and never modified; writing goes to a temporary name beside the target and is moved
into place, refusing an existing file unless asked and always refusing the file the data were read from.
"""

from __future__ import annotations

import os
import uuid
from dataclasses import replace
from pathlib import Path
from typing import Any, Mapping, Sequence

import h5py
import numpy as np

from ..errors import InputError
from ..reports.outdir import refuse_existing_file
from .schema import SCHEMA, TRIAL_DATASETS, MeasuredData, PathLike, Trial, to_h5_attr
from .validate import find_problems, raise_problems, validate_measured


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
    problems = structural + find_problems(data, source, allow_no_trials=bool(structural))
    raise_problems(problems, source)
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


def write_measured(path: PathLike, data: MeasuredData, overwrite: bool = False) -> Path:
    """Validate ``data`` and write it in the measured-data layout; return the path written.

    Refuses an existing file unless overwrite=True, and always refuses the file ``data`` was read from. The
    file is written to a temporary name beside ``path`` and moved into place, so a failure leaves no half file.
    """
    out = Path(path)
    validate_measured(data, source=str(out))
    if data.path is not None and out.exists() and _same_file(out, data.path):
        raise InputError(f"{out}: is the input file these data were read from; write to another path")
    refuse_existing_file(out, overwrite)
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
        node.attrs[key] = to_h5_attr(value)
