"""Herzog & Leonard (2002), cat soleus force enhancement after stretch: the digitized traces as measured data.

Units: time s, force N, length mm relative to the paper's 0 mm (NOT the model's reference: shift before
simulating). Source files: github.com/mjhmilla/DigitizedMusculotendonData (``cat_soleus_herzog_leonard_2002``).
"""

from __future__ import annotations

import csv
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from ..errors import InputError
from ..measured import MeasuredData, Trial, validate_measured
from ..measured.csv_import import parse_cell, read_csv_table
from ..measured.schema import PathLike


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
    table = read_csv_table(path, wanted)
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
        cells = [parse_cell(path, line, f"column {i + 1}", c) if c.strip() else np.nan for i, c in enumerate(row)]
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
