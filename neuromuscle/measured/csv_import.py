"""CSV import into the measured-data layout: one CSV a trial (time, force, length columns) plus a stimulus list.

Also the CSV reading helpers the literature loaders use (:func:`read_csv_table`, :func:`parse_cell`); every
error names the file, the line and the column.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping, Sequence

import numpy as np

from ..errors import InputError
from .hdf5 import write_measured
from .schema import MeasuredData, PathLike, Trial
from .validate import raise_problems, trial_problems


@dataclass(frozen=True)
class CsvTable:
    """Numeric columns of a CSV file with a header row (values as read, no unit conversion)."""

    path: Path
    columns: dict[str, np.ndarray]


def read_csv_table(path: Path, wanted: Sequence[str], optional: Sequence[str] = ()) -> CsvTable:
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
            values[c][k] = parse_cell(path, line, c, row[index[c]])
    return CsvTable(path, values)


def parse_cell(path: Path, line: int, column: str, cell: str) -> float:
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
                times.append(parse_cell(path, line_no, "stimulus time", text))
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
        raise_problems([f"{csv_path}: trial '{tid}': {p}" for p in trial_problems(trial)], str(csv_path))
        trials[tid] = trial
    data = MeasuredData(trials=trials, attrs=dict(attrs or {}))
    write_measured(out_path, data, overwrite=overwrite)
    return data


def _trial_from_csv(csv_path: Path, stim_path: Path | None, trial_id: str, protocol: str, force_unit: str,
                    length_unit: str, to_s: float, columns: tuple[str, str, str],
                    length_const: float | None) -> Trial:
    """One Trial from a CSV (time in time units * to_s = s) and an optional stimulus list."""
    time_col, force_col, length_col = columns
    table = read_csv_table(csv_path, (time_col, force_col), optional=(length_col,))
    length = table.columns.get(length_col)
    if length is None and length_const is None:
        raise InputError(f"{csv_path}: no column '{length_col}' in the header and no length_const given")
    stimuli = np.zeros(0) if stim_path is None else _read_stimulus_list(stim_path, to_s)
    return Trial(trial_id=trial_id, protocol=protocol, time_s=table.columns[time_col] * to_s,
                 force=table.columns[force_col], force_unit=force_unit, length_unit=length_unit,
                 length=length, length_const=None if length is not None else length_const,
                 stimulus_times_s=stimuli, attrs={"imported_from": str(csv_path)})
