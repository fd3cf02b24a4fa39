"""Evaluation of candidates: the map over candidate parameter vectors, each trial's runs batched.

* **Simulation of a trial**: :func:`neuromuscle.measured.simulation.trial_simulation` (the trial's clock in s
  becomes the simulation clock in ms, ``time_s[0]`` at ``settle_ms``; the force interpolated at the trial's samples).
* **Map.**  All candidates of one Jacobian are evaluated by one call of the map in a fixed order, so serial and
  parallel fits are identical: every candidate is a pure function of its parameter vector (fixed-step
  integration; each simulation builds and tears down its unit).
* **Packed runs** (:func:`simulate_pairs`).  The (parameter set, trial) pairs of one call run together, as units
  of one NEURON run (up to ``BATCH_UNITS``), the runs of one trial and of trials of similar duration alike: a lone
  unit spends most of each step in NEURON's per-mechanism overhead, which the units of a run share.  Each unit is
  the fused unit in its fixed-step form, KimUnitFixed (with its extensions), whose force is bit for bit the three
  mechanisms' and KimUnit's at a lower cost per step (no METHOD euler loop per unit, which only CVODE needs), and
  bit for bit its own run's (``neuromuscle.sim.simulate_protocols``, always the fixed step).
* **Trial pool** (:class:`TrialPool`, ``fit(..., workers=N)`` or ``fit(..., pool=)``).  The work is split into
  packed runs, longest first, small enough that every worker gets several: a single candidate (a trust-region
  step, the final run, the half-step re-run of the intervals) then uses every worker too, and a Jacobian's
  candidates need not be a multiple of the workers.  The trials are sent to each worker once, when the pool
  starts; a task carries parameter sets, their options and trial indices.  The forces are the same simulations as
  in one process, so the fit is identical.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
from contextlib import contextmanager
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Callable, Iterable, Iterator, MutableMapping, Sequence

import numpy as np

from ..errors import InputError, NumericalError
from ..measured import Trial
from ..measured.simulation import trial_clock
from ..model.kim_unit import kim_fused
from ..parameters import ParameterSet
from ..sim import simulate_protocols

if TYPE_CHECKING:
    from .problem import FitProblem

MapFn = Callable[[Callable[[Any], Any], Iterable[Any]], Iterable[Any]]

#: The most units one packed NEURON run holds (:func:`simulate_pairs`): a single unit spends most of its step in
#: NEURON's per-mechanism overhead, which a run's units share; per run of a 12.5 s train (on two cores) 106 ms
#: alone, 47 ms in batches of 8, 41 ms of 16, no better beyond.
BATCH_UNITS = 16
#: A packed run takes trials down to this share of its longest trial's duration; the shorter trials' units run on,
#: unrecorded, to the run's end.
PACK_SHARE = 0.5


@dataclass(frozen=True)
class SimulationOptions:
    """How each trial is simulated: fixed step dt_ms (ms), recording interval record_dt_ms (ms; None = dt_ms),
    settling time settle_ms (ms) before the trial's first sample, the model's eq 18 / eqs 19-20 switches, and the
    catalogue extensions switched on (canonical names; their values come from the parameter set by qualified name,
    e.g. ``fatigue.k``, else their defaults).  differenced: the forces are only differenced against runs at the
    same step (finite-difference Jacobians), so dt_ms may be up to ``sim.MAX_DIFFERENCE_DT_MS``."""

    dt_ms: float = 0.05
    record_dt_ms: float | None = None
    settle_ms: float = 500.0
    length_compensation: bool = True
    movement_compensation: bool = False
    extensions: tuple[str, ...] = ()
    differenced: bool = False


def packs(durations: Sequence[float], max_units: int, share: float | None = None) -> list[list[int]]:
    """Indices of ``durations`` (ms) in packs of at most ``max_units``, longest first: a pack takes the next
    longest while it is at least ``share`` (default ``PACK_SHARE``) of the pack's first (so a run wastes at most
    1 - share of a unit's steps on a shorter trial)."""
    share = PACK_SHARE if share is None else share
    out: list[list[int]] = []
    for i in sorted(range(len(durations)), key=lambda k: (-durations[k], k)):
        if out and len(out[-1]) < max_units and durations[i] >= share * durations[out[-1][0]]:
            out[-1].append(i)
        else:
            out.append([i])
    return out


def _packed(pairs: Sequence[tuple[ParameterSet, Trial, SimulationOptions]], max_units: int) -> list[list[int]]:
    """The pairs (indices) in packs of :func:`packs`, the pairs of one pack alike in their options but for the
    extensions (they share a NEURON run's step and excitation model)."""
    groups: dict[SimulationOptions, list[int]] = {}
    for c, (_, _, o) in enumerate(pairs):
        groups.setdefault(replace(o, extensions=()), []).append(c)
    out = []
    for opts, members in groups.items():
        durations = [opts.settle_ms + 1000.0 * float(pairs[c][1].time_s[-1] - pairs[c][1].time_s[0]) for c in members]
        out += [[members[i] for i in pack] for pack in packs(durations, max_units)]
    return sorted(out, key=lambda pack: -float(pairs[pack[0]][1].time_s[-1] - pairs[pack[0]][1].time_s[0]))


def simulate_pairs(pairs: Sequence[tuple[ParameterSet, Trial, SimulationOptions]],
                   max_units: int | None = None) -> list[np.ndarray | None]:
    """The force (N) of each (parameter set, trial, options) pair at the trial's samples (None where the run failed
    numerically): :func:`trial_simulation`'s numbers bit for bit, the pairs packed into NEURON runs of at most
    ``max_units`` (default ``BATCH_UNITS``) units (:func:`packs`; each trial's clock and length made once)."""
    out: list[np.ndarray | None] = [None] * len(pairs)
    clocks: dict[tuple[int, float], tuple] = {}
    for pack in _packed(pairs, max_units or BATCH_UNITS):
        opts = pairs[pack[0]][2]
        index: dict[int, int] = {}
        protocols = []
        for c in pack:
            trial = pairs[c][1]
            key = (id(trial), opts.settle_ms)
            if key not in clocks:
                clocks[key] = trial_clock(trial, opts.settle_ms)
            if id(trial) not in index:
                index[id(trial)] = len(protocols)
                _, duration_ms, spikes_ms, length = clocks[key]
                protocols.append((spikes_ms, length, duration_ms))
        results = simulate_protocols(
            [(pairs[c][0], {name: {} for name in pairs[c][2].extensions} or None, index[id(pairs[c][1])])
             for c in pack], protocols,
            excitation=kim_fused(opts.length_compensation, opts.movement_compensation, fixed_step=True),
            record=("muscle.F",),
            dt_ms=opts.dt_ms, record_dt_ms=opts.dt_ms if opts.record_dt_ms is None else opts.record_dt_ms,
            differenced=opts.differenced)
        for c, res in zip(pack, results):
            t_ms = clocks[(id(pairs[c][1]), opts.settle_ms)][0]
            out[c] = None if res is None else np.interp(t_ms, res.t_ms, res.force_N)
    return out


def trial_simulations(params: Sequence[ParameterSet], trial: Trial,
                      options: Sequence[SimulationOptions]) -> list[np.ndarray | None]:
    """The force (N) of ``trial`` under each parameter set with its options (None where the run failed
    numerically): :func:`trial_simulation`'s numbers bit for bit, the runs packed (:func:`simulate_pairs`)."""
    if len(params) != len(options):
        raise ValueError(f"{len(options)} options for {len(params)} parameter sets")
    return simulate_pairs([(p, trial, o) for p, o in zip(params, options)])


def evaluate_candidate(problem: FitProblem, z: np.ndarray) -> np.ndarray:
    """The residuals of ``problem`` at search vector z (module-level so that worker processes can run it);
    a run that fails numerically gives NaN residuals."""
    try:
        return problem.residuals(z)
    except NumericalError:
        return np.full(problem.n_residuals, np.nan)


def simulate_batched(params: Sequence[ParameterSet], trials: Sequence[Trial],
                     options: Sequence[SimulationOptions]) -> list[list[np.ndarray] | None]:
    """In this process, what :meth:`TrialPool.simulate` gives: the force (N) of every one of ``trials`` under
    each parameter set with its options (None for a set whose run of some trial failed numerically), all runs
    packed (:func:`simulate_pairs`)."""
    if len(params) != len(options):
        raise ValueError(f"{len(options)} options for {len(params)} parameter sets")
    flat = simulate_pairs([(p, t, o) for p, o in zip(params, options) for t in trials])
    out = [flat[c * len(trials):(c + 1) * len(trials)] for c in range(len(params))]
    return [None if any(f is None for f in sims) else sims for sims in out]  # type: ignore[misc]


def batched_residuals(problem: FitProblem, zs: Sequence[np.ndarray]) -> list[np.ndarray]:
    """``problem``'s residual vectors at ``zs`` in this process, each trial's runs batched (NaN for a candidate
    whose run failed numerically): :func:`evaluate_candidate` on each z, at a fraction of the cost."""
    sims = simulate_batched([problem.parameters(z) for z in zs], problem.trials, [problem.options] * len(zs))
    return [np.full(problem.n_residuals, np.nan) if s is None else problem.residuals_from(s) for s in sims]


_WORKER_TRIALS: list[Trial] = []


def _install_trials(trials: list[Trial]) -> None:
    """Pool initializer: the trials every task of this worker simulates."""
    global _WORKER_TRIALS
    _WORKER_TRIALS = trials


def _simulate_task(task: list[tuple[ParameterSet, int, SimulationOptions]]) -> list[np.ndarray | None]:
    """One packed run: each (parameter set, trial index into the worker's trials, options)'s force (N), None for a
    run that failed numerically (:func:`simulate_pairs`)."""
    return simulate_pairs([(p, _WORKER_TRIALS[k], o) for p, k, o in task])


class TrialPool:
    """``workers`` processes that simulate (parameter set, trial) pairs of a fixed list of trials (module
    docstring: the trials are sent to each worker once, when the pool starts; the longest runs go first).  A
    context manager: the processes stop on exit.  One pool can serve several fits (``fit(..., pool=)``) and
    simulations of the same trials."""

    def __init__(self, trials: Sequence[Trial], workers: int, mp_context: str = "spawn") -> None:
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise InputError(f"workers must be an integer >= 1, got {workers!r}")
        self.trials = list(trials)
        self._index = {id(t): k for k, t in enumerate(self.trials)}
        self.workers = workers
        self._pool = concurrent.futures.ProcessPoolExecutor(
            workers, mp_context=multiprocessing.get_context(mp_context), initializer=_install_trials,
            initargs=(self.trials,))

    def __enter__(self) -> TrialPool:
        return self

    def __exit__(self, *exc: object) -> None:
        self._pool.shutdown(cancel_futures=True)

    def indices(self, trials: Sequence[Trial]) -> list[int]:
        """Where each of ``trials`` (the same objects) is in the pool; InputError for a trial it does not hold."""
        missing = [t.trial_id for t in trials if id(t) not in self._index]
        if missing:
            raise InputError(f"trial(s) {missing} are not in this pool (give the pool the same Trial objects)")
        return [self._index[id(t)] for t in trials]

    def simulate(self, params: Sequence[ParameterSet], trials: Sequence[Trial],
                 options: SimulationOptions | Sequence[SimulationOptions]) -> list[list[np.ndarray] | None]:
        """The force (N) of every one of ``trials`` (in their order) under each parameter set of ``params``
        (None for a set whose run of some trial failed numerically).  options: one for every set, or one per set
        (e.g. each with its own extensions: one call keeps both workers busy to the end, longest trials first)."""
        idx = self.indices(trials)
        per_set = [options] * len(params) if isinstance(options, SimulationOptions) else list(options)
        if len(per_set) != len(params):
            raise ValueError(f"{len(per_set)} options for {len(params)} parameter sets")
        pairs = [(params[c], trials[j], per_set[c]) for c in range(len(params)) for j in range(len(idx))]
        # small enough packs that every worker gets several (a single parameter set's trials too), longest first
        size = max(1, min(BATCH_UNITS, -(-len(pairs) // (2 * self.workers))))
        tasks = _packed(pairs, size)
        out: list[list[Any]] = [[None] * len(idx) for _ in params]
        for pack, forces in zip(tasks, self._pool.map(
                _simulate_task, [[(pairs[i][0], idx[i % len(idx)], pairs[i][2]) for i in pack] for pack in tasks])):
            for i, f in zip(pack, forces):
                out[i // len(idx)][i % len(idx)] = f
        return [None if any(f is None for f in sims) else sims for sims in out]

    def residuals(self, problem: FitProblem, zs: Sequence[np.ndarray],
                  keep: MutableMapping[bytes, list[np.ndarray]] | None = None) -> list[np.ndarray]:
        """``problem``'s residual vectors at ``zs`` (NaN for a candidate whose run failed numerically).
        keep: where each candidate's forces (N) are stored under ``z.tobytes()`` (z as float64)."""
        sims = self.simulate([problem.parameters(z) for z in zs], problem.trials, problem.options)
        if keep is not None:
            keep.update((np.asarray(z, dtype=float).tobytes(), s) for z, s in zip(zs, sims) if s is not None)
        return [np.full(problem.n_residuals, np.nan) if s is None else problem.residuals_from(s) for s in sims]


def serial_map(fn: Callable, items: Iterable) -> list:
    """``map`` into a list, in this process."""
    return [fn(x) for x in items]


@contextmanager
def candidate_map(map_fn: MapFn | None, workers: int, mp_context: str = "spawn") -> Iterator[MapFn]:
    """The map that evaluates candidates: ``map_fn`` when given, else a pool of ``workers`` processes
    (started by ``mp_context``) when workers > 1, else :func:`serial_map`.  The pool is shut down on exit."""
    if map_fn is not None:
        yield map_fn
    elif workers == 1:
        yield serial_map
    else:
        with concurrent.futures.ProcessPoolExecutor(
                workers, mp_context=multiprocessing.get_context(mp_context)) as pool:
            yield pool.map
