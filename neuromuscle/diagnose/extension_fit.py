"""Step 4 of the diagnosis: fit a candidate's extension on the calibration trials, then predict every trial.

The extension is taken from the catalogue by its canonical name (``neuromuscle.model.extensions.registry()``);
its declared parameters (``Param`` with bounds) are free, from their defaults, within their declared bounds,
together with Module 2's C1, C2, C3, alpha (the baseline was calibrated without the extension and may have bent
to absorb the effect).  Objective NRMSE (trials count alike), forward differences, from the given start (the
reference's Module 2).  The *reference* (``fit_reference``) is the same fit without an extension: Module 2 refitted
on every calibration trial, the nested model each candidate is judged against (:mod:`.verdict`).
The 95 % intervals are the fit's (``hac+integrator``: HAC covariance per trial and the integrator's error, see
:mod:`neuromuscle.fit.intervals`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ..calibration import MODULE2_FREE
from ..errors import InputError
from ..fit import FitProblem, FitResult, SimulationOptions, fit
from ..fit.evaluate import TrialPool
from ..measured import Trial
from ..model.extensions import registry
from ..parameters import ParameterSet
from .baseline import simulate_all


@dataclass
class ExtensionFit:
    """One candidate's fitted extension: the full parameter set, the extension's own parameters (qualified names,
    parameter units) with 95 % intervals and their neutral values, the fit, and every trial's simulated force."""

    name: str
    parameters: ParameterSet
    extension_values: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    neutral: dict[str, float | None]
    fit: FitResult
    simulated: dict[str, np.ndarray]

    @property
    def n_parameters(self) -> int:
        """Parameters the extension adds (the refitted Module 2 ones are the baseline's)."""
        return len(self.extension_values)

    def away_from_neutral(self) -> list[str]:
        """Effect parameters whose 95 % interval excludes their neutral value."""
        out = []
        for q, nv in self.neutral.items():
            lo, hi = self.ci95[q]
            if nv is not None and np.isfinite(lo) and np.isfinite(hi) and not lo <= nv <= hi:
                out.append(q)
        return out


def available() -> list[str]:
    """Canonical names of the extensions in the catalogue."""
    return sorted(registry())


#: The fits' stopping tolerance (scipy's ftol, xtol, gtol): a fit stops when an iteration lowers the cost (a sum of
#: squared NRMSEs, %^2) by less than this fraction.  1e-4 of a cost of ~300 %^2 is ~0.03 %^2 over all calibration
#: trials, far below what the held-out judgement can see; the fits then stop on their plateau instead of creeping
#: on to ``max_iterations`` (suite seed 1: a doublet fit spent 8 of its 10 iterations lowering its cost by 0.05 %).
TOLERANCE = 1e-4


def _fit_on(calibration: Sequence[Trial], start: ParameterSet, free: dict, options: SimulationOptions, workers: int,
            max_iterations: int, pool: TrialPool | None) -> FitResult:
    """The one fit of this step: ``free`` parameters from ``start`` on ``calibration``, NRMSE, forward differences
    (on ``pool`` when given, else on ``workers`` processes)."""
    return fit(FitProblem(list(calibration), start, free, objective="nrmse", options=options),
               workers=workers if pool is None else 1, pool=pool, progress=False, max_iterations=max_iterations,
               fd="forward", tolerance=TOLERANCE)


#: The reference's name in fits and reports.
REFERENCE = "reference"


def fit_reference(baseline: ParameterSet, calibration: Sequence[Trial], all_trials: Sequence[Trial],
                  options: SimulationOptions, *, workers: int = 1, max_iterations: int = 10,
                  pool: TrialPool | None = None) -> ExtensionFit:
    """The baseline with Module 2 (C1, C2, C3, alpha) refitted on every ``calibration`` trial, no extension;
    ``all_trials`` simulated with it (pool: a TrialPool holding ``all_trials``, else ``workers`` processes)."""
    res = _fit_on(calibration, baseline, {n: None for n in MODULE2_FREE}, options, workers, max_iterations, pool)
    params = ParameterSet(baseline.name, res.parameters.values,
                          f"{baseline.source}; Module 2 refitted on every calibration trial (the reference)")
    return ExtensionFit(REFERENCE, params, {}, {}, {}, res, simulate_all(params, all_trials, options, pool=pool))


def fit_extension(name: str, baseline: ParameterSet, calibration: Sequence[Trial], all_trials: Sequence[Trial],
                  options: SimulationOptions, *, workers: int = 1, max_iterations: int = 10,
                  pool: TrialPool | None = None) -> ExtensionFit:
    """Fit extension ``name`` (+ Module 2, from ``baseline``'s values: the reference's) on ``calibration``;
    simulate ``all_trials`` with the result (pool: a TrialPool holding ``all_trials``, else ``workers``)."""
    known = registry()
    if name not in known:
        raise InputError(f"no extension {name!r} in the catalogue (have: {', '.join(sorted(known)) or 'none'})")
    ext = known[name]
    bounds = {ext.qualified(p.name): (p.lower, p.upper) for p in ext.parameters}
    start = {ext.qualified(p.name): p.default for p in ext.parameters}
    neutral = {ext.qualified(p.name): p.neutral for p in ext.parameters}
    free = {**bounds, **{n: None for n in MODULE2_FREE}}
    opts = replace(options, extensions=(name,))
    base = baseline.with_values(start)
    res = _fit_on(calibration, base, free, opts, workers, max_iterations, pool)
    params = ParameterSet(f"{baseline.name}+{name}", res.parameters.values,
                          f"{baseline.source}; extension {name} fitted on the calibration trials")
    sims = simulate_all(params, all_trials, options, extensions=(name,), pool=pool)
    return ExtensionFit(name, params, {q: res.estimates[q] for q in bounds}, {q: res.ci95[q] for q in bounds},
                        neutral, res, sims)
