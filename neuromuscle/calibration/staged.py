"""The staged calibration of Kim et al. 2015 (section 2.2.2), each stage usable alone.

The paper's order: Module 1 is adopted (Westerblad & Allen); Module 3 from three kinds of data
(KSE from a step shortening, g1/g2 (and P0) from isometric force-length points, a0..d0 from velocity-tension
points); then Module 2 (C1..C5, alpha) against twitches and sub-tetanic trains at the optimal length; finally
the length compensation phi1..phi4 (eq 18) from twitches at several lengths.

:func:`staged_calibration` chains the stages on one :class:`~neuromuscle.measured.MeasuredData` and skips, with
the reason, any stage whose data are absent.  Where the point data live in a measured-data file (extra
datasets, allowed by the layout):

* ``/calibration/force_length``   (n, 2): length Xm (mm), isometric tetanic force (N), at full activation.
* ``/calibration/force_velocity`` (n, 2): velocity (mm/s, + lengthening), tension (N), full activation at the
  optimum.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..fit import SimulationOptions
from ..fit.evaluate import TrialPool
from ..measured import MeasuredData
from ..parameters import ParameterSet
from .length_compensation import calibrate_length_compensation, twitch_trials
from .module2 import MODULE2_FREE, calibrate_module2, module2_trials
from .module3 import calibrate_force_length, calibrate_force_velocity, kse_from_steps
from .stage import StageResult
from .trials import is_step_trial, isometric_length

FORCE_LENGTH_PATH = "/calibration/force_length"
FORCE_VELOCITY_PATH = "/calibration/force_velocity"


@dataclass
class StagedCalibration:
    """All stages in order and the final parameter set."""

    parameters: ParameterSet
    stages: list[StageResult]

    def stage(self, name: str) -> StageResult:
        """The stage called ``name`` (KeyError if absent)."""
        for s in self.stages:
            if s.stage == name:
                return s
        raise KeyError(name)

    def summary(self) -> str:
        return "\n".join(s.summary() for s in self.stages)


def _points_from(data: MeasuredData, path: str) -> np.ndarray | None:
    arr = data.extra_datasets.get(path)
    if arr is None:
        return None
    a = np.asarray(arr, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"{path}: expected an (n, 2) dataset, got shape {a.shape}")
    return a


def staged_calibration(data: MeasuredData, base_params: ParameterSet, *, module2_free: Sequence[str] = MODULE2_FREE,
                       options: SimulationOptions | None = None, workers: int = 1, max_iterations: int = 30,
                       progress: bool = False, name: str | None = None,
                       length_compensation: bool = True, pool: TrialPool | None = None) -> StagedCalibration:
    """Module 3 (force-length, force-velocity, KSE) -> Module 2 -> length compensation, on whatever ``data``
    holds; a stage without its data is skipped with the reason (the base values stay).  length_compensation=False
    skips the eq 18 stage (a model without eq 18, e.g. the diagnosis baseline).  pool: a TrialPool holding
    ``data``'s trials for the Module 2 stage, instead of ``workers`` processes."""
    params = base_params
    stages: list[StageResult] = []
    fl = _points_from(data, FORCE_LENGTH_PATH)
    if fl is None:
        stages.append(StageResult("force-length", skipped=f"no {FORCE_LENGTH_PATH} points"))
    else:
        r = calibrate_force_length(fl[:, 0], fl[:, 1])
        params = params.with_values(**r.values)
        stages.append(r)
    fv = _points_from(data, FORCE_VELOCITY_PATH)
    if fv is None:
        stages.append(StageResult("force-velocity", skipped=f"no {FORCE_VELOCITY_PATH} points"))
    else:
        r = calibrate_force_velocity(fv[:, 0], fv[:, 1], params["P0"])
        params = params.with_values(**r.values)
        stages.append(r)
    steps = [t for t in data.trials.values() if is_step_trial(t)]
    if not steps:
        stages.append(StageResult("KSE", skipped="no step-shortening trial (protocol 'step' with a length trace)"))
    else:
        r = kse_from_steps(steps, params["P0"])
        params = params.with_values(**r.values)
        stages.append(r)
    m2 = module2_trials(data, params["g1"])
    if not m2:
        stages.append(StageResult("module2", skipped=f"no isometric stimulated trial at g1 = {params['g1']:g} mm"))
    else:
        r = calibrate_module2(data, params, [t.trial_id for t in m2], free=module2_free, options=options,
                              workers=workers, max_iterations=max_iterations, progress=progress, pool=pool)
        params = params.with_values(**r.values)
        stages.append(r)
    tw = twitch_trials(data)
    n_len = len({round(isometric_length(t), 9) for t in tw})
    if not length_compensation:
        stages.append(StageResult("length-compensation", skipped="eq 18 switched off"))
    elif n_len < 2:
        stages.append(StageResult("length-compensation", skipped=f"twitches at {n_len} length(s); >= 2 needed"))
    else:
        r = calibrate_length_compensation(data, params, [t.trial_id for t in tw], options=options)
        params = params.with_values(**r.values)
        stages.append(r)
    final = ParameterSet(name or f"{base_params.name}-calibrated", params.values,
                         f"staged calibration from {base_params.name} on {data.path or 'data in memory'}")
    return StagedCalibration(final, stages)
