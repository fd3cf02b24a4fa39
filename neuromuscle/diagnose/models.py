"""Fitted models of one file: the baseline and every extended model the diagnosis compares, all fitted the same way.

A model is the Kim, Sandercock & Heckman 2015 muscle (Modules 1-3, eq 18 and eqs 19-20 off) plus zero or more
catalogue extensions (``neuromuscle.model.extensions``).  :func:`fit_model` fits its free parameters on the
calibration trials and simulates every trial with the result:

* **objective**: the chi-square the rules judge with: each trial's residual over its noise sd, scaled by
  sqrt((1 - rho)/(1 + rho)) for its AR(1) correlation (``Noise.chi2_weight``), so a 12 s train weighs as its
  samples do;
* **free parameters**: the baseline parameters the file identifies (:mod:`.baseline` chooses them: Module 2's
  C1, C2, C3 and alpha, Module 1's pump rate Umax and release decay tau2, Module 3's P0, g1, g2 and, with moving
  trials, KSE and the force-velocity coefficients a0-d0), plus every parameter of the model's extensions within
  its declared bounds.  A candidate is therefore judged against a model fitted with the same baseline freedom,
  and never against the compensations the baseline made for it;
* **several starts** (``starts``): each is fitted for ``RACE_ITERATIONS`` iterations, and the best continues to
  convergence.  A candidate starts from the model before it and from the same model with the baseline parameters
  it interacts with (``Extension.interacts``) put back at the base set's values: a baseline that bent Module 3 to
  absorb a length effect does not trap the length extension's fit in the bend;
* **movement parameters where they act**: KSE and the force-velocity coefficients are never fitted on the
  stimulated holds after movement whose history the model has no extension for (:func:`fit_model`);
* **convergence** is stated, never assumed: a fit converges when scipy's relative tolerance is met or when its
  last three iterations together lowered the chi-square by less than ``COST_TOLERANCE``; one that stops at
  ``max_iterations`` says so (``converged``).

Simulation: fixed step ``DT_MS`` (ms, the largest the fixed-step scheme allows: it resolves the 3 ms release
kernel), recorded every ``RECORD_DT_MS``, no settling (every mechanism starts at its resting steady state at the
trial's first length).  On a synthetic preparation simulated at 0.025 ms, the true parameters at 0.2 ms fit every
trial as well as at 0.025 ms (RMS residual over the noise sd equal to 0.01); the fits' Jacobians are forward
differences at the same step.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Mapping, Sequence

import numpy as np

from ..errors import InputError, NumericalError
from ..fit import FitProblem, FitResult, SimulationOptions, fit, trial_simulation
from ..fit.evaluate import TrialPool
from ..measured import Trial
from ..model.extensions import MOVEMENT_PARAMETERS, Extension, registry
from ..parameters import ParameterSet
from .phases import TrialPhases
from .residuals import Noise

DT_MS = 0.2
RECORD_DT_MS = 0.5
#: The fixed step (ms) of the runs that are only differenced: each fit's Jacobian (its columns and the point they
#: are taken from) and the screening's columns.  The step's error is nearly the same in a run and its moved copy
#: and cancels in their difference: the columns stay within a few per cent of those at DT_MS, at half the cost.
DIFFERENCE_DT_MS = 0.4
OPTIONS = SimulationOptions(dt_ms=DT_MS, record_dt_ms=RECORD_DT_MS, settle_ms=0.0, length_compensation=False,
                            movement_compensation=False)
#: The fits' stopping tolerance (scipy's ftol, xtol, gtol): an iteration that lowers the cost by less than this
#: fraction ends the fit.  1e-4 of a calibration chi-square of ~1e4-1e5 is 1-10 noise variances, below the BIC
#: penalties of the rules (15-35).
TOLERANCE = 1e-4
#: A candidate's fit stops earlier: one that stops short understates its own gain, never the model before it.
CANDIDATE_TOLERANCE = 1e-3
MAX_ITERATIONS = 15
#: The baseline's and a named model's own fits (what every candidate is measured against) get more.
MODEL_MAX_ITERATIONS = 24
#: Iterations every start of a fit gets before the best one continues alone.
RACE_ITERATIONS = 2
#: Every fit here is also converged where its last three iterations together lowered the calibration chi-square by
#: less than this: further iterations would move no parameter by as much as a standard error (a change of one in
#: chi-square), and the rules judge gains against BIC penalties of several units a parameter.
COST_TOLERANCE = 1.0


@dataclass
class FittedModel:
    """A model fitted on the calibration trials: its extensions, parameters, the names it freed, the fit, every
    trial's simulated force (N, by id), which start won and each start's calibration chi-square after the race."""

    extensions: tuple[str, ...]
    parameters: ParameterSet
    free: tuple[str, ...]
    fit: FitResult | None
    simulated: dict[str, np.ndarray]
    start: str = ""
    start_costs: dict[str, float] = field(default_factory=dict)
    converged: bool = True
    message: str = ""
    wall_s: float = 0.0

    @property
    def cost(self) -> float:
        """The calibration chi-square (noise variances)."""
        return float(self.fit.cost) if self.fit is not None else float("nan")

    @property
    def name(self) -> str:
        return " + ".join(("baseline",) + self.extensions)

    def extension_values(self, name: str) -> dict[str, float]:
        """The fitted parameters of extension ``name`` (qualified names, parameter units)."""
        ext = registry()[name]
        return {ext.qualified(p.name): float(self.parameters[ext.qualified(p.name)]) for p in ext.parameters}

    def ci95(self, name: str) -> dict[str, tuple[float, float]]:
        """95 % intervals of extension ``name``'s fitted parameters (HAC + integrator, the fit's)."""
        ext = registry()[name]
        out = {}
        for p in ext.parameters:
            q = ext.qualified(p.name)
            out[q] = self.fit.ci95[q] if self.fit is not None and q in self.fit.ci95 else (np.nan, np.nan)
        return out


def extension_class(name: str) -> type[Extension]:
    """The catalogue extension ``name``; InputError listing the catalogue otherwise."""
    known = registry()
    if name not in known:
        raise InputError(f"no extension {name!r} in the catalogue (have: {', '.join(sorted(known)) or 'none'})")
    return known[name]


def extension_bounds(names: Sequence[str]) -> dict[str, tuple[float, float]]:
    """Every parameter of the extensions ``names`` with its declared bounds (qualified names)."""
    out: dict[str, tuple[float, float]] = {}
    for n in names:
        ext = extension_class(n)
        out.update({ext.qualified(p.name): (p.lower, p.upper) for p in ext.parameters})
    return out


def extension_defaults(name: str) -> dict[str, float]:
    """Extension ``name``'s parameters at their declared defaults (qualified names)."""
    ext = extension_class(name)
    return {ext.qualified(p.name): p.default for p in ext.parameters}


def extension_neutral(name: str) -> dict[str, float]:
    """Extension ``name``'s effect parameters at their neutral values (qualified names): the extension inert."""
    ext = extension_class(name)
    return {ext.qualified(p.name): p.neutral for p in ext.parameters if p.neutral is not None}


def chi2_weights(trials: Sequence[Trial], noise: Mapping[str, Noise]) -> list[float]:
    """Each trial's weight (1/N^2) in the "sse" objective that makes a fit's cost the rules' chi-square."""
    return [noise[t.trial_id].chi2_weight for t in trials]


def simulate_all(params: ParameterSet, trials: Sequence[Trial], extensions: tuple[str, ...] = (),
                 options: SimulationOptions = OPTIONS, pool: TrialPool | None = None) -> dict[str, np.ndarray]:
    """Simulated force (N) of every trial, by id (on ``pool``'s workers when given)."""
    opts = replace(options, extensions=tuple(extensions))
    if pool is not None:
        sims = pool.simulate([params], trials, opts)[0]
        if sims is None:
            raise NumericalError(f"{params.name}: a trial's simulation failed numerically")
        return {t.trial_id: s for t, s in zip(trials, sims)}
    return {t.trial_id: trial_simulation(params, t, opts.dt_ms, record_dt_ms=opts.record_dt_ms,
                                         settle_ms=opts.settle_ms, length_compensation=opts.length_compensation,
                                         movement_compensation=opts.movement_compensation,
                                         extensions=opts.extensions) for t in trials}


def _one_fit(calibration: Sequence[Trial], start: ParameterSet, free: Mapping[str, tuple[float, float] | None],
             options: SimulationOptions, noise: Mapping[str, Noise], pool: TrialPool | None,
             max_iterations: int, tolerance: float, intervals: str, final_jacobian: bool = True,
             sample_weights: Mapping[str, np.ndarray] | None = None) -> FitResult:
    cal = list(calibration)
    per_sample = [sample_weights.get(t.trial_id) for t in cal] if sample_weights else None
    problem = FitProblem(cal, start, dict(free), objective="sse", weights=chi2_weights(cal, noise), options=options,
                         sample_weights=per_sample)
    return fit(problem, pool=pool, progress=False, max_iterations=max_iterations, fd="forward", tolerance=tolerance,
               intervals=intervals, final_jacobian=final_jacobian, cost_tolerance=COST_TOLERANCE,
               jacobian_dt_ms=DIFFERENCE_DT_MS)


def unexplained_history(phases: Mapping[str, TrialPhases], ids: Sequence[str],
                        extensions: Sequence[str]) -> dict[str, np.ndarray]:
    """Masks of the samples of trials ``ids`` in the holds after an active stretch or shortening
    (:meth:`.TrialPhases.hold_after`) whose history no extension of ``extensions`` describes (``Extension.after``),
    by id; trials without such samples are left out."""
    known = registry()
    signs = [s for s in (+1, -1) if not any(known[e].after == s for e in extensions)]
    out = {}
    for i in ids:
        m = np.zeros(phases[i].time_s.size, bool)
        for s in signs:
            m |= phases[i].hold_after(s)
        if m.any():
            out[i] = m
    return out


def fit_model(extensions: Sequence[str], baseline_free: Sequence[str], starts: Mapping[str, ParameterSet],
              calibration: Sequence[Trial], all_trials: Sequence[Trial], noise: Mapping[str, Noise], *,
              pool: TrialPool | None = None, max_iterations: int = MAX_ITERATIONS,
              options: SimulationOptions = OPTIONS, fixed_extensions: Sequence[str] = (),
              tolerance: float = TOLERANCE, intervals: str = "hac+integrator",
              phases: Mapping[str, TrialPhases] | None = None) -> FittedModel:
    """Fit the baseline plus ``extensions`` on ``calibration`` (module docstring): ``baseline_free`` and the
    parameters of every extension not in ``fixed_extensions`` free, from each of ``starts`` (name -> parameter
    set) for RACE_ITERATIONS, the best continued to ``max_iterations`` in all; every trial of ``all_trials``
    simulated with the result; tolerance: the fits' relative stopping tolerance; intervals: how the 95 %
    intervals are made (``neuromuscle.fit.intervals``; "hac" skips the half-step re-run where no interval is
    used).

    Movement parameters where only they act: with ``phases`` (every calibration trial's, by id), when KSE or a
    force-velocity coefficient is free and calibration trials hold stimulated holds after movement whose history
    the model has no extension for (:func:`unexplained_history`), the fit runs in two stages: every parameter on
    the samples outside those holds, then the movement parameters held there and the others refitted on every
    sample.  In such a hold, from HOLD_DELAY_S after the ramp, the model's force is the isometric force at that
    length: KSE and the force-velocity curve shape it only by a slow return they would need to be bent for, so a
    model fitted there takes up force enhancement or depression in its movement parameters (a slow eccentric
    return, a soft series element) and every history cause is then judged against that bend."""
    exts = tuple(extensions)
    history = unexplained_history(phases, [t.trial_id for t in calibration], exts) if phases is not None else {}
    movement = tuple(n for n in baseline_free if n in MOVEMENT_PARAMETERS)
    if not history or not movement:
        return _fit_model(exts, baseline_free, starts, calibration, all_trials, noise, pool=pool,
                          max_iterations=max_iterations, options=options, fixed_extensions=fixed_extensions,
                          tolerance=tolerance, intervals=intervals)
    t0 = time.perf_counter()
    weights = {i: (~m).astype(float) for i, m in history.items()}
    first = _fit_model(exts, baseline_free, starts, calibration, calibration, noise, pool=pool,
                       max_iterations=max_iterations, options=options, fixed_extensions=fixed_extensions,
                       tolerance=tolerance, intervals="hac", sample_weights=weights, final_jacobian=False)
    rest = tuple(n for n in baseline_free if n not in movement)
    second = _fit_model(exts, rest, {"movement parameters off the holds after movement": first.parameters},
                        calibration, all_trials, noise, pool=pool, max_iterations=max_iterations, options=options,
                        fixed_extensions=fixed_extensions, tolerance=tolerance, intervals=intervals)
    n = sum(int(m.sum()) for m in history.values())
    message = (f"{', '.join(movement)} fitted without the {n} samples of holds after movement in "
               f"{len(history)} trial(s): {first.message}; the rest on every sample: {second.message}")
    return replace(second, free=tuple(dict.fromkeys(movement + second.free)), start=first.start,
                   start_costs=first.start_costs, converged=first.converged and second.converged, message=message,
                   wall_s=time.perf_counter() - t0)


def _fit_model(extensions: Sequence[str], baseline_free: Sequence[str], starts: Mapping[str, ParameterSet],
               calibration: Sequence[Trial], all_trials: Sequence[Trial], noise: Mapping[str, Noise], *,
               pool: TrialPool | None, max_iterations: int, options: SimulationOptions,
               fixed_extensions: Sequence[str], tolerance: float, intervals: str,
               sample_weights: Mapping[str, np.ndarray] | None = None, final_jacobian: bool = True) -> FittedModel:
    """One stage of :func:`fit_model`; sample_weights: per-sample weights in [0, 1] of some calibration trials, by
    id (samples of weight 0 leave the objective); final_jacobian: False skips the Jacobian at the end, whose only
    use is the 95 % intervals (a first stage's are never read)."""
    t0 = time.perf_counter()
    exts = tuple(extensions)
    free: dict[str, tuple[float, float] | None] = {n: None for n in baseline_free}
    free.update(extension_bounds([e for e in exts if e not in set(fixed_extensions)]))
    opts = replace(options, extensions=exts)
    defaults = {q: v for e in exts for q, v in extension_defaults(e).items()}
    unique: dict[str, ParameterSet] = {}
    for how, p in starts.items():
        missing = {q: v for q, v in defaults.items() if q not in p}
        p = p.with_values(missing) if missing else p
        if not any(all(p[n] == q[n] for n in free) for q in unique.values()):
            unique[how] = p
    if not unique:
        raise InputError("fit_model needs at least one start")
    if len(unique) == 1:
        how, start = next(iter(unique.items()))
        res = _one_fit(calibration, start, free, opts, noise, pool, max_iterations, tolerance, intervals,
                       final_jacobian=final_jacobian, sample_weights=sample_weights)
        costs = {how: res.cost}
    else:
        # a start stopped by the race is continued by a fit of its own (or dropped): no Jacobian at its last point
        continued = max_iterations > RACE_ITERATIONS
        race = {how: _one_fit(calibration, p, free, opts, noise, pool, RACE_ITERATIONS, tolerance, "hac",
                              final_jacobian=not continued, sample_weights=sample_weights)
                for how, p in unique.items()}
        costs = {how: r.cost for how, r in race.items()}
        how = min(costs, key=costs.get)
        first = race[how]
        res = first
        if max_iterations > RACE_ITERATIONS and "max_iterations" in first.message:
            res = _one_fit(calibration, first.parameters, free, opts, noise, pool, max_iterations - RACE_ITERATIONS,
                           tolerance, intervals, final_jacobian=final_jacobian, sample_weights=sample_weights)
    converged = "max_iterations" not in res.message
    name = " + ".join(("baseline",) + exts)
    params = ParameterSet(name, res.parameters.values, f"fitted on the calibration trials from the {how} start")
    # the calibration trials were simulated at these parameters by the fit itself: only the others are run
    known = res.simulated
    rest = [t for t in all_trials if t.trial_id not in known]
    more = simulate_all(params, rest, exts, options, pool) if rest else {}
    sims = {t.trial_id: known[t.trial_id] if t.trial_id in known else more[t.trial_id] for t in all_trials}
    return FittedModel(exts, params, tuple(free), res, sims, how, costs, converged, res.message,
                       time.perf_counter() - t0)
