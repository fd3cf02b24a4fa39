"""``fit``: one fit of a :class:`.problem.FitProblem`, from the start (or a checkpoint) to a :class:`FitResult`
with the uncertainty and identifiability of its estimates (:mod:`.intervals` on :mod:`.uncertainty`,
``Rules.for_fit``)."""

from __future__ import annotations

import os
import time
from collections import OrderedDict
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

import numpy as np

from ..errors import InputError, NumericalError
from ..analysis.metrics import nrmse_percent
from ..parameters import SPECS, ParameterSet
from ..sim.simulator import MAX_DIFFERENCE_DT_MS
from .checkpoint import Tracker, read_checkpoint
from .evaluate import MapFn, SimulationOptions, TrialPool, batched_residuals, candidate_map, evaluate_candidate
from .intervals import INTERVAL_METHODS, fit_uncertainty
from .optimizers import fd_jacobian, praxis, trust_region_least_squares
from .problem import FitProblem
from .uncertainty import Rules, Uncertainty, describe_method

METHODS = ("least_squares", "praxis")


@dataclass
class FitResult:
    """Outcome of :func:`fit`: the fitted ParameterSet, the :class:`Uncertainty` of the free parameters
    (estimates, SE and intervals in the units of ``SPECS``), cost (sum of squared residuals, see
    :mod:`.objectives`), ``nrmse_percent`` and the simulated force (N) per trial id, counters and history
    (``n_simulations`` counts the trial runs the fit needed, also one a pool-backed fit took from a candidate it
    had just run);
    ``z`` and ``jacobian``: the search vector of the estimate and dr/dz there, from runs at ``fit``'s
    ``jacobian_dt_ms`` when given (other interval methods: :func:`.intervals.fit_uncertainty`); ``jacobian`` is None
    when ``fit(..., final_jacobian=False)`` stopped at its iteration limit."""

    parameters: ParameterSet
    uncertainty: Uncertainty
    cost: float
    nrmse_percent: dict[str, float]
    simulated: dict[str, np.ndarray]
    n_simulations: int
    n_iterations: int
    wall_time_s: float
    method: str
    message: str
    history: list[dict[str, Any]] = field(default_factory=list)
    z: np.ndarray | None = None
    jacobian: np.ndarray | None = None

    @property
    def free(self) -> list[str]:
        return list(self.uncertainty.names)

    @property
    def estimates(self) -> dict[str, float]:
        return self.uncertainty.estimates

    @property
    def std_errors(self) -> dict[str, float]:
        return self.uncertainty.std_errors

    @property
    def ci95(self) -> dict[str, tuple[float, float]]:
        return self.uncertainty.ci95

    @property
    def identifiable(self) -> dict[str, bool]:
        return self.uncertainty.identifiable

    @property
    def interval_method(self) -> str:
        """How the intervals were made (``Uncertainty.method``; :func:`.uncertainty.describe_method`)."""
        return self.uncertainty.method

    @property
    def flags(self) -> dict[str, str]:
        return self.uncertainty.flags

    @property
    def singular_values(self) -> np.ndarray:
        return self.uncertainty.singular_values

    @property
    def correlation(self) -> np.ndarray:
        return self.uncertainty.correlation

    @property
    def unidentifiable(self) -> list[str]:
        """Names of the parameters the data cannot identify."""
        return [n for n in self.free if not self.identifiable[n]]

    def summary(self) -> str:
        """A short table: estimate, SE, 95 % interval, flag."""
        lines = [f"{self.method}: cost {self.cost:.6g}, {self.n_iterations} iterations, {self.n_simulations} "
                 f"simulations, {self.wall_time_s:.1f} s ({self.message})",
                 f"  intervals: {describe_method(self.interval_method)}"]
        for n in self.free:
            lo, hi = self.ci95[n]
            flag = f"  NOT IDENTIFIABLE: {self.flags[n]}" if n in self.flags else ""
            lines.append(f"  {n:7s} = {self.estimates[n]:.6g} {SPECS[n].unit}  SE {self.std_errors[n]:.3g}  "
                         f"95% [{lo:.6g}, {hi:.6g}]{flag}")
        lines += [f"  NRMSE {k}: {v:.3f} %" for k, v in self.nrmse_percent.items()]
        return "\n".join(lines)


#: Candidates whose forces a pool-backed fit keeps (the estimate is usually among them).
_RECENT = 16
Residuals = Callable[[list[np.ndarray]], Iterable[np.ndarray]]
Simulate = Callable[[np.ndarray, "SimulationOptions | None"], list[np.ndarray]]
ResidualsOf = Callable[[FitProblem], Residuals]


@contextmanager
def _evaluator(problem: FitProblem, map_fn: MapFn | None, workers: int, mp_context: str,
               pool: TrialPool | None) -> Iterator[tuple[Residuals, Simulate, ResidualsOf]]:
    """How the fit evaluates: (residuals of a list of candidates, every trial's force at one z with given
    options, the residuals of a variant of ``problem`` with other simulation options, e.g. the Jacobian's).  With
    ``pool``, or ``workers`` > 1 (a pool of this fit's own), all go through a :class:`.evaluate.TrialPool` (split
    by candidate and trial); else candidates go through ``map_fn`` (or serially) and single runs stay in this
    process."""
    if pool is None and map_fn is None and workers > 1:
        with TrialPool(problem.trials, workers, mp_context) as own:
            with _evaluator(problem, None, 1, mp_context, own) as ev:
                yield ev
        return
    if pool is not None:
        pool.indices(problem.trials)  # refuse a pool without these trials before any work
        recent: OrderedDict[bytes, list[np.ndarray]] = OrderedDict()  # the forces of the last candidates

        def residuals(zs: list[np.ndarray]) -> list[np.ndarray]:
            out = pool.residuals(problem, zs, keep=recent)
            while len(recent) > _RECENT:
                recent.popitem(last=False)
            return out

        def simulate(z: np.ndarray, options: SimulationOptions | None) -> list[np.ndarray]:
            if options is None and (key := np.asarray(z, dtype=float).tobytes()) in recent:
                return recent[key]  # the estimate is usually a candidate just evaluated: not run again
            return _all_ran(pool.simulate([problem.parameters(z)], problem.trials,
                                          problem.options if options is None else options)[0])

        yield residuals, simulate, lambda variant: partial(pool.residuals, variant)
        return
    if map_fn is None:  # in this process: each trial's candidates batched into one NEURON run
        yield partial(batched_residuals, problem), problem.simulate_trials, lambda v: partial(batched_residuals, v)
        return
    with candidate_map(map_fn, workers, mp_context) as map_candidates:
        yield (partial(map_candidates, partial(evaluate_candidate, problem)), problem.simulate_trials,
               lambda variant: partial(map_candidates, partial(evaluate_candidate, variant)))


def _all_ran(sims: list[np.ndarray] | None) -> list[np.ndarray]:
    if sims is None:
        raise NumericalError("the fitted parameters' simulation failed numerically")
    return sims


def fit(problem: FitProblem, method: str = "least_squares", map_fn: MapFn | None = None, workers: int = 1,
        checkpoint: str | os.PathLike | None = None, progress: bool = True, *, resume: bool = False,
        fd: str = "central", fd_step: float = 1e-3, max_iterations: int = 100, tolerance: float = 1e-8,
        ident_rcond: float = 1e-3, max_rel_se: float = 0.5, mp_context: str = "spawn",
        intervals: str = INTERVAL_METHODS[0], pool: TrialPool | None = None,
        jacobian_dt_ms: float | None = None, final_jacobian: bool = True,
        cost_tolerance: float | None = None) -> FitResult:
    """Fit ``problem``'s free parameters (search space: :mod:`.transforms`; statistics: :mod:`.uncertainty`).

    method: "least_squares" (scipy trust-region reflective with a finite-difference Jacobian in z) or
    "praxis" (NEURON's h.fit_praxis on the cost, the optimiser of Kim et al. 2015; serial; bounds by clipping plus a
    penalty).  map_fn(fn, iterable) evaluates candidates (any ``map``; serial by default); ``workers`` > 1
    instead splits every evaluation by candidate and trial over a process pool (:class:`.evaluate.TrialPool`),
    and ``pool`` (a TrialPool holding the problem's trials) does the same on a pool the caller keeps.
    checkpoint: JSON path written after every iteration; resume=True starts from it.
    tolerance: scipy's ftol/xtol/gtol (least_squares) or praxis' tolerance in z.  cost_tolerance (least_squares):
    also converged where the last three iterations together lowered the cost by less than this, in the cost's own
    units (a chi-square when the residuals are weighted by 1/sd).  max_iterations: iterations
    (Jacobians; praxis: rounds of 2k+2 evaluations) of this call; the best point so far is returned after it.
    fd, fd_step: finite differences (:func:`.optimizers.fd_jacobian`).  ident_rcond, max_rel_se: the
    identifiability flags (``Rules.for_fit``).  intervals: how the 95 % intervals are made, one of
    ``INTERVAL_METHODS`` (:mod:`.intervals`; the default adds one simulation of every trial at half the step).
    jacobian_dt_ms: the fixed step (ms, at most ``sim.MAX_DIFFERENCE_DT_MS``) of the least-squares Jacobian's runs,
    its base point run again at that step (None: the problem's own step).  The step's error cancels in the
    differences, so a coarser step makes the Jacobian cheaper at little cost in accuracy; every residual the
    optimiser minimises, the best point, the cost and the forces returned stay at the problem's step.  The intervals
    use the last Jacobian.
    final_jacobian: False for a fit that another continues from its estimate when it stops at ``max_iterations``
    (e.g. starts raced for a few iterations): a fit stopped there ends at a point whose Jacobian was not yet made,
    and none is made for its intervals (a Jacobian costs one run of every trial per free parameter); its
    ``uncertainty`` is then :meth:`.uncertainty.Uncertainty.not_estimated` and ``jacobian`` None.
    """
    if not (isinstance(max_iterations, int) and max_iterations >= 1):
        raise InputError(f"max_iterations must be an integer >= 1, got {max_iterations!r}")
    if cost_tolerance is not None and not (isinstance(cost_tolerance, (int, float)) and cost_tolerance > 0):
        raise InputError(f"cost_tolerance must be a number > 0 or None, got {cost_tolerance!r}")
    if method not in METHODS:
        raise InputError(f"method must be one of {METHODS}, got {method!r}")
    if intervals not in INTERVAL_METHODS:
        raise InputError(f"intervals must be one of {INTERVAL_METHODS}, got {intervals!r}")
    if fd not in ("central", "forward"):
        raise InputError(f"fd must be 'central' or 'forward', got {fd!r}")
    if not (isinstance(workers, int) and workers >= 1):
        raise InputError(f"workers must be an integer >= 1, got {workers!r}")
    if jacobian_dt_ms is not None and not (isinstance(jacobian_dt_ms, (int, float))
                                           and 0 < jacobian_dt_ms <= MAX_DIFFERENCE_DT_MS):
        raise InputError(f"jacobian_dt_ms must be a fixed step in ms, > 0 and <= {MAX_DIFFERENCE_DT_MS}, got "
                         f"{jacobian_dt_ms!r}")
    if sum((map_fn is not None, workers > 1, pool is not None)) > 1:
        raise InputError("give one of map_fn, workers > 1 and pool, not several")
    ckpt = Path(checkpoint) if checkpoint is not None else None
    if resume and ckpt is None:
        raise InputError("resume=True needs the checkpoint path")
    previous = read_checkpoint(ckpt, problem) if resume else None
    z0 = problem.to_z(previous["best"]) if previous else np.zeros(len(problem.free))
    lo, hi = problem.z_bounds()
    z0 = np.clip(z0, lo, hi)
    tracker = Tracker(problem, method, ckpt, progress, previous)
    with _evaluator(problem, map_fn, workers, mp_context, pool) as (residuals, simulate, residuals_of):

        def run_all(zs: list[np.ndarray]) -> list[np.ndarray]:
            rs = [np.asarray(r, dtype=float) for r in residuals(zs)]
            tracker.evaluated(zs, rs)
            return rs

        jacobian_run_all: Callable[[list[np.ndarray]], list[np.ndarray]] | None = None
        if jacobian_dt_ms is not None:
            coarse = residuals_of(problem.with_options(replace(problem.options, dt_ms=float(jacobian_dt_ms),
                                                               record_dt_ms=None, differenced=True)))

            def run_coarse(zs: list[np.ndarray]) -> list[np.ndarray]:
                tracker.n_sim += len(zs) * len(problem.trials)  # counted, never the best point (another step)
                return [np.asarray(r, dtype=float) for r in coarse(zs)]

            jacobian_run_all = run_coarse

        if method == "least_squares":
            z, message, jr = trust_region_least_squares(z0, lo, hi, run_all, tracker, fd, fd_step,
                                                        max_iterations, tolerance, jacobian_run_all,
                                                        cost_tolerance)
        else:
            z, message = praxis(z0, lo, hi, run_all, tracker, max_iterations, tolerance)
            jr = None
        stopped = "max_iterations" in message
        jac: np.ndarray | None = None
        if jr is not None:
            jac = jr[0]
        elif final_jacobian or not stopped:
            jac = fd_jacobian(z, lo, hi, jacobian_run_all or run_all, fd, fd_step, None)[0]
        sims = simulate(z, None)
        tracker.n_sim += len(problem.trials)
        r = problem.residuals_from(sims)
        tracker.best_z, tracker.best_cost = z, float(r @ r)
        if jac is None:
            unc = Uncertainty.not_estimated(problem.to_values(z), "not estimated: the fit stopped at max_iterations "
                                            "and is to be continued from this point")
        else:
            unc = fit_uncertainty(problem, z, jac, sims, intervals, Rules.for_fit(ident_rcond, max_rel_se), simulate)
    if "integrator" in intervals and jac is not None:  # the re-run at half the step
        tracker.n_sim += len(problem.trials)
    tracker.write(final=True)
    return FitResult(
        parameters=problem.parameters(z), uncertainty=unc, cost=float(r @ r),
        nrmse_percent={t.trial_id: nrmse_percent(t.force, s) for t, s in zip(problem.trials, sims)},
        simulated={t.trial_id: s for t, s in zip(problem.trials, sims)}, n_simulations=tracker.n_sim,
        n_iterations=tracker.n_iter, wall_time_s=time.perf_counter() - tracker.t_start, method=method,
        message=message, history=tracker.history, z=z, jacobian=jac)
