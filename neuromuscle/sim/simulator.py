"""The Simulator: NEURON's global integrator settings for one run, set and put back (BluePyOpt's simulators).

NEURON is a process-wide singleton.  A Simulator owns every global setting a run touches -- dt and steps_per_ms,
secondorder, CVODE on/off, atol, rtol, the atolscale of every registered mechanism state, the number of threads,
and ParallelContext's spike-exchange interval (maxstep) -- sets them for the run and restores the previous
values afterwards, also when the run fails.  Fixed step and CVODE go through the same ``run``: the fixed step by
``ParallelContext.psolve`` (the stepping loop stays in C), CVODE by stdrun's ``continuerun`` on one rank and by
``psolve`` in ``maxstep_ms`` chunks on several MPI ranks (spikes must cross ranks) and with ``local_dt`` (so that
1 and N ranks stop every cell's integrator at the same times).  ``local_dt`` turns on NEURON's
local variable time step (one CVODE integrator per cell: per connected tree of sections).

    sim = Simulator(method="cvode", atol=1e-3)
    sim.run(700.0, units=[unit])         # after building units and their recordings

Two engines integrate the fixed step: NEURON itself (``engine="neuron"``) or CoreNEURON (``engine="coreneuron"``),
NEURON's compute engine for large networks, which runs the same model from NEURON's memory (``psolve`` hands it
over and takes the states, recordings and spikes back) with the mechanisms compiled by NMODL's code generator
(``mechanisms.coreneuron_library``).  CoreNEURON has no variable step, no local step and no interval recording:
variables are recorded every step and sampled afterwards (:class:`neuromuscle.sim.recordings.Recorder`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from ..errors import InputError
from ..validate import positive_number

#: Largest fixed step (ms) accepted.  The linearly implicit scheme stays stable beyond it, but the release
#: kernel (tau1 = 3 ms) and spike timing are resolved only below it: larger steps are refused, not tolerated.
MAX_DT_MS = 0.2
#: Largest fixed step (ms) of a run whose forces are only differenced against another run at the same step (a
#: finite-difference Jacobian's columns): the step's error is nearly the same in both and cancels in the
#: difference, so such a run may take a coarser step than a result (``Simulator.differenced``).
MAX_DIFFERENCE_DT_MS = 0.4

#: CVODE's default wall-time budget (s) of one run: this much plus DEFAULT_BUDGET_S_PER_S per simulated second.
#: A CT09 unit takes about 0.05 s per simulated second under CVODE; the budget is three orders of magnitude more.
DEFAULT_BUDGET_S = 60.0
DEFAULT_BUDGET_S_PER_S = 60.0
#: CVODE's default step budget of one run (a CT09 unit takes a few thousand steps per simulated second).
DEFAULT_MAX_STEPS = 10_000_000

#: The CVODE stepping loop (stdrun's continuerun without its extras, plus the budgets), in hoc: an event at tstop
#: and one fadvance per CVODE step, as continuerun does, so the results are the same; startsw() is hoc's wall
#: clock (s).
#: Returns 0 when tstop ($1) is reached, 1 when the wall budget ($2, s) is spent, 2 after $3 steps.
_CVODE_LOOP = """
func neuromuscle_cvode_run() { local wall0, n
    wall0 = startsw()
    n = 0
    cvode.event($1)
    while (t < $1) {
        fadvance()
        n = n + 1
        if (startsw() - wall0 > $2) { return 1 }
        if (n >= $3) { return 2 }
    }
    return 0
}
"""

#: The engines that can integrate a run (see the module docstring).
ENGINES = ("neuron", "coreneuron")

#: NEURON has no getter for ParallelContext.set_maxstep: after a run the interval is put back to this value,
#: larger than any run, which is how a serial psolve behaves before anyone sets it.
MAXSTEP_AFTER_RUN_MS = 1e9


def _registered_states() -> list[tuple[str, float]]:
    """(``"Suffix.state"``, atolscale) for every state of every registered component."""
    from ..model import extensions, hatze, kim

    comps = (*kim.COMPONENTS, *hatze.COMPONENTS, *extensions.mechanism_extensions())
    return [(f"{c.suffix}.{s.name}", s.atolscale) for c in comps for s in c.states]


def _refuse_fixed_step_only() -> None:
    """InputError when the model holds a mechanism that only the fixed step advances (KimUnitFixed, mn_soma_fixed,
    mn_pic_fixed): under CVODE its states would stand still."""
    from neuron import h

    from ..model.mechanisms import FIXED_STEP_ONLY_CHANNELS, fixed_step_only_mechanisms

    for name in fixed_step_only_mechanisms():
        n = int(h.List(name).count())
        if n:
            raise InputError(f"{n} {name} point process(es) advance under the fixed step only: run them with "
                             "method='fixed', or build the muscle with KimUnit (kim_fused() without fixed_step, a "
                             "pool's muscle_model='fused') for CVODE")
    for name in FIXED_STEP_ONLY_CHANNELS:
        secs = [sec.name() for sec in h.allsec() if sec.has_membrane(name)]
        if secs:
            raise InputError(f"{name} in {len(secs)} section(s) ({secs[0]}, ...) advances under the fixed step "
                             "only: run with method='fixed', or build the cells with channels='fused' for CVODE")


@dataclass(frozen=True)
class Simulator:
    """How to integrate: ``method`` "fixed" (step ``dt_ms``, ms) or "cvode" (variable step, ``atol`` in each
    state's atolscale units, ``rtol``); ``nthread`` NEURON threads; ``maxstep_ms`` the psolve interval (ms; with
    MPI the spike-exchange interval, capped by NEURON at the smallest NetCon delay); ``v_init_mV`` the membrane
    potential every section starts from (mV; None leaves each segment's v as it is, enough for a muscle alone).

    rtol is 1e-7, not 1e-6: Module 3's state (the CE length change dxce, mm) grows with the length excursion, and
    rtol |dxce| at 1e-6 let a weak unit's force err by up to 1.3 % of its peak where the series element takes up
    slack under random length (two draws of the accuracy sweep, ``neuromuscle bench sweep``); 1e-7 costs 1.2-1.7x
    the CVODE time under movement.

    CVODE cannot hang: each run has a wall-time budget ``max_wall_s`` (s) and a step budget ``max_steps``, checked
    after every CVODE step; a run that spends either stops with a NumericalError naming ``label`` and the time
    reached.  The default wall budget (-1) is ``DEFAULT_BUDGET_S`` plus ``DEFAULT_BUDGET_S_PER_S`` per simulated
    second; None means none.  ``cvode_minstep_ms`` is NEURON's CVode.minstep (0: CVODE's own limit); a failing
    CVODE step is reported the same way.  ``local_dt`` (CVODE only): one integrator per cell (NEURON's lvardt).
    On several MPI ranks, and with local_dt, CVODE runs by psolve in chunks of ``maxstep_ms``; the wall budget is
    checked between chunks and the step budget does not apply.  ``engine``: "neuron" or "coreneuron" (fixed step
    only; see the module docstring); ``cell_permute`` (CoreNEURON only): 1 interleaves the compartments of its
    cells so that neighbours in memory are neighbours in the cable (bit-identical to 0), 0 keeps NEURON's order;
    ``condition_order``: NEURON's CVode.condition_order, 1 (a NetCon's threshold crossing at the end of the step
    that detects it) or 2 (interpolated within the step: under CVODE only; NEURON's and CoreNEURON's fixed step
    ignore it).  ``secondorder``: NEURON's h.secondorder under the fixed step, 0 (backward Euler, first order in
    dt) or 2 (Crank-Nicolson for the membrane, second order; 1 is its variant without the ionic-current
    correction).  The muscle's mechanisms give the same numbers under each (they do not depend on v), a
    motoneuron's discharges converge faster with 2 (docs/validation/speed.md).  ``differenced``: the run's forces
    are only differenced against a run at the same step (a finite-difference Jacobian), so its fixed step may be
    up to ``MAX_DIFFERENCE_DT_MS`` instead of ``MAX_DT_MS``.  The run uses these values whatever the caller set in
    NEURON, and restores the caller's after it."""

    method: str = "fixed"
    dt_ms: float = 0.025
    atol: float = 1e-3
    rtol: float = 1e-7
    nthread: int = 1
    maxstep_ms: float = 10.0
    v_init_mV: float | None = None
    max_wall_s: float | None = -1.0
    max_steps: int = DEFAULT_MAX_STEPS
    cvode_minstep_ms: float = 0.0
    label: str = "run"
    local_dt: bool = False
    engine: str = "neuron"
    cell_permute: int = 1
    condition_order: int = 1
    secondorder: int = 0
    differenced: bool = False

    def __post_init__(self) -> None:
        if self.method not in ("fixed", "cvode"):
            raise InputError(f"method must be 'fixed' or 'cvode', got {self.method!r}")
        if self.engine not in ENGINES:
            raise InputError(f"engine must be one of {', '.join(ENGINES)}, got {self.engine!r}")
        if self.engine == "coreneuron" and self.method != "fixed":
            raise InputError("engine='coreneuron' integrates the fixed step only (CoreNEURON has no CVODE): give "
                             "method='fixed' or engine='neuron'")
        if self.cell_permute not in (0, 1) or isinstance(self.cell_permute, bool):
            raise InputError(f"cell_permute must be 0 or 1 (CoreNEURON's CPU layouts), got {self.cell_permute!r}")
        if self.condition_order not in (1, 2) or isinstance(self.condition_order, bool):
            raise InputError(f"condition_order must be 1 or 2 (NEURON's threshold detection), got "
                             f"{self.condition_order!r}")
        if self.secondorder not in (0, 1, 2) or isinstance(self.secondorder, bool):
            raise InputError(f"secondorder must be 0, 1 or 2 (NEURON's fixed-step scheme), got {self.secondorder!r}")
        if self.secondorder and self.method != "fixed":
            raise InputError("secondorder applies to the fixed step only (CVODE chooses its own order): give "
                             "method='fixed' or secondorder=0")
        for name in ("dt_ms", "atol", "rtol", "maxstep_ms"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
                raise InputError(f"{name} must be finite and > 0, got {v!r}")
        if not isinstance(self.differenced, bool):
            raise InputError(f"differenced must be True or False, got {self.differenced!r}")
        limit = MAX_DIFFERENCE_DT_MS if self.differenced else MAX_DT_MS
        if self.method == "fixed" and self.dt_ms > limit:
            why = ("for runs that are only differenced" if self.differenced else
                   "for the fixed-step scheme (the 3 ms release kernel must be resolved)")
            raise InputError(f"dt_ms = {self.dt_ms} ms is too large {why}: maximum {limit} ms; give a smaller dt_ms")
        if isinstance(self.nthread, bool) or not isinstance(self.nthread, int) or self.nthread < 1:
            raise InputError(f"nthread must be an integer >= 1, got {self.nthread!r}")
        if self.max_wall_s is not None and self.max_wall_s != -1.0 and not (self.max_wall_s > 0):
            raise InputError(f"max_wall_s must be > 0 s, None (no budget) or -1 (the default), got "
                             f"{self.max_wall_s!r}")
        if isinstance(self.max_steps, bool) or not isinstance(self.max_steps, int) or self.max_steps < 1:
            raise InputError(f"max_steps must be an integer >= 1, got {self.max_steps!r}")
        if self.local_dt and self.method != "cvode":
            raise InputError("local_dt (NEURON's local variable time step) needs method='cvode'")
        if not (self.cvode_minstep_ms >= 0):
            raise InputError(f"cvode_minstep_ms must be >= 0 ms, got {self.cvode_minstep_ms!r}")

    def budget_s(self, duration_ms: float) -> float | None:
        """The wall-time budget (s) of a CVODE run of duration_ms (ms)."""
        if self.max_wall_s == -1.0:
            return DEFAULT_BUDGET_S + DEFAULT_BUDGET_S_PER_S * duration_ms / 1000.0
        return self.max_wall_s

    def settings(self) -> dict[str, Any]:
        """The integrator settings as recorded in provenance (None where the method ignores one)."""
        cv = self.method == "cvode"
        out = {"method": self.method, "dt_ms": None if cv else self.dt_ms, "atol": self.atol if cv else None,
               "rtol": self.rtol if cv else None, "nthread": self.nthread}
        if self.local_dt:
            out["local_dt"] = True
        if self.condition_order != 1:
            out["condition_order"] = self.condition_order
        if self.secondorder:
            out["secondorder"] = self.secondorder
        if self.differenced:
            out["differenced"] = True
        if self.engine != "neuron":
            out["engine"] = self.engine
            out["cell_permute"] = self.cell_permute
        return out

    # -- NEURON's global state -----------------------------------------------------------------------------
    @staticmethod
    def snapshot() -> dict[str, Any]:
        """Every global setting a run may change, as NEURON holds it now."""
        from neuron import h

        h.load_file("stdrun.hoc")
        cv = h.CVode()
        pc = h.ParallelContext()
        from neuron import coreneuron

        return {"dt": h.dt, "steps_per_ms": h.steps_per_ms, "secondorder": h.secondorder,
                "condition_order": cv.condition_order(), "cvode_active": cv.active(), "atol": cv.atol(),
                "rtol": cv.rtol(), "nthread": pc.nthread(),
                "minstep": cv.minstep(), "local_dt": cv.use_local_dt(),
                "atolscale": {name: cv.atolscale(name) for name, _ in _registered_states()},
                "cache_efficient": cv.cache_efficient(), "coreneuron": coreneuron.enable,
                "coreneuron_verbose": coreneuron.verbose, "coreneuron_cell_permute": coreneuron.cell_permute,
                "CORENEURONLIB": os.environ.get("CORENEURONLIB")}

    @staticmethod
    def _restore(saved: dict[str, Any]) -> None:
        from neuron import h

        cv = h.CVode()
        pc = h.ParallelContext()
        cv.use_local_dt(saved["local_dt"])
        cv.active(saved["cvode_active"])
        cv.condition_order(saved["condition_order"])
        cv.minstep(saved["minstep"])
        cv.atol(saved["atol"])
        cv.rtol(saved["rtol"])
        for name, scale in saved["atolscale"].items():
            cv.atolscale(name, scale)
        if pc.nthread() != saved["nthread"]:
            pc.nthread(saved["nthread"])
        pc.set_maxstep(MAXSTEP_AFTER_RUN_MS)
        h.dt, h.steps_per_ms, h.secondorder = saved["dt"], saved["steps_per_ms"], saved["secondorder"]
        from neuron import coreneuron

        coreneuron.enable = saved["coreneuron"]
        coreneuron.verbose = saved["coreneuron_verbose"]
        coreneuron.cell_permute = saved["coreneuron_cell_permute"]
        cv.cache_efficient(saved["cache_efficient"])
        if saved["CORENEURONLIB"] is None:
            os.environ.pop("CORENEURONLIB", None)
        else:
            os.environ["CORENEURONLIB"] = saved["CORENEURONLIB"]

    def _apply(self) -> None:
        from neuron import h

        cv = h.CVode()
        pc = h.ParallelContext()
        h.secondorder = self.secondorder
        cv.condition_order(self.condition_order)
        if pc.nthread() != self.nthread:
            pc.nthread(self.nthread)
        # also under CVODE: stdrun and interval recording use dt and steps_per_ms, so a caller's values must
        # not leak into the run
        h.dt = self.dt_ms
        h.steps_per_ms = 1.0 / self.dt_ms
        if self.method == "cvode":
            cv.use_local_dt(int(self.local_dt))
            cv.active(1)
            cv.minstep(self.cvode_minstep_ms)
            cv.atol(self.atol)
            cv.rtol(self.rtol)
            for name, scale in _registered_states():
                cv.atolscale(name, scale)
        else:
            cv.active(0)
        if self.engine == "coreneuron":
            from neuron import coreneuron

            from ..model.mechanisms import coreneuron_library

            os.environ["CORENEURONLIB"] = str(coreneuron_library())  # where NEURON finds CoreNEURON's build
            cv.cache_efficient(1)  # CoreNEURON takes the model from NEURON's cache-efficient layout
            coreneuron.enable = True
            coreneuron.verbose = 0
            coreneuron.cell_permute = self.cell_permute

    def _fixed_psolve(self, duration_ms: float, chunk_ms: float | None, after_chunk: Callable[[], None] | None
                      ) -> None:
        """The fixed step to duration_ms (ms), in chunks of chunk_ms (ms) with after_chunk() after each."""
        from neuron import h

        pc = h.ParallelContext()
        if chunk_ms is None:
            pc.psolve(duration_ms)
            if after_chunk is not None:
                after_chunk()
            return
        positive_number("chunk_ms", chunk_ms)
        k, stop = 1, 0.0
        while stop < duration_ms:
            # chunk ends on the step grid, counted from 0 (no drift from adding chunk lengths)
            stop = min(duration_ms, self.dt_ms * round(k * chunk_ms / self.dt_ms))
            pc.psolve(stop)
            if h.t < stop - 0.5 * self.dt_ms:
                # CoreNEURON counts the steps to a stop from a t that carries rounding from the chunks before, and
                # can stop one step short of it: the step it left out (one step: it takes int(1.5) steps)
                pc.psolve(h.t + 1.5 * self.dt_ms)
            if after_chunk is not None:
                after_chunk()
            k += 1

    def _cvode_with_budget(self, duration_ms: float) -> None:
        from neuron import h

        from ..errors import NumericalError

        if h.ParallelContext().nhost() > 1 or self.local_dt:
            self._cvode_psolve(duration_ms)
            return
        if not h.name_declared("neuromuscle_cvode_run"):
            h(_CVODE_LOOP)
        budget = self.budget_s(duration_ms)
        try:
            status = h.neuromuscle_cvode_run(duration_ms, 1e300 if budget is None else budget,
                                             float(self.max_steps))
        except RuntimeError as exc:
            raise NumericalError(f"{self.label}: CVODE failed at t = {h.t:.6g} ms of {duration_ms:g} ms (atol "
                                 f"{self.atol:g}, rtol {self.rtol:g}): {str(exc).splitlines()[0][:200]}; use the "
                                 "fixed step or loosen atol") from None
        if status == 1:
            raise NumericalError(f"{self.label}: CVODE spent its wall-time budget of {budget:.3g} s and reached only "
                                 f"t = {h.t:.6g} ms of {duration_ms:g} ms (atol {self.atol:g}); raise max_wall_s, "
                                 "loosen atol, or use the fixed step")
        if status == 2:
            raise NumericalError(f"{self.label}: CVODE took its budget of {self.max_steps} steps and reached only "
                                 f"t = {h.t:.6g} ms of {duration_ms:g} ms (atol {self.atol:g}); raise max_steps, "
                                 "loosen atol, or use the fixed step")

    def _cvode_psolve(self, duration_ms: float) -> None:
        """CVODE on several MPI ranks: psolve in chunks of maxstep_ms (spike exchange at each), the wall budget
        (agreed by every rank) checked between chunks."""
        import time

        from neuron import h

        from ..errors import NumericalError

        pc = h.ParallelContext()
        budget = self.budget_s(duration_ms)
        start = time.perf_counter()
        while h.t < duration_ms:
            try:
                pc.psolve(min(h.t + self.maxstep_ms, duration_ms))
            except RuntimeError as exc:
                raise NumericalError(f"{self.label}: CVODE failed at t = {h.t:.6g} ms of {duration_ms:g} ms "
                                     f"(atol {self.atol:g}): {str(exc).splitlines()[0][:200]}") from None
            spent = pc.allreduce(time.perf_counter() - start, 2)  # the slowest rank's time: all stop together
            if budget is not None and spent > budget and h.t < duration_ms:
                raise NumericalError(f"{self.label}: CVODE spent its wall-time budget of {budget:.3g} s and reached "
                                     f"only t = {h.t:.6g} ms of {duration_ms:g} ms (atol {self.atol:g}); raise "
                                     "max_wall_s, loosen atol, or use the fixed step")

    # -- running -------------------------------------------------------------------------------------------
    def run(self, duration_ms: float, units: Iterable[Any] = (), cvode_events_ms: Sequence[float] = (),
            chunk_ms: float | None = None, after_chunk: Callable[[], None] | None = None) -> float:
        """Initialise and integrate from 0 to duration_ms (ms); returns the integration's wall time (s).
        ``units`` (MuscleUnit or anything with ``prepare()``) queue their recorded spikes at initialisation;
        ``cvode_events_ms`` are times (ms) where CVODE must stop and restart (discontinuities of an input, e.g.
        eq 19's movement onset).  Fixed step: with ``chunk_ms`` (ms) the run stops every chunk_ms and calls
        ``after_chunk()`` (e.g. to take the samples out of every-step recordings, which CoreNEURON fills in
        memory); the states, queued events and results are those of one run."""
        import time

        from neuron import h

        if isinstance(duration_ms, bool) or not isinstance(duration_ms, (int, float)) or \
                not np.isfinite(duration_ms) or duration_ms <= 0:
            raise InputError(f"duration_ms must be finite and > 0, got {duration_ms!r}")
        for u in units:
            u.prepare()
        if self.method == "cvode":
            _refuse_fixed_step_only()
        saved = self.snapshot()
        try:
            self._apply()
            pc = h.ParallelContext()
            if self.method != "cvode" or pc.nhost() > 1 or self.local_dt:
                # before finitialize, which sets up the spike exchange between ranks: set after it, the first run
                # of a newly built network does not deliver the spikes that cross ranks as one rank does
                pc.set_maxstep(self.maxstep_ms)
            if self.v_init_mV is None:
                h.finitialize()
            else:
                h.finitialize(self.v_init_mV)
            if self.method == "cvode":
                for t in cvode_events_ms:
                    h.CVode().event(float(t))
                start = time.perf_counter()
                self._cvode_with_budget(duration_ms)
            else:  # psolve steps in C: no per-step hoc interpreter loop
                start = time.perf_counter()
                self._fixed_psolve(duration_ms, chunk_ms, after_chunk)
            return time.perf_counter() - start
        finally:
            self._restore(saved)
