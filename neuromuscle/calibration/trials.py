"""Which measured trials a calibration stage can use."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import InputError
from ..measured import MeasuredData, Trial

#: Isometric trials within this distance (mm) of g1 count as "at the optimum".
OPTIMUM_TOLERANCE_MM = 0.5


def isometric_length(trial: Trial) -> float | None:
    """The trial's constant length (mm), or None when its length varies (> 1e-6 mm)."""
    if trial.length is None:
        return None if trial.length_const is None else float(trial.length_const)
    x = np.asarray(trial.length, dtype=float)
    return float(x[0]) if np.ptp(x) <= 1e-6 else None


def in_model_units(trial: Trial) -> bool:
    """True when the trial's force is in N and its length in mm."""
    return trial.force_unit == "N" and trial.length_unit == "mm"


def is_step_trial(trial: Trial) -> bool:
    """A step-shortening trial that measures KSE: protocol "step", a sampled length (mm) and force in N."""
    return trial.protocol == "step" and trial.length is not None and in_model_units(trial)


def all_trials(data: MeasuredData | Sequence[Trial]) -> list[Trial]:
    """The trials of a data file, or the given trials."""
    return list(data.trials.values()) if isinstance(data, MeasuredData) else list(data)


def select_trials(data: MeasuredData, trials: Sequence[str] | None) -> list[Trial] | None:
    """The trials with ids ``trials`` (None: None, the stage chooses); refuses unknown ids."""
    if trials is None:
        return None
    missing = [t for t in trials if t not in data.trials]
    if missing:
        raise InputError(f"trial(s) {missing} not in the data (have: {', '.join(data.trials)})")
    return [data.trials[t] for t in trials]
