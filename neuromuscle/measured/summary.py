"""Human-readable summary of measured data (times in s, rates in Hz), and the check of a file."""

from __future__ import annotations

import numpy as np

from .hdf5 import read_measured
from .schema import MeasuredData, PathLike, Trial


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
