"""``neuromuscle bench sweep``: robustness of the numerics over random parameter sets.

Each draw (``sweep_draws``) runs every protocol of ``sweep_protocols`` under the fixed step and under CVODE
(with a per-run wall-time budget); draws run in parallel in a ``guarded_pool``, each draw's process killed if it
exceeds its own timeout, so nothing in the sweep can hang.  Each run is recorded (``sweep_summary``) and the
records are summarised: exceptions, hangs, non-finite values, negative force, fixed-vs-CVODE differences (% of
peak) and wall times.

    from neuromuscle.bench.sweep import SweepSettings, sweep
    report = sweep(SweepSettings(n_draws=6, short=True), workers=2)
    report["summary"]["failures"]            # [] when every check passed
"""

from __future__ import annotations

import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..parameters import ParameterSet, load_parameters
from .guarded_pool import Outcome, guarded_map
from .sweep_draws import FACTOR_RANGE, draw
from .sweep_journal import append_draw, open_journal
from .sweep_protocols import Protocol, sweep_protocols
from .sweep_explain import explain
from .sweep_summary import TOLERANCE_PCT, comparison, run_record, summarise

METHODS = ("fixed", "cvode")
#: Recording interval (ms) of the force compared between the integrators.
RECORD_DT_MS = 0.5
#: CVODE's step budget of one run, per simulated ms: CT09 takes at most about 170 steps per ms (100 Hz train), so
#: a run past it takes six times as many steps as the published set; a budget in steps counts the same on any
#: machine under any load.  A run that spends it stops (NumericalError) and counts as a hang.
STEPS_PER_MS = 1000
#: CVODE's wall-time budget of one run (s), the safety net behind the step budget.
RUN_BUDGET_S = 60.0
#: Process-level timeout of a draw, per protocol, on top of its CVODE run's budget (s): the fixed-step run and
#: building the units fit many times over in it.
PROTOCOL_ALLOWANCE_S = 20.0


@dataclass(frozen=True)
class SweepSettings:
    """What a sweep runs: ``n_draws`` sets around ``base`` (a set name or file) from ``seed``, each parameter
    times a log-uniform factor in ``factor_range``; ``short`` protocols (tests); fixed step ``dt_ms`` (ms); CVODE's
    budgets per run, ``steps_per_ms`` steps per simulated ms and ``run_budget_s`` (s) of wall time; the
    process-level timeout per draw ``draw_timeout_s`` (s; None: per protocol, the run budget plus
    PROTOCOL_ALLOWANCE_S)."""

    n_draws: int
    seed: int = 0
    base: str = "CT09"
    factor_range: tuple[float, float] = FACTOR_RANGE
    short: bool = False
    dt_ms: float = 0.025
    steps_per_ms: float = STEPS_PER_MS
    run_budget_s: float = RUN_BUDGET_S
    draw_timeout_s: float | None = None

    def protocols_per_draw(self) -> int:
        """How many protocols each draw runs (under each integrator)."""
        return len(sweep_protocols(-8.0, 0, False, self.short))

    def timeout_s(self) -> float:
        """The process-level timeout (s) of one draw."""
        if self.draw_timeout_s is not None:
            return self.draw_timeout_s
        return self.protocols_per_draw() * (self.run_budget_s + PROTOCOL_ALLOWANCE_S)


def run_protocol(params: ParameterSet, draw_index: int, protocol: Protocol, method: str,
                 settings: SweepSettings) -> tuple[dict[str, Any], np.ndarray | None]:
    """One run: its record and its force (N, every RECORD_DT_MS ms; None when it raised).  Force, activation and
    Module 1's troponin-bound Ca are recorded, so the package's non-finite check covers all three modules."""
    from neuron import h

    from ..model.kim import kim_excitation
    from ..sim import Simulator, simulate

    sim = Simulator(method=method, dt_ms=settings.dt_ms, max_wall_s=settings.run_budget_s,
                    max_steps=int(settings.steps_per_ms * protocol.duration_ms))
    start = time.perf_counter()
    try:
        r = simulate(params, protocol.spikes_ms, protocol.length, protocol.duration_ms, simulator=sim,
                     record=("force.F", "act.A", "ca.CaSPT"), record_dt_ms=RECORD_DT_MS,
                     excitation=kim_excitation(movement_compensation=protocol.movement_compensation))
    except Exception as exc:  # every failure is a finding of the sweep: recorded by class and message
        return run_record(draw_index, protocol.name, method, protocol.duration_ms, time.perf_counter() - start,
                          error=exc, t_reached_ms=float(h.t)), None
    return run_record(draw_index, protocol.name, method, protocol.duration_ms, time.perf_counter() - start,
                      force_N=r.force_N, warnings=r.warnings), r.force_N


def run_draw(task: dict[str, Any], emit: Callable[[dict[str, Any]], None]) -> None:
    """Worker side: every protocol of one draw under both integrators.  Emits {"kind": "start"} before each run
    (so a killed draw names the run it was in), then the run's record and, per protocol, the comparison."""
    settings = SweepSettings(**task["settings"])
    params = ParameterSet(task["name"], task["values"])
    for protocol in sweep_protocols(params["g1"], task["length_seed"], task["movement_compensation"],
                                    settings.short):
        forces = {}
        for method in METHODS:
            emit({"kind": "start", "protocol": protocol.name, "method": method,
                  "duration_ms": protocol.duration_ms, "at": time.time()})
            record, forces[method] = run_protocol(params, task["draw"], protocol, method, settings)
            emit({"kind": "run", "record": record})
        if all(f is not None for f in forces.values()):
            record = comparison(task["draw"], protocol.name, forces["fixed"], forces["cvode"])
            if record["pct"] > TOLERANCE_PCT:
                record["explained"] = _explained(params, protocol, forces, settings)
            emit({"kind": "comparison", "comparison": record})


def _explained(params: ParameterSet, protocol: Protocol, forces: dict[str, np.ndarray],
               settings: SweepSettings) -> dict[str, Any]:
    """``sweep_explain.explain`` of an over-tolerance comparison; a failure of its own runs is "unexplained"."""
    try:
        return explain(params, protocol, forces["fixed"], forces["cvode"], settings.dt_ms, RECORD_DT_MS)
    except Exception as exc:  # the checks' own failure is a finding too
        return {"cause": "unexplained", "error": f"{type(exc).__name__}: {str(exc).splitlines()[0][:200]}"}


def _records(draw_index: int, outcome: Outcome) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The run records and comparisons of one draw's outcome, with a record for the run a killed, dead or failed
    draw was in."""
    runs = [m["record"] for m in outcome.messages if m["kind"] == "run"]
    if outcome.status != "done":
        status = "exception" if outcome.status == "error" else outcome.status
        runs.append(_unfinished_run(draw_index, outcome.messages, status, outcome.error or ""))
    return runs, [m["comparison"] for m in outcome.messages if m["kind"] == "comparison"]


def _unfinished_run(draw_index: int, messages: list[dict[str, Any]], status: str, error: str) -> dict[str, Any]:
    """The record of the run a killed, dead or failed draw was in (from its last "start" message)."""
    started = next((m for m in reversed(messages) if m["kind"] in ("start", "run")), None)
    if started is None or started["kind"] == "run":  # it failed outside a run
        return run_record(draw_index, "(draw setup)", "-", 0.0, None, error=error, status=status)
    return run_record(draw_index, started["protocol"], started["method"], started["duration_ms"],
                      time.time() - started["at"], error=error, status=status)


def _progress(done: int, total: int, runs: list[dict[str, Any]], started: float, ran: int) -> None:
    """A progress line on stderr every 10 draws (every draw of a short sweep); ``ran`` draws ran in this call."""
    if done % max(1, min(10, total // 20)) and done != total:
        return
    elapsed = time.monotonic() - started
    bad = sum(r["status"] != "ok" for r in runs)
    print(f"sweep: {done}/{total} draws, {len(runs)} runs, {bad} not ok, {elapsed / 60:.1f} min, "
          f"about {elapsed / ran * (total - done) / 60:.1f} min left", file=sys.stderr, flush=True)


def sweep(settings: SweepSettings, workers: int = 2, progress: bool = True,
          journal: str | Path | None = None) -> dict[str, Any]:
    """Run the sweep in ``workers`` processes; returns {"summary", "draws", "runs", "comparisons"}: the summary
    (``sweep_summary.summarise`` plus the settings, total wall time in s and the worst draw's parameters), each
    draw's factors and refusals, and every run record and comparison.  With ``journal`` (a file) each finished
    draw is appended to it, and the draws it already holds are taken from it (``sweep_journal``)."""
    from ..sim import Simulator

    base = load_parameters(settings.base)
    draws = [draw(base, settings.seed, i, settings.factor_range) for i in range(settings.n_draws)]
    done = open_journal(journal, asdict(settings)) if journal is not None else {}
    done = {i: d for i, d in done.items() if i < settings.n_draws}
    runs = [r for d in done.values() for r in d["runs"]]
    comparisons = [c for d in done.values() for c in d["comparisons"]]
    tasks = [{"draw": d.index, "name": d.params.name, "values": dict(d.params.values), "length_seed": d.length_seed,
              "movement_compensation": d.movement_compensation, "settings": asdict(settings)}
             for d in draws if d.index not in done]
    started = time.monotonic()
    for n, outcome in enumerate(guarded_map(run_draw, tasks, workers, settings.timeout_s()), start=len(done) + 1):
        index = tasks[outcome.index]["draw"]
        draw_runs, draw_comparisons = _records(index, outcome)
        runs += draw_runs
        comparisons += draw_comparisons
        if journal is not None:
            append_draw(journal, index, draw_runs, draw_comparisons)
        if progress:
            _progress(n, len(draws), runs, started, n - len(done))
    summary = summarise(runs, comparisons, seed=settings.seed, n_draws=settings.n_draws,
                        n_refused=sum(len(d.refused) for d in draws),
                        n_runs_expected=settings.n_draws * settings.protocols_per_draw() * len(METHODS))
    summary["settings"] = {**asdict(settings), "workers": workers, "record_dt_ms": RECORD_DT_MS,
                           "draw_timeout_s": settings.timeout_s(), "cvode_atol": Simulator.atol,
                           "cvode_rtol": Simulator.rtol}
    summary["total_wall_s"] = time.monotonic() - started
    worst = summary["worst_fixed_vs_cvode_pct"]
    if worst is not None:
        worst_draw = draws[worst["draw"]]
        worst["parameters"] = {n: worst_draw.params[n] for n in worst_draw.factors}
        worst["factors"] = worst_draw.factors
    return {"summary": summary,
            "draws": [{"draw": d.index, "factors": d.factors, "refused": list(d.refused),
                       "length_seed": d.length_seed, "movement_compensation": d.movement_compensation}
                      for d in draws],
            "runs": sorted(runs, key=lambda r: r["draw"]),
            "comparisons": sorted(comparisons, key=lambda c: c["draw"])}
