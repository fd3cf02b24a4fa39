"""The diagnosis of a measured-data file, without writing anything.

    result = diagnose_data(read_measured("prep.h5"), workers=2)
    result.verdict                     # the first cause named, "none" or "unexplained"
    result.named                       # every cause named, in order, then "unexplained" when structure remains

Steps: describe every trial (:mod:`.phases`); split the trials into calibration and held-out (:mod:`.split`); calibrate
the baseline (:mod:`.baseline`); set its residuals against the explanatory variables (:mod:`.residuals`); then the
forward selection of causes (:mod:`.selection`), each candidate fitted with the baseline freedom of the model before it
(:mod:`.models`) and judged on the held-out trials (:mod:`.evidence`, :mod:`.rules`), and the backward check
(:mod:`.pruning`): a cause named before the last one that fails a rule of redundancy against the final model without
it is dropped.
After the last cause, the residual is *unexplained* when structure that no candidate removes is left in enough trials: a
trend where the model's muscle is quiet (rule R6's test) or a residual RMS over the whole trial above
``ACTIVE_STRUCTURE_RATIO`` noise sd.  Below that ratio, a preparation's misfit of parameters its trials cannot pin
down and an effect outside the catalogue cannot be told apart.
"""

from __future__ import annotations

import time
from contextlib import nullcontext
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..fit.evaluate import TrialPool
from ..measured import MeasuredData
from ..parameters import ParameterSet, load_parameters
from .baseline import Baseline, calibrate_baseline, check_split_sizes, check_trials
from .evidence import structured_trials
from .models import FittedModel
from .phases import TrialPhases, describe_all
from .pruning import Check, prune
from .residuals import Structure, explanatory_variables, residual_structure
from .rules import REST_Z, enough_trials
from .selection import Context, Step, rest_trends, select
from .split import Split, automatic_split, given_split

#: After the last cause: a residual RMS above this many noise sd in enough trials is structure left unexplained.
ACTIVE_STRUCTURE_RATIO = 3.0


@dataclass
class Diagnosis:
    """Everything the report needs: the data and their descriptions, the split, the baseline, the residual
    structure of the baseline, every step of the forward selection, the backward check's judgements, the causes
    named (those the backward check kept), the final model, the trials still structured under it, each trial's
    rest trend z under it (None without a rest window), wall time (s), and whether the held-out evidence was
    measured from the models' reach (:mod:`.reach`)."""

    data: MeasuredData
    phases: dict[str, TrialPhases]
    split: Split
    baseline: Baseline
    structure: Structure
    steps: list[Step]
    named: list[str]
    final: FittedModel
    structured_after: list[str]
    rest: dict[str, float | None]
    wall_time_s: float
    variables: dict[str, dict[str, np.ndarray]] = field(repr=False, default_factory=dict)
    checks: list[Check] = field(default_factory=list)
    reach: bool = False

    @property
    def verdict(self) -> str:
        """The first cause named, else "unexplained" or "none"."""
        return self.named[0] if self.named else "none"

    @property
    def causes(self) -> list[str]:
        """The causes named, in order ("unexplained" left out)."""
        return [n for n in self.named if n != "unexplained"]

    @property
    def noise(self):
        return self.baseline.noise


def prepare(data: MeasuredData, heldout: Sequence[str] | None = None) -> Split:
    """Refuse unusable data and an unusable split before any work (bad input: nothing is computed)."""
    check_trials(data)
    split = automatic_split(data) if heldout is None else given_split(data, heldout)
    check_split_sizes(split.calibration, split.heldout)
    return split


def left_unexplained(d_rest: dict[str, float | None], structured_active: Sequence[str], n_trials: int) -> bool:
    """Whether a final model leaves structure no candidate removed (module docstring)."""
    have = {i: z for i, z in d_rest.items() if z is not None}
    at_rest = [i for i, z in have.items() if abs(z) > REST_Z]
    return enough_trials(len(at_rest), len(have)) or enough_trials(len(structured_active), n_trials)


def diagnose_data(data: MeasuredData, *, heldout: Sequence[str] | None = None, base: ParameterSet | None = None,
                  workers: int = 1, progress: bool = False, max_steps: int | None = None,
                  reach: bool = False) -> Diagnosis:
    """The diagnosis of ``data`` (module docstring): automatic split or the ``heldout`` ids, base set CT09 unless
    ``base``, ``workers`` simulation processes, progress on stderr; reach: every candidate's held-out evidence
    measured from what the model before and the candidate's model each reach within their calibration confidence
    region (:mod:`.reach`; off by default: on held-out files it named what the default names, at more cost)."""
    t0 = time.perf_counter()
    split = prepare(data, heldout)
    base = base or load_parameters("CT09")
    trials = list(data.trials.values())
    with TrialPool(trials, workers) if workers > 1 else nullcontext() as pool:
        phases = describe_all(data.trials)
        ctx = Context(data, phases, split.calibration, split.heldout, {}, base, (), pool, progress, reach=reach)
        ctx.say(f"split ({split.method}): {len(split.calibration)} calibration, {len(split.heldout)} held-out")
        baseline = calibrate_baseline(data, phases, split.calibration, base, pool=pool, progress=progress)
        ctx.noise = baseline.noise
        ctx.base = baseline.scaled
        ctx.baseline_free = baseline.free
        measured = ctx.measured
        variables = {i: explanatory_variables(t, baseline.parameters, baseline.simulated[i])
                     for i, t in data.trials.items()}
        structure = residual_structure(data.trials, {i: baseline.simulated[i] - measured[i] for i in data.trials},
                                       variables)
        steps = select(ctx, baseline.model, **({} if max_steps is None else {"max_steps": max_steps}))
        pruned = prune(ctx, steps)
        final, named = pruned.final, list(pruned.named)
        ids = list(data.trials)
        structured = structured_trials(measured, final.simulated, baseline.noise, ids)
        active = structured_trials(measured, final.simulated, baseline.noise, ids, ACTIVE_STRUCTURE_RATIO)
        rest = rest_trends(ctx, final.simulated)
        if left_unexplained(rest, active, len(ids)):
            named.append("unexplained")
        ctx.say(f"named: {', '.join(named) or 'none'}")
    return Diagnosis(data, phases, split, baseline, structure, steps, named, final, structured, rest,
                     time.perf_counter() - t0, variables, pruned.checks, reach)
