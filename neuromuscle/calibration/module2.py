"""Module 2 of the muscle (C1..C5, alpha) against twitches and sub-tetanic trains at the optimal length
(Kim et al. 2015, section 2.2.2), through :mod:`neuromuscle.fit`.

A :class:`~neuromuscle.fit.FitProblem` with the NRMSE objective (twitch and trains count alike), free C1, C2, C3,
alpha by default (C4, C5 shape tau_A far from the operating range and trade off with C3).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import InputError
from ..fit import FitProblem, SimulationOptions, fit
from ..fit.evaluate import TrialPool
from ..measured import MeasuredData, Trial
from ..parameters import ParameterSet
from .stage import StageResult
from .trials import OPTIMUM_TOLERANCE_MM, all_trials, in_model_units, isometric_length, select_trials

MODULE2_FREE = ("C1", "C2", "C3", "alpha")


def module2_trials(data: MeasuredData | Sequence[Trial], g1: float,
                   tolerance_mm: float = OPTIMUM_TOLERANCE_MM) -> list[Trial]:
    """Isometric, stimulated trials in N/mm within tolerance_mm of the optimum g1 (mm)."""
    out = []
    for t in all_trials(data):
        x = isometric_length(t)
        if in_model_units(t) and x is not None and abs(x - g1) <= tolerance_mm and np.size(t.stimulus_times_s):
            out.append(t)
    return out


def calibrate_module2(data: MeasuredData, base_params: ParameterSet, trials: Sequence[str] | None = None, *,
                      free: Sequence[str] = MODULE2_FREE, options: SimulationOptions | None = None,
                      objective: str = "nrmse", workers: int = 1, max_iterations: int = 30,
                      progress: bool = False, pool: TrialPool | None = None) -> StageResult:
    """Fit a Module 2 subset (default C1, C2, C3, alpha) to twitches and sub-tetanic trains at the optimum.

    trials: ids to use (default: every isometric stimulated trial within 0.5 mm of g1).  Flags of
    unidentifiable parameters (the fit's identifiability rules) are reported in ``notes``.  pool: a
    :class:`~neuromuscle.fit.evaluate.TrialPool` holding ``data``'s trials, instead of ``workers`` processes."""
    chosen = select_trials(data, trials)
    if chosen is None:
        chosen = module2_trials(data, base_params["g1"])
    if not chosen:
        raise InputError(f"Module 2: no isometric stimulated trial (N, mm) at the optimum g1 = "
                         f"{base_params['g1']:g} mm")
    opts = options or SimulationOptions(dt_ms=0.05, settle_ms=300.0)
    problem = FitProblem(chosen, base_params, list(free), objective=objective, options=opts)
    res = fit(problem, workers=workers if pool is None else 1, pool=pool, progress=progress,
              max_iterations=max_iterations)
    errors: dict[str, float] = {f"nrmse_{k}": v for k, v in res.nrmse_percent.items()}
    errors.update({f"se_{k}": v for k, v in res.std_errors.items()})
    notes = [f"{n} NOT IDENTIFIABLE: {why}" for n, why in res.flags.items()]
    notes.append(f"{res.n_iterations} iterations, {res.n_simulations} simulations, {res.wall_time_s:.1f} s: "
                 f"{res.message}")
    return StageResult("module2", dict(res.estimates), errors, [t.trial_id for t in chosen], notes, fit=res)
