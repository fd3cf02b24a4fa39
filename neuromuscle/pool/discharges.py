"""Recorded motor-unit discharges and force: decomposed HD-EMG files of Caillet et al. (2022, 2023) as pool input.

    rec = load_caillet("S1_30_256.mat")               # level (% MVC) read from the name; level_percent_mvc= else
    trial = rec.trial(pad_ms=1000.0)                  # the window the discharges cover, times from its start
    whole = rec.trial(from_rest=True)                 # ... and the whole contraction, from rest to rest
    pool.drive_discharges(trial.discharges_ms, trial.duration_ms)   # recruitment order = the pool's unit order

File layout (MATLAB .mat, ``scipy.io.loadmat``): ``MUPulses`` a 1 x n cell of discharge sample indices (one row a
unit, at ``fsamp`` Hz, counted from 1 as MATLAB does: sample k is at (k - 1) / fsamp s), ``fsamp`` the sampling rate
(Hz), ``ref_signal`` the force transducer at ``fsamp`` (arbitrary units).  The force is normalised to % MVC: its
baseline (the muscle at rest: the median of the samples before the first discharge that lie within
:data:`REST_BAND_FRACTION` of the force's span above the lowest of them, their 1st percentile, so that a
decomposition whose first unit is recruited late in the ramp does not lift it) is 0 and its plateau (median of the
samples above 80 % of the baseline-to-99th-percentile span) is the trial's target level.  Units are put in
recruitment order: by the normalised force at their first discharge (ties by the time of that discharge).  Times in
ms.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..validate import finite_number, positive_number, time_order_problem

#: Fraction of the baseline-to-99th-percentile span above which force samples count as the plateau.
PLATEAU_FRACTION = 0.8
#: Width of the resting band, as a fraction of the span from the lowest force before the first discharge (its 1st
#: percentile) to the 99th percentile: the baseline is the median of the samples before the first discharge within it.
REST_BAND_FRACTION = 0.05
#: Force (% MVC) at or below which the muscle counts as at rest (:meth:`RecordedDischarges.rest_times_ms`).
REST_PERCENT_MVC = 1.0
#: Time (ms) a window taken from rest keeps before the force leaves rest and after it returns.
REST_MARGIN_MS = 500.0


@dataclass(frozen=True)
class DischargeTrial:
    """Discharges (ms, from the trial's start; recruitment order) and the recorded force (% MVC) of one trial
    window; ``start_ms`` is where the window starts in the file, ``units`` the file's unit index of each train."""

    source: str
    start_ms: float
    duration_ms: float
    discharges_ms: list[np.ndarray]
    units: np.ndarray
    force_t_ms: np.ndarray
    force_percent_mvc: np.ndarray

    def force_at(self, t_ms: np.ndarray) -> np.ndarray:
        """The recorded force (% MVC) linearly interpolated at ``t_ms`` (ms from the trial's start)."""
        return np.interp(t_ms, self.force_t_ms, self.force_percent_mvc)


@dataclass(frozen=True)
class RecordedDischarges:
    """One file: every unit's discharges (ms from the recording's start, file order) and the force (% MVC)."""

    path: Path
    fsamp_hz: float
    level_percent_mvc: float
    discharges_ms: list[np.ndarray]
    force_percent_mvc: np.ndarray

    @property
    def n_units(self) -> int:
        """Number of decomposed units."""
        return len(self.discharges_ms)

    @property
    def force_t_ms(self) -> np.ndarray:
        """Sample times of the force (ms)."""
        return np.arange(self.force_percent_mvc.size) * (1000.0 / self.fsamp_hz)

    def thresholds_percent_mvc(self) -> np.ndarray:
        """Each unit's recruitment threshold: the force (% MVC) at its first discharge (file order)."""
        return np.interp([d[0] for d in self.discharges_ms], self.force_t_ms, self.force_percent_mvc)

    def recruitment_order(self) -> np.ndarray:
        """File indices of the units from the lowest recruitment threshold to the highest."""
        first = np.array([d[0] for d in self.discharges_ms])
        return np.lexsort((first, self.thresholds_percent_mvc()))

    def rest_times_ms(self, rest_percent_mvc: float = REST_PERCENT_MVC) -> tuple[float, float]:
        """When the muscle was last at rest before the first discharge and first at rest again after the last one
        (ms): the force at or below ``rest_percent_mvc`` (% MVC).  The record's start (end) when it never is."""
        rest = finite_number(f"{self.path}: rest_percent_mvc", rest_percent_mvc)
        t, y = self.force_t_ms, self.force_percent_mvc
        first = min(d[0] for d in self.discharges_ms)
        last = max(d[-1] for d in self.discharges_ms)
        before = np.flatnonzero((t < first) & (y <= rest))
        after = np.flatnonzero((t > last) & (y <= rest))
        return (float(t[before[-1]]) if before.size else 0.0, float(t[after[0]]) if after.size else float(t[-1]))

    def trial(self, pad_ms: float = 1000.0, from_rest: bool = False,
              rest_percent_mvc: float = REST_PERCENT_MVC) -> DischargeTrial:
        """The window from ``pad_ms`` (ms) before the first discharge to ``pad_ms`` after the last one (within the
        force record), discharges in recruitment order with times from the window's start.  ``from_rest``: the
        window also covers the whole contraction, from :data:`REST_MARGIN_MS` before the force last left rest
        (:meth:`rest_times_ms`) to as long after it came back, so that a model starts and ends at rest as the
        muscle did even where the decomposition found no unit of the lowest thresholds."""
        pad = positive_number("pad_ms", pad_ms)
        t = self.force_t_ms
        start = min(d[0] for d in self.discharges_ms) - pad
        end = max(d[-1] for d in self.discharges_ms) + pad
        if from_rest:
            rest_before, rest_after = self.rest_times_ms(rest_percent_mvc)
            start, end = min(start, rest_before - REST_MARGIN_MS), max(end, rest_after + REST_MARGIN_MS)
        start, end = max(0.0, start), min(float(t[-1]), end)
        order = self.recruitment_order()
        sel = (t >= start) & (t <= end)
        return DischargeTrial(str(self.path), start, end - start, [self.discharges_ms[i] - start for i in order],
                              order, t[sel] - start, self.force_percent_mvc[sel])


def level_from_name(path: Path) -> float:
    """The contraction level (% MVC) in a Caillet file name (``S1_30_256``, ``TA_35_D``, ``GM_30``: the first
    number of two digits)."""
    m = re.search(r"(?:^|_)(\d{2})(?:_|$)", path.stem)
    if not m:
        raise InputError(f"{path}: no contraction level (% MVC) in the file name; pass level_percent_mvc")
    return float(m.group(1))


def _field(mat: dict, path: Path, name: str) -> np.ndarray:
    if name not in mat:
        found = sorted(k for k in mat if not k.startswith("__"))
        raise InputError(f"{path}: field {name!r} is missing (found {found})")
    return np.asarray(mat[name])


def numeric_field(path: Path, name: str, value: np.ndarray) -> np.ndarray:
    """``value`` as finite float64 numbers (flattened), else InputError naming the file and the field."""
    if value.dtype.kind not in "iuf" or value.size == 0:
        raise InputError(f"{path}: field {name!r} must hold numbers, got {value.dtype} of size {value.size}")
    out = value.astype(np.float64).ravel()
    if not np.all(np.isfinite(out)):
        raise InputError(f"{path}: field {name!r} is not finite at index {int(np.flatnonzero(~np.isfinite(out))[0])}")
    return out


def pulse_trains(path: Path, field: str, trains: Sequence[object], fsamp: float, n_samples: int,
                 first_sample: int) -> list[np.ndarray]:
    """Discharge sample indices of each unit (counted from ``first_sample``: 1 in MATLAB files, 0 in openhdemg's)
    as ms from the recording's start; every problem raises InputError naming the file, ``field`` and the unit."""
    out = []
    for i, x in enumerate(trains):
        where = f"{path}: field {field!r} unit {i}"
        k = numeric_field(path, f"{field} unit {i}", np.asarray(x))
        if np.any(k != np.round(k)):
            raise InputError(f"{where}: sample indices must be integers, got {k[k != np.round(k)][0]:g}")
        last = n_samples - 1 + first_sample
        if k[0] < first_sample or k[-1] > last:
            bad = k[0] if k[0] < first_sample else k[-1]
            raise InputError(f"{where}: sample {bad:g} lies outside the force record ({first_sample}..{last} at "
                             f"{fsamp:g} Hz)")
        problem = time_order_problem(k, where, "samples")
        if problem:
            raise InputError(problem)
        out.append((k - first_sample) * (1000.0 / fsamp))
    if not out:
        raise InputError(f"{path}: field {field!r} holds no units")
    return out


def _pulses(path: Path, cell: np.ndarray, fsamp: float, n_samples: int) -> list[np.ndarray]:
    if cell.dtype != object or cell.ndim != 2 or 1 not in cell.shape:
        raise InputError(f"{path}: field 'MUPulses' must be a 1 x n cell array, got {cell.dtype} {cell.shape}")
    return pulse_trains(path, "MUPulses", list(cell.ravel()), fsamp, n_samples, 1)


def normalise_force(path: Path, raw: np.ndarray, first_sample: int, level: float) -> np.ndarray:
    """``raw`` force (a.u.) in % MVC: baseline (the muscle at rest, see the module docstring) at 0, plateau at
    ``level``."""
    if first_sample < 1:
        raise InputError(f"{path}: field 'ref_signal' has no sample before the first discharge (no baseline)")
    pre = raw[:first_sample]
    floor = float(np.percentile(pre, 1.0))
    top = float(np.percentile(raw, 99.0))
    if top <= floor:
        raise InputError(f"{path}: field 'ref_signal' never rises above its baseline {floor:g}: no contraction")
    base = float(np.median(pre[pre <= floor + REST_BAND_FRACTION * (top - floor)]))  # below top: the band is narrower
    plateau = float(np.median(raw[raw >= base + PLATEAU_FRACTION * (top - base)]))
    return level * (raw - base) / (plateau - base)


def load_caillet(path: str | Path, level_percent_mvc: float | None = None) -> RecordedDischarges:
    """Read one Caillet .mat file (layout in the module docstring); every problem raises InputError naming the
    file and the field (and the unit)."""
    import scipy.io
    from scipy.io.matlab import MatReadError

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        mat = scipy.io.loadmat(p)
    except (MatReadError, ValueError, TypeError, OSError, NotImplementedError, IndexError) as exc:
        raise InputError(f"{p}: not a readable MATLAB .mat file ({exc})") from None
    level = level_from_name(p) if level_percent_mvc is None else positive_number("level_percent_mvc",
                                                                                 level_percent_mvc)
    fs = numeric_field(p, "fsamp", _field(mat, p, "fsamp"))
    if fs.size != 1 or fs[0] <= 0:
        raise InputError(f"{p}: field 'fsamp' must be one positive rate (Hz), got {fs[:3]}")
    raw = numeric_field(p, "ref_signal", _field(mat, p, "ref_signal"))
    trains = _pulses(p, _field(mat, p, "MUPulses"), float(fs[0]), raw.size)
    first = int(round(min(d[0] for d in trains) * fs[0] / 1000.0))
    force = normalise_force(p, raw, first, level)
    return RecordedDischarges(p, float(fs[0]), level, trains, force)
