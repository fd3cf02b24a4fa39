"""The twitch the workflow of van Zandwijk et al. 1998 fits: a measured CSV, or a synthetic isometric twitch with
seeded noise."""

from __future__ import annotations

import csv
import hashlib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .contraction import DEFAULT_STEP_S
from .twitch_fit import twitch_moment
from ..model.hatze_parameters import ExcitationTheta, Subject

#: Columns a twitch CSV must have.
CSV_COLUMNS: tuple[str, str] = ("time_s", "moment_nm")


@dataclass(frozen=True)
class Twitch:
    """A twitch to fit: times (s), moment (N m), the noise-free moment of a synthetic twitch (None for a CSV),
    and what the report says of its source."""
    t_s: NDArray[np.float64]
    moment_nm: NDArray[np.float64]
    clean_nm: NDArray[np.float64] | None
    info: dict[str, Any]


def read_twitch_csv(path: str | Path) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Read a measured twitch: a CSV with a header holding ``time_s`` (s) and ``moment_nm`` (N m).

    Raises InputError naming the file and the missing column, or the row and column of a bad value.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"twitch CSV {str(path)!r} does not exist")
    with p.open(newline="") as fh:
        reader = csv.DictReader(fh)
        header = [h.strip() for h in (reader.fieldnames or [])]
        missing = [c for c in CSV_COLUMNS if c not in header]
        if missing:
            raise InputError(f"{path}: missing column(s) {', '.join(map(repr, missing))} "
                             f"(found: {', '.join(map(repr, header)) or 'no header'})")
        reader.fieldnames = header
        cols: dict[str, list[float]] = {c: [] for c in CSV_COLUMNS}
        for row_no, row in enumerate(reader, start=2):
            for c in CSV_COLUMNS:
                raw = row.get(c)
                try:
                    v = float(str(raw).strip())
                except ValueError:
                    raise InputError(f"{path}: row {row_no}, column {c!r}: not a number ({raw!r})") from None
                if not math.isfinite(v):
                    raise InputError(f"{path}: row {row_no}, column {c!r}: non-finite value ({raw!r})")
                cols[c].append(v)
    t, m = (np.asarray(cols[c], dtype=float) for c in CSV_COLUMNS)
    if t.size < 6:
        raise InputError(f"{path}: need at least 6 samples, got {t.size}")
    if np.any(np.diff(t) <= 0.0):
        raise InputError(f"{path}: column 'time_s' must increase strictly")
    if t[0] < 0.0:
        raise InputError(f"{path}: column 'time_s' must be >= 0 (got {t[0]})")
    return t, m


def synthetic_twitch(subject: Subject, theta: ExcitationTheta, noise_nm: float, seed: int,
                     stim_time_s: float = 0.02, duration_s: float = 0.8, sample_interval_s: float = 1e-3,
                     step_s: float = DEFAULT_STEP_S) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                              NDArray[np.float64]]:
    """Isometric twitch (N m) of ``subject`` under ``theta`` sampled every ``sample_interval_s`` for ``duration_s``
    (s), plus N(0, noise_nm^2) noise from ``default_rng(seed)``. Returns t (s), noisy moment, clean moment."""
    n = int(round(duration_s / sample_interval_s))
    t = np.arange(n + 1) * sample_interval_s
    clean = twitch_moment(t, [stim_time_s], subject, theta, step_s)[0]
    noisy = clean + np.random.default_rng(seed).normal(0.0, noise_nm, clean.size)
    return t, noisy, clean


def load_twitch(twitch_csv: str | Path | None, subject: Subject, theta: ExcitationTheta, noise_nm: float,
                seed: int, stim_time_s: float, step_s: float) -> Twitch:
    """The CSV ``twitch_csv`` (its stimulus at ``stim_time_s``, s, inside its time range), or, when None, the
    synthetic twitch of ``subject`` under ``theta`` with noise ``noise_nm`` (N m) drawn with ``seed``."""
    if twitch_csv is not None:
        t, m_data = read_twitch_csv(twitch_csv)
        if not t[0] <= stim_time_s < t[-1]:
            raise InputError(f"stim_time_s = {stim_time_s} s lies outside the CSV's time_s range "
                             f"[{t[0]}, {t[-1]}] s")
        digest = hashlib.sha256(Path(twitch_csv).read_bytes()).hexdigest()
        info: dict[str, Any] = {"source": "csv", "path": str(Path(twitch_csv).resolve()), "sha256": digest}
        clean = None
    else:
        t, m_data, clean = synthetic_twitch(subject, theta, noise_nm, seed, stim_time_s, step_s=step_s)
        info = {"source": "synthetic", "theta": "Table 2 (subject 3)", "noise_nm": noise_nm, "seed": seed,
                "rng": "numpy.random.default_rng(seed).normal", "sample_interval_s": 1e-3,
                "duration_s": float(t[-1])}
    info.update({"subject": subject.name, "stim_time_s": stim_time_s, "n_samples": int(t.size),
                 "peak_moment_nm": float(np.max(m_data))})
    return Twitch(t, m_data, clean, info)
