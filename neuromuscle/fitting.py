"""Fit parameters of the three-module muscle to measured trials (seed 000 eq 5: sum of squared force errors).

Reads like the experiment::

    data = read_measured("cat_soleus.h5")
    problem = FitProblem(list(data.trials.values()), base=load_parameters("CT09"), free=["C1", "C3"])
    result = fit(problem, workers=2, checkpoint="fit.json")
    result.parameters.save("fitted.json"); result.summary()

Decisions (documented once, here):

* **Simulation of a trial** (:func:`trial_simulation`): the trial's clock (s) becomes the simulation clock (ms)
  with ``time_s[0]`` at ``settle_ms`` (default 500 ms, spec: Ã starts at 0 and must settle before the first
  stimulus).  During the settling period the length is held at the trial's first length.  The force is recorded
  every ``record_dt_ms`` (default: every step) and linearly interpolated at the trial's samples.  Trials must
  be in N and mm (the model's units): joint moments / angles are refused.
* **Search space.**  A free parameter whose admissible range (``SPECS``) is strictly positive, or non-negative
  with a positive start and lower bound, is fitted as z = ln(p / p_start); any other as
  z = (p - p_start) / scale with scale = max(|p_start|, (upper - lower) / 10).  z = 0 at the start, and equal
  steps in z are equal relative changes: finite differences and trust regions behave the same for C3 (ms,
  ~60) and C1 (~0.1).  Default bounds: [p/10, 10 p] for log parameters, p ± max(|p|, 1) for the others, both
  clipped to the admissible range.
* **Objective.**  ``"sse"``: residuals sqrt(w_k) (F_sim - F_meas) (N), cost = sum of squares (eq 5 of seed 000,
  weighted by trial).  ``"nrmse"``: residuals sqrt(w_k) 100 (F_sim - F_meas) / (range_k sqrt(n_k)), so that
  cost = sum_k w_k NRMSE_k^2 (%^2, eq 17): trials of different size and force range count alike.
  ``cost`` in :class:`FitResult` is that sum of squares (not scipy's half of it).
* **Jacobian.**  Central differences in z (step ``fd_step``, default 1e-3, i.e. 0.1 % for log parameters;
  one-sided at a bound; ``fd="forward"`` halves the cost).  All candidates of one Jacobian are evaluated by one
  call of ``map_fn`` in a fixed order, so serial and parallel fits are identical: every candidate is a pure
  function of its parameter vector (fixed-step integration; each simulation builds and tears down its unit).
* **Uncertainty** (at the optimum, in parameter units): cov = s^2 (J^T J)^-1 with s^2 = cost / (n - k);
  95 % intervals est ± t_{0.975, n-k} SE (Wald, symmetric).  With weights, this is the usual weighted-least-
  squares estimate (exact when the weights are inverse noise variances).
* **Identifiability.**  J (in z) is column-normalised and decomposed; a parameter is flagged when it has no
  effect (zero column), when it loads (|v| > 0.2) on a direction whose singular value is below
  ``ident_rcond`` (default 1e-3) times the largest, or when its relative SE exceeds ``max_rel_se`` (default 0.5).
* **Checkpoint** (JSON, written atomically after every iteration): the free names and their search-space
  references, the current best parameters and cost, the history (one entry per iteration) and counters.
  ``fit(..., checkpoint=path, resume=True)`` starts from the best parameters in it and continues its history.
"""

from __future__ import annotations

import concurrent.futures
import json
import math
import multiprocessing
import os
import sys
import time
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from .errors import InputError, NumericalError
from .analysis.metrics import nrmse_percent
from .length import LengthTrace
from .measured import Trial
from .parameters import SPECS, ParameterSet
from .unit import simulate

OBJECTIVES = ("sse", "nrmse")
METHODS = ("least_squares", "praxis")
CHECKPOINT_SCHEMA = "neuromuscle.fit-checkpoint/1"

MapFn = Callable[[Callable[[Any], Any], Iterable[Any]], Iterable[Any]]


# ------------------------------------------------------------------------------------------ one trial


@dataclass(frozen=True)
class SimulationOptions:
    """How each trial is simulated: fixed step dt_ms (ms), recording interval record_dt_ms (ms; None = dt_ms),
    settling time settle_ms (ms) before the trial's first sample, and the model's eq 18 / eqs 19-20 switches."""

    dt_ms: float = 0.05
    record_dt_ms: float | None = None
    settle_ms: float = 500.0
    length_compensation: bool = True
    movement_compensation: bool = False


def _check_trial_units(trial: Trial) -> None:
    if trial.force_unit != "N" or trial.length_unit != "mm":
        raise InputError(f"trial '{trial.trial_id}': force in {trial.force_unit!r} and length in "
                         f"{trial.length_unit!r}; the muscle model needs 'N' and 'mm' (convert joint moments "
                         "and angles first)")


def trial_simulation(params: ParameterSet, trial: Trial, dt_ms: float = 0.05, *,
                     record_dt_ms: float | None = None, settle_ms: float = 500.0,
                     length_compensation: bool = True, movement_compensation: bool = False) -> np.ndarray:
    """Simulated force (N) of a measured trial at the trial's own time points (``trial.time_s``, s).

    The trial's time_s[0] is placed at settle_ms (ms) of simulated time; the length (constant or played) is
    held at its first value before that.  Stimulus times (s) are converted to ms on the same clock.
    """
    _check_trial_units(trial)
    if not np.isfinite(settle_ms) or settle_ms < 0:
        raise InputError(f"settle_ms must be finite and >= 0, got {settle_ms}")
    t0 = float(trial.time_s[0])
    t_ms = settle_ms + (np.asarray(trial.time_s, dtype=float) - t0) * 1000.0
    duration_ms = float(t_ms[-1])
    spikes_ms = settle_ms + (np.asarray(trial.stimulus_times_s, dtype=float) - t0) * 1000.0
    length: LengthTrace | float
    if trial.length is None:
        if trial.length_const is None:
            raise InputError(f"trial '{trial.trial_id}': neither a length dataset nor a constant length")
        length = float(trial.length_const)
    else:
        x = np.asarray(trial.length, dtype=float)
        lt, lx = (t_ms, x) if settle_ms == 0 else (np.concatenate([[0.0], t_ms]), np.concatenate([[x[0]], x]))
        length = float(x[0]) if np.all(x == x[0]) else LengthTrace(lt, lx, name=f"trial {trial.trial_id}")
    rec = dt_ms if record_dt_ms is None else record_dt_ms
    res = simulate(params, spikes_ms, length, duration_ms, dt_ms=dt_ms, record_dt_ms=rec,
                   length_compensation=length_compensation, movement_compensation=movement_compensation)
    return np.interp(t_ms, res.t_ms, res.force_N)


# --------------------------------------------------------------------------------------------- problem


@dataclass(frozen=True)
class _Transform:
    """z <-> p for one free parameter (see the module docstring)."""

    name: str
    ref: float
    log: bool
    scale: float

    def to_z(self, p: float) -> float:
        return math.log(p / self.ref) if self.log else (p - self.ref) / self.scale

    def to_p(self, z: float) -> float:
        return self.ref * math.exp(z) if self.log else self.ref + z * self.scale

    def dp_dz(self, p: float) -> float:
        return p if self.log else self.scale


def _default_bounds(name: str, p: float) -> tuple[float, float]:
    spec = SPECS[name]
    if spec.lower >= 0 and p > 0:
        return p / 10.0, p * 10.0
    half = max(abs(p), 1.0)
    return max(p - half, spec.lower), p + half


class FitProblem:
    """What to fit: trials (list of measured ``Trial``) with weights, a base ParameterSet, the free parameters
    with bounds (parameter units), frozen values, the objective ("sse" or "nrmse") and simulation options.

    free: names, or a mapping name -> (lower, upper) or None (default bounds, see module docstring).
    start: optional start values of free parameters (default: the base set after ``frozen``).
    """

    def __init__(self, trials: Sequence[Trial], base: ParameterSet,
                 free: Sequence[str] | Mapping[str, tuple[float, float] | None], *,
                 weights: Sequence[float] | None = None, frozen: Mapping[str, float] | None = None,
                 start: Mapping[str, float] | None = None, objective: str = "sse",
                 options: SimulationOptions = SimulationOptions()) -> None:
        if not isinstance(base, ParameterSet):
            raise InputError(f"base must be a ParameterSet (see load_parameters), got {type(base).__name__}")
        self.trials = list(trials)
        if not self.trials:
            raise InputError("FitProblem needs at least one trial")
        for t in self.trials:
            if not isinstance(t, Trial):
                raise InputError(f"trials must be measured Trial objects, got {type(t).__name__}")
            _check_trial_units(t)
        self.weights = np.ones(len(self.trials)) if weights is None else np.asarray(weights, dtype=float)
        if self.weights.shape != (len(self.trials),) or not np.all(np.isfinite(self.weights)) \
                or np.any(self.weights < 0):
            raise InputError(f"weights must be {len(self.trials)} finite values >= 0, got {weights!r}")
        if objective not in OBJECTIVES:
            raise InputError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
        self.objective = objective
        self.options = options
        bounds_in = dict(free) if isinstance(free, Mapping) else {n: None for n in free}
        if not bounds_in:
            raise InputError("no free parameters: give at least one name to fit")
        unknown = [n for n in bounds_in if n not in SPECS]
        if unknown:
            raise InputError(f"unknown free parameter(s) {unknown}; known: {', '.join(SPECS)}")
        frozen = dict(frozen or {})
        both = sorted(set(frozen) & set(bounds_in))
        if both:
            raise InputError(f"parameter(s) {both} are both free and frozen")
        self.frozen = frozen
        self.base = base.with_values(**frozen) if frozen else base
        start = dict(start or {})
        extra = sorted(set(start) - set(bounds_in))
        if extra:
            raise InputError(f"start values given for parameter(s) {extra} that are not free")
        self.free = list(bounds_in)
        self.start = {n: float(start.get(n, self.base[n])) for n in self.free}
        self.base.with_values(**self.start)  # admissible?
        self.bounds: dict[str, tuple[float, float]] = {}
        self._tf: list[_Transform] = []
        for n in self.free:
            lo, hi = bounds_in[n] if bounds_in[n] is not None else _default_bounds(n, self.start[n])
            lo, hi = float(lo), float(hi)
            spec = SPECS[n]
            if not (lo < hi) or not (np.isfinite(lo) and np.isfinite(hi)):
                raise InputError(f"free parameter {n!r}: bounds ({lo}, {hi}) {spec.unit} must be finite with "
                                 "lower < upper")
            if lo < spec.lower or (lo == spec.lower and not spec.lower_inclusive):
                raise InputError(f"free parameter {n!r}: lower bound {lo} {spec.unit} is outside the admissible "
                                 f"range ({'>=' if spec.lower_inclusive else '>'} {spec.lower})")
            p0 = self.start[n]
            if not lo <= p0 <= hi:
                raise InputError(f"free parameter {n!r}: start {p0} {spec.unit} is outside its bounds "
                                 f"[{lo}, {hi}]")
            self.bounds[n] = (lo, hi)
            log = spec.lower >= 0 and lo > 0 and p0 > 0
            self._tf.append(_Transform(n, p0, log, 1.0 if log else max(abs(p0), (hi - lo) / 10.0)))
        needs_stim = [n for n in self.free if SPECS[n].module in (0, 1, 2)]
        for t in self.trials:
            if np.size(t.stimulus_times_s) == 0:
                what = (f"Module 1/2 parameter(s) {needs_stim}" if needs_stim else f"parameter(s) {self.free}")
                raise InputError(f"trial '{t.trial_id}' has no stimulus: without one the model stays at rest and "
                                 f"the trial carries no information on {what}; drop it from the fit")
            if t.n_samples < 2:
                raise InputError(f"trial '{t.trial_id}' has fewer than 2 samples")
        self._scale = []
        for t, w in zip(self.trials, self.weights):
            if objective == "sse":
                self._scale.append(math.sqrt(w))
            else:
                span = float(np.max(t.force) - np.min(t.force))
                if span <= 0:
                    raise InputError(f"trial '{t.trial_id}': constant force, NRMSE objective undefined")
                self._scale.append(math.sqrt(w) * 100.0 / (span * math.sqrt(t.n_samples)))

    # -- search space -------------------------------------------------------------------------------------
    @property
    def n_residuals(self) -> int:
        return int(sum(t.n_samples for t in self.trials))

    def z_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds of the search vector z."""
        lo = np.array([tf.to_z(self.bounds[tf.name][0]) for tf in self._tf])
        hi = np.array([tf.to_z(self.bounds[tf.name][1]) for tf in self._tf])
        return lo, hi

    def to_z(self, values: Mapping[str, float]) -> np.ndarray:
        return np.array([tf.to_z(float(values[tf.name])) for tf in self._tf])

    def to_values(self, z: Sequence[float]) -> dict[str, float]:
        return {tf.name: tf.to_p(float(zi)) for tf, zi in zip(self._tf, z)}

    def dp_dz(self, z: Sequence[float]) -> np.ndarray:
        vals = self.to_values(z)
        return np.array([tf.dp_dz(vals[tf.name]) for tf in self._tf])

    def parameters(self, z: Sequence[float]) -> ParameterSet:
        """The complete ParameterSet at search vector z."""
        return self.base.with_values(**self.to_values(z))

    def reference(self) -> dict[str, dict[str, Any]]:
        return {tf.name: {"ref": tf.ref, "log": tf.log, "scale": tf.scale} for tf in self._tf}

    # -- evaluation ---------------------------------------------------------------------------------------
    def simulate_trials(self, z: Sequence[float]) -> list[np.ndarray]:
        """Simulated force (N) of every trial at search vector z."""
        params = self.parameters(z)
        o = self.options
        return [trial_simulation(params, t, o.dt_ms, record_dt_ms=o.record_dt_ms, settle_ms=o.settle_ms,
                                 length_compensation=o.length_compensation,
                                 movement_compensation=o.movement_compensation) for t in self.trials]

    def residuals_from(self, sims: Sequence[np.ndarray]) -> np.ndarray:
        return np.concatenate([s * (f - t.force) for s, f, t in zip(self._scale, sims, self.trials)])

    def residuals(self, z: Sequence[float]) -> np.ndarray:
        """The residual vector at z (see the module docstring for its units)."""
        return self.residuals_from(self.simulate_trials(z))


def _evaluate(problem: FitProblem, z: np.ndarray) -> np.ndarray:
    """One candidate (module-level so worker processes can run it); non-finite runs give NaN residuals."""
    try:
        return problem.residuals(z)
    except NumericalError:
        return np.full(problem.n_residuals, np.nan)


# ---------------------------------------------------------------------------------------------- result


@dataclass
class FitResult:
    """Outcome of :func:`fit`.  Estimates, SE and intervals in the units of ``SPECS``; cost as in the module
    docstring; ``nrmse_percent`` per trial id; ``identifiable`` False for the flagged parameters."""

    parameters: ParameterSet
    free: list[str]
    estimates: dict[str, float]
    std_errors: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    identifiable: dict[str, bool]
    flags: dict[str, str]
    singular_values: np.ndarray
    correlation: np.ndarray
    cost: float
    nrmse_percent: dict[str, float]
    simulated: dict[str, np.ndarray]
    n_simulations: int
    n_iterations: int
    wall_time_s: float
    method: str
    message: str
    history: list[dict[str, Any]] = field(default_factory=list)

    @property
    def unidentifiable(self) -> list[str]:
        """Names of the parameters the data cannot identify."""
        return [n for n in self.free if not self.identifiable[n]]

    def summary(self) -> str:
        """A short table: estimate, SE, 95 % interval, flag."""
        lines = [f"{self.method}: cost {self.cost:.6g}, {self.n_iterations} iterations, {self.n_simulations} "
                 f"simulations, {self.wall_time_s:.1f} s ({self.message})"]
        for n in self.free:
            lo, hi = self.ci95[n]
            flag = f"  NOT IDENTIFIABLE: {self.flags[n]}" if n in self.flags else ""
            lines.append(f"  {n:7s} = {self.estimates[n]:.6g} {SPECS[n].unit}  SE {self.std_errors[n]:.3g}  "
                         f"95% [{lo:.6g}, {hi:.6g}]{flag}")
        lines += [f"  NRMSE {k}: {v:.3f} %" for k, v in self.nrmse_percent.items()]
        return "\n".join(lines)


def _uncertainty(problem: FitProblem, z: np.ndarray, jac_z: np.ndarray, resid: np.ndarray, ident_rcond: float,
                 max_rel_se: float) -> tuple[dict, dict, dict, dict, np.ndarray, np.ndarray]:
    from scipy.stats import t as student_t

    names = problem.free
    n, k = jac_z.shape
    dof = max(n - k, 1)
    s2 = float(resid @ resid) / dof
    values = problem.to_values(z)
    dpdz = problem.dp_dz(z)
    norms = np.linalg.norm(jac_z, axis=0)
    flags: dict[str, str] = {}
    for i, nm in enumerate(names):
        if not norms[i] > 0:
            flags[nm] = "no effect on the simulated force (zero sensitivity)"
    safe = np.where(norms > 0, norms, 1.0)
    jn = jac_z / safe
    _, svals, vt = np.linalg.svd(jn, full_matrices=False)
    smax = svals[0] if svals.size and svals[0] > 0 else 1.0
    for j, s in enumerate(svals):
        if s < ident_rcond * smax:
            involved = np.flatnonzero(np.abs(vt[j]) > 0.2)
            for i in involved:
                others = ", ".join(names[m] for m in involved if m != i) or "nothing else"
                flags.setdefault(names[i], f"lies in a near-singular direction (singular value {s / smax:.2g} of "
                                           f"the largest) with {others}")
    # covariance in z (infinite along exactly singular directions), then to parameter units
    inv_s2 = np.array([1.0 / s ** 2 if s > 1e-12 * smax else np.inf for s in svals])
    with np.errstate(invalid="ignore"):
        cov_n = (vt.T * inv_s2) @ vt if np.all(np.isfinite(inv_s2)) else _cov_inf(vt, inv_s2)
    cov_z = s2 * cov_n / np.outer(safe, safe)
    cov_p = cov_z * np.outer(dpdz, dpdz)
    se = np.sqrt(np.abs(np.diag(cov_p)))
    se = np.where(norms > 0, se, np.inf)
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_p / np.outer(se, se)
    tq = float(student_t.ppf(0.975, dof))
    std_errors, ci = {}, {}
    for i, nm in enumerate(names):
        std_errors[nm] = float(se[i])
        ci[nm] = (values[nm] - tq * se[i], values[nm] + tq * se[i])
        rel = se[i] / abs(values[nm]) if values[nm] != 0 else np.inf
        if rel > max_rel_se:
            flags.setdefault(nm, f"relative standard error {rel:.3g} exceeds {max_rel_se}")
    ident = {nm: nm not in flags for nm in names}
    return std_errors, ci, ident, flags, svals, corr


def _cov_inf(vt: np.ndarray, inv_s2: np.ndarray) -> np.ndarray:
    """(J^T J)^-1 in the SVD basis when some singular values are zero: infinite variance along those."""
    finite = np.where(np.isfinite(inv_s2), inv_s2, 0.0)
    cov = (vt.T * finite) @ vt
    null = vt[~np.isfinite(inv_s2)]
    touched = np.any(np.abs(null) > 1e-8, axis=0)
    cov[np.ix_(touched, touched)] = np.inf
    return cov


# ------------------------------------------------------------------------------------------ checkpoint


def _write_json_atomic(path: Path, doc: dict) -> None:
    tmp = path.with_name(path.name + f".tmp{os.getpid()}")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    os.replace(tmp, path)


def read_checkpoint(path: str | os.PathLike, problem: FitProblem) -> dict[str, Any]:
    """Read a fit checkpoint and check it belongs to ``problem`` (same free parameters)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"checkpoint {p}: file not found (cannot resume)")
    try:
        doc = json.loads(p.read_text())
    except json.JSONDecodeError as exc:
        raise InputError(f"checkpoint {p}: not valid JSON ({exc})") from None
    if not isinstance(doc, dict) or doc.get("schema") != CHECKPOINT_SCHEMA:
        raise InputError(f"checkpoint {p}: schema is not {CHECKPOINT_SCHEMA!r}")
    if doc.get("free") != problem.free:
        raise InputError(f"checkpoint {p}: fits {doc.get('free')}, the problem fits {problem.free}")
    if doc.get("objective") != problem.objective:
        raise InputError(f"checkpoint {p}: objective {doc.get('objective')!r}, the problem uses "
                         f"{problem.objective!r}")
    return doc


class _Tracker:
    """Counts simulations and iterations, keeps the best point, prints progress and writes the checkpoint."""

    def __init__(self, problem: FitProblem, method: str, checkpoint: Path | None, progress: bool,
                 previous: dict | None) -> None:
        self.problem, self.method, self.checkpoint, self.progress = problem, method, checkpoint, progress
        self.t_start = time.perf_counter()
        self.history: list[dict] = list(previous["history"]) if previous else []
        self.n_sim = int(previous["n_simulations"]) if previous else 0
        self.n_iter = int(previous["n_iterations"]) if previous else 0
        self.best_z: np.ndarray | None = None
        self.best_cost = math.inf

    def evaluated(self, zs: Sequence[np.ndarray], rs: Sequence[np.ndarray]) -> None:
        self.n_sim += len(zs) * len(self.problem.trials)
        for z, r in zip(zs, rs):
            c = float(r @ r)
            if np.isfinite(c) and c < self.best_cost:
                self.best_cost, self.best_z = c, np.array(z, dtype=float)

    def iteration(self, z: np.ndarray, cost: float) -> None:
        self.n_iter += 1
        values = self.problem.to_values(z)
        entry = {"iteration": self.n_iter, "cost": cost, "parameters": values, "n_simulations": self.n_sim,
                 "elapsed_s": round(time.perf_counter() - self.t_start, 3)}
        self.history.append(entry)
        if self.progress:
            shown = " ".join(f"{k}={v:.6g}" for k, v in values.items())
            print(f"[fit {self.method}] iter {self.n_iter:3d}  cost {cost:.6g}  {shown}  ({self.n_sim} sims, "
                  f"{entry['elapsed_s']:.1f} s)", file=sys.stderr, flush=True)
        self.write()

    def write(self, final: bool = False) -> None:
        if self.checkpoint is None or self.best_z is None:
            return
        pr = self.problem
        doc = {"schema": CHECKPOINT_SCHEMA, "method": self.method, "objective": pr.objective, "free": pr.free,
               "bounds": pr.bounds, "frozen": pr.frozen, "search_space": pr.reference(),
               "best": pr.to_values(self.best_z), "best_cost": self.best_cost,
               "n_simulations": self.n_sim, "n_iterations": self.n_iter, "finished": final,
               "parameters": pr.parameters(self.best_z).to_json(), "history": self.history}
        _write_json_atomic(self.checkpoint, doc)


# ---------------------------------------------------------------------------------------------- fit


def _serial_map(fn: Callable, items: Iterable) -> list:
    return [fn(x) for x in items]


def fit(problem: FitProblem, method: str = "least_squares", map_fn: MapFn | None = None, workers: int = 1,
        checkpoint: str | os.PathLike | None = None, progress: bool = True, *, resume: bool = False,
        fd: str = "central", fd_step: float = 1e-3, max_iterations: int = 100, tolerance: float = 1e-8,
        ident_rcond: float = 1e-3, max_rel_se: float = 0.5, mp_context: str = "spawn") -> FitResult:
    """Fit ``problem``'s free parameters; see the module docstring for the search space and statistics.

    method: "least_squares" (scipy trust-region reflective with a finite-difference Jacobian in z) or
    "praxis" (NEURON's h.fit_praxis on the cost, the seed's baseline; serial; bounds by clipping plus a
    penalty).  map_fn(fn, iterable) evaluates candidates (any ``map``: serial by default, a process pool with
    ``workers`` > 1).  checkpoint: JSON path written after every iteration; resume=True starts from it.
    tolerance: scipy's ftol/xtol/gtol (least_squares) or praxis' tolerance in z.  max_iterations: iterations
    (Jacobians; praxis: rounds of 2k+2 evaluations) of this call; the best point so far is returned after it.
    """
    if not (isinstance(max_iterations, int) and max_iterations >= 1):
        raise InputError(f"max_iterations must be an integer >= 1, got {max_iterations!r}")
    if method not in METHODS:
        raise InputError(f"method must be one of {METHODS}, got {method!r}")
    if fd not in ("central", "forward"):
        raise InputError(f"fd must be 'central' or 'forward', got {fd!r}")
    if not (isinstance(workers, int) and workers >= 1):
        raise InputError(f"workers must be an integer >= 1, got {workers!r}")
    if map_fn is not None and workers > 1:
        raise InputError("give either map_fn or workers > 1, not both")
    ckpt = Path(checkpoint) if checkpoint is not None else None
    if resume and ckpt is None:
        raise InputError("resume=True needs the checkpoint path")
    previous = read_checkpoint(ckpt, problem) if resume else None
    z0 = problem.to_z(previous["best"]) if previous else np.zeros(len(problem.free))
    lo, hi = problem.z_bounds()
    z0 = np.clip(z0, lo, hi)
    tracker = _Tracker(problem, method, ckpt, progress, previous)
    pool = None
    if map_fn is None:
        if workers > 1:
            pool = concurrent.futures.ProcessPoolExecutor(workers,
                                                          mp_context=multiprocessing.get_context(mp_context))
            map_fn = pool.map
        else:
            map_fn = _serial_map
    try:
        evaluate = partial(_evaluate, problem)

        def run_all(zs: list[np.ndarray]) -> list[np.ndarray]:
            rs = [np.asarray(r, dtype=float) for r in map_fn(evaluate, zs)]
            tracker.evaluated(zs, rs)
            return rs

        if method == "least_squares":
            z, message, jr = _least_squares(problem, z0, lo, hi, run_all, tracker, fd, fd_step,
                                            max_iterations, tolerance)
        else:
            z, message = _praxis(problem, z0, lo, hi, run_all, tracker, max_iterations, tolerance)
            jr = None
        jac = jr[0] if jr is not None else _jacobian(z, lo, hi, run_all, fd, fd_step, None)[0]
    finally:
        if pool is not None:
            pool.shutdown()
    sims = problem.simulate_trials(z)
    tracker.n_sim += len(problem.trials)
    r = problem.residuals_from(sims)
    tracker.best_z, tracker.best_cost = z, float(r @ r)
    tracker.write(final=True)
    se, ci, ident, flags, sv, corr = _uncertainty(problem, z, jac, r, ident_rcond, max_rel_se)
    return FitResult(
        parameters=problem.parameters(z), free=list(problem.free), estimates=problem.to_values(z),
        std_errors=se, ci95=ci, identifiable=ident, flags=flags, singular_values=sv, correlation=corr,
        cost=float(r @ r),
        nrmse_percent={t.trial_id: nrmse_percent(t.force, s) for t, s in zip(problem.trials, sims)},
        simulated={t.trial_id: s for t, s in zip(problem.trials, sims)}, n_simulations=tracker.n_sim,
        n_iterations=tracker.n_iter, wall_time_s=time.perf_counter() - tracker.t_start, method=method,
        message=message, history=tracker.history)


def _jacobian(z: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: Callable, fd: str, h: float,
              r0: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Finite-difference Jacobian of the residuals in z (central, one-sided at a bound); also r(z).

    All candidates go through one run_all call, in the order [z (if r0 is None), then per parameter +h, -h]."""
    k = z.size
    plan: list[tuple[int, float, float]] = []  # (index, step up, step down) (down = 0: one-sided)
    for i in range(k):
        up = h if z[i] + h <= hi[i] else -h
        if fd == "central" and z[i] - h >= lo[i] and z[i] + h <= hi[i]:
            plan.append((i, h, -h))
        else:
            plan.append((i, up, 0.0))
    zs: list[np.ndarray] = [] if r0 is not None else [z.copy()]
    for i, a, b in plan:
        for step in (a, b) if b != 0.0 else (a,):
            zz = z.copy()
            zz[i] += step
            zs.append(zz)
    rs = run_all(zs)
    if r0 is None:
        r0, rs = rs[0], rs[1:]
    jac = np.empty((r0.size, k))
    pos = 0
    for i, a, b in plan:
        if b != 0.0:
            jac[:, i] = (rs[pos] - rs[pos + 1]) / (a - b)
            pos += 2
        else:
            jac[:, i] = (rs[pos] - r0) / a
            pos += 1
    if not np.all(np.isfinite(jac)):
        raise NumericalError("the Jacobian has non-finite entries: a candidate simulation failed near "
                             "the current parameters")
    return jac, r0


class _IterationLimit(Exception):
    """Raised inside the optimiser's Jacobian callback when the iteration budget of this run is spent."""


def _least_squares(problem: FitProblem, z0: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: Callable,
                   tracker: _Tracker, fd: str, h: float, max_iterations: int,
                   tol: float) -> tuple[np.ndarray, str, tuple[np.ndarray, np.ndarray] | None]:
    """scipy's trust-region reflective least squares in z; returns z, a message and (J, r) at z if known."""
    from scipy.optimize import least_squares

    cache: dict[bytes, np.ndarray] = {}
    last: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
    done = [0]

    def fun(z: np.ndarray) -> np.ndarray:
        key = np.asarray(z, dtype=float).tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = run_all([np.array(z, dtype=float)])[0]
        r = cache[key]
        return r if np.all(np.isfinite(r)) else np.full(r.size, 1e150)

    def jac(z: np.ndarray) -> np.ndarray:
        if done[0] >= max_iterations:
            raise _IterationLimit
        z = np.array(z, dtype=float)
        r0 = fun(z)
        j, _ = _jacobian(z, lo, hi, run_all, fd, h, r0)
        last.clear()
        last[z.tobytes()] = (j, r0)
        done[0] += 1
        tracker.iteration(z, float(r0 @ r0))
        return j

    # trf keeps iterates strictly inside the bounds: a start on a bound is nudged inside
    z_in = np.clip(z0, lo + 1e-10 * (hi - lo), hi - 1e-10 * (hi - lo))
    try:
        sol = least_squares(fun, z_in, jac=jac, bounds=(lo, hi), method="trf", x_scale=1.0, ftol=tol, xtol=tol,
                            gtol=tol, max_nfev=max(10 * max_iterations, 50))
        z, message = np.asarray(sol.x, dtype=float), str(sol.message)
    except _IterationLimit:
        z = tracker.best_z if tracker.best_z is not None else z_in
        message = f"stopped after max_iterations = {max_iterations} iterations (resume to continue)"
    return z, message, last.get(z.tobytes())


def _praxis(problem: FitProblem, z0: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: Callable,
            tracker: _Tracker, max_iterations: int, tol: float) -> tuple[np.ndarray, str]:
    """NEURON's principal-axis method on cost(z); outside the bounds the cost is that of the clipped point plus
    a quadratic penalty.  Reproducible (fixed mcell_ran4 index).  Stops after max_iterations principal-axis
    rounds."""
    from neuron import h

    h.attr_praxis(1)
    h.attr_praxis(tol, 0.5, 0)
    n_eval = [0]
    per_round = max(2 * z0.size + 2, 4)

    def efun(v: Any) -> float:
        z = np.array([v[i] for i in range(int(v.size()))])
        zc = np.clip(z, lo, hi)
        r = run_all([zc])[0]
        c = float(r @ r) if np.all(np.isfinite(r)) else 1e300
        c *= 1.0 + 1e3 * float(np.sum((z - zc) ** 2))
        n_eval[0] += 1
        if n_eval[0] % per_round == 0:
            tracker.iteration(tracker.best_z if tracker.best_z is not None else zc, tracker.best_cost)
            if n_eval[0] // per_round >= max_iterations:
                h.stoprun = 1
        return c

    vec = h.Vector(list(map(float, z0)))
    h.stoprun = 0
    try:
        h.fit_praxis(efun, vec)
    finally:
        h.stoprun = 0
    z = np.clip(np.array([vec[i] for i in range(int(vec.size()))]), lo, hi)
    if tracker.best_z is not None and tracker.best_cost < float(np.sum(run_all([z])[0] ** 2)):
        z = tracker.best_z
    return z, f"praxis finished after {n_eval[0]} evaluations"
