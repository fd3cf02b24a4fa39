"""``simulate``: one unit, one protocol, one run -- build, play the length, deliver the spikes, record, destroy."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from ..errors import InputError, NumericalError
from ..parameters import ParameterSet
from ..protocols.lengths import LengthTrace, as_length_trace
from ..validate import check_spike_times
from .provenance import provenance
from .recordings import Recorder, on_time_grid
from .results import CA_STATES, SimulationResult, find_variable
from .simulator import Simulator
from .unit import Model, MuscleUnit


def default_recordings(unit: MuscleUnit) -> list[str]:
    """The output, A, the length, and whatever of Atil and Module 1's Ca states the unit has (in the slots "act"
    and "ca", or in the one slot of a fused unit such as KimUnit's "muscle")."""
    known = unit.recordables()
    found = [find_variable(known, "act", "A"), "length.xm", find_variable(known, "act", "atil"),
             *(find_variable(known, "ca", var) for var in CA_STATES)]
    return [unit.output, *(n for n in found if n is not None)]


def simulate(params: ParameterSet, spikes_ms: Iterable[float], length: LengthTrace | float, duration_ms: float,
             *, excitation: Model = None, contraction: Model = None,
             extensions: Mapping[str, Mapping[str, float]] | None = None, record: Sequence[str] | None = None,
             record_dt_ms: float = 0.1, method: str = "fixed", dt_ms: float = Simulator.dt_ms,
             atol: float = Simulator.atol, rtol: float = Simulator.rtol, simulator: Simulator | None = None,
             initial_state: str = "rest",
             provenance_extra: dict | None = None) -> SimulationResult:
    """Simulate one unit from 0 to duration_ms (ms).

    spikes_ms: stimulus times (ms; finite, >= 0, strictly increasing).  length: a LengthTrace or a constant
    length (mm), played continuously into the unit's MuscleLength.  excitation/contraction/extensions: as
    ``MuscleUnit``.  record: names "slot.variable" (default ``default_recordings``), sampled every
    record_dt_ms (ms).  method/dt_ms/atol/rtol build the ``Simulator`` unless ``simulator`` is given.
    initial_state: "rest" (the resting steady state at the initial length) or "published" (that of Kim et al. 2015).
    """
    sim = simulator if simulator is not None else Simulator(method=method, dt_ms=dt_ms, atol=atol, rtol=rtol)
    sim = replace(sim, label=f"parameter set {getattr(params, 'name', '?')!r}")
    spikes, late, trace, notes = _checked_protocol(spikes_ms, length, duration_ms, record_dt_ms, sim)
    unit = MuscleUnit(params, excitation=excitation, contraction=contraction, extensions=extensions,
                      initial_state=initial_state)
    try:
        _check_pulse_spacing(unit, spikes)
        notes += [w for c in unit.components.values() for w in c.input_warnings(trace, unit.params)]
        result = _run([_Group([unit], spikes, trace, duration_ms)], sim, record, record_dt_ms,
                      provenance_extra or {})[0]
    finally:
        unit.destroy()
    if isinstance(result, NumericalError):
        raise result
    for n in reversed(notes):
        result.warnings.insert(0, n)
    result.settings["n_spikes_not_delivered"] = late
    return result


def simulate_batch(runs: Sequence[tuple[ParameterSet, Mapping[str, Mapping[str, float]] | None]],
                   spikes_ms: Iterable[float], length: LengthTrace | float, duration_ms: float, *,
                   excitation: Model = None, contraction: Model = None, record: Sequence[str] | None = None,
                   record_dt_ms: float = 0.1, dt_ms: float = Simulator.dt_ms,
                   initial_state: str = "rest") -> list[SimulationResult | None]:
    """One protocol (spikes_ms, length, duration_ms as :func:`simulate`) under several (parameter set,
    extensions) runs, simulated together as units of one fixed-step NEURON run (:func:`simulate_protocols` with
    one protocol).

    Each unit's result is bit for bit the one :func:`simulate` gives it alone: the units share only their section
    and the length input, and no muscle mechanism writes a current.  What is shared is NEURON's per-step cost of
    each mechanism type, paid once for all the units (a single unit spends most of its step there): eight runs
    of a 12.5 s train cost about a third of eight separate runs.  A unit whose run fails numerically gives None;
    the others are unaffected.  Fixed step only: under CVODE the units would share the integrator's steps.
    excitation/contraction: a model name or a mapping slot -> Component (copied for every unit)."""
    runs = list(runs)
    for k, run in enumerate(runs):
        if not (isinstance(run, tuple) and len(run) == 2 and isinstance(run[0], ParameterSet)
                and (run[1] is None or isinstance(run[1], Mapping))):
            raise InputError(f"simulate_batch: run {k} must be a (ParameterSet, extensions or None) pair, got "
                             f"{type(run).__name__} {run!r:.80}")
    return simulate_protocols([(p, e, 0) for p, e in runs], [(spikes_ms, length, duration_ms)],
                              excitation=excitation, contraction=contraction, record=record,
                              record_dt_ms=record_dt_ms, dt_ms=dt_ms, initial_state=initial_state)


#: One protocol of :func:`simulate_protocols`: stimulus times (ms), the length (a LengthTrace or a constant, mm)
#: and the duration (ms).
Protocol = tuple[Iterable[float], LengthTrace | float, float]


def simulate_protocols(runs: Sequence[tuple[ParameterSet, Mapping[str, Mapping[str, float]] | None, int]],
                       protocols: Sequence[Protocol], *, excitation: Model = None, contraction: Model = None,
                       record: Sequence[str] | None = None, record_dt_ms: float = 0.1,
                       dt_ms: float = Simulator.dt_ms, initial_state: str = "rest", differenced: bool = False
                       ) -> list[SimulationResult | None]:
    """Several protocols, each under one or more (parameter set, extensions) runs, simulated together as the units
    of one fixed-step NEURON run to the longest protocol's duration.  Run k is (parameter set, extensions or None,
    index into ``protocols``); a protocol is (spikes_ms, length, duration_ms) as :func:`simulate` takes them.

    Each unit's result covers its own protocol's duration and is bit for bit the one :func:`simulate` gives it
    alone: the units of one protocol share its length input, each protocol has its own, and no muscle mechanism
    writes a current, so a unit's states never depend on another's; a unit whose protocol ends before the run
    keeps its samples up to its own end (the fixed step's states at those times do not depend on when the run
    stops).  Packing the runs of several protocols into one NEURON run shares NEURON's per-step cost of each
    mechanism type where each protocol alone would have few units.  A unit whose run fails numerically gives None;
    the others are unaffected.  differenced: the forces are only differenced against runs at the same step
    (``Simulator.differenced``: a coarser step is accepted)."""
    sim = Simulator(method="fixed", dt_ms=dt_ms, differenced=differenced)
    runs = list(runs)
    checked = [_checked_protocol(s, x, d, record_dt_ms, sim) for s, x, d in protocols]
    for k, run in enumerate(runs):
        if not (isinstance(run, tuple) and len(run) == 3 and isinstance(run[0], ParameterSet)
                and (run[1] is None or isinstance(run[1], Mapping)) and isinstance(run[2], int)
                and 0 <= run[2] < len(checked)):
            raise InputError(f"simulate_protocols: run {k} must be a (ParameterSet, extensions or None, protocol "
                             f"index < {len(checked)}) triple, got {type(run).__name__} {run!r:.80}")
    if not runs:
        return []
    from neuron import h

    section = h.Section(name="batch_muscle")
    units: list[MuscleUnit] = []
    owners: dict[int, MuscleUnit] = {}  # protocol index -> the unit that owns its length input
    try:
        for k, (params, extensions, j) in enumerate(runs):
            unit = MuscleUnit(params, excitation=excitation, contraction=contraction, extensions=extensions,
                              section=section, length_source=owners[j].length if j in owners else None,
                              name=f"unit {k}", initial_state=initial_state)
            units.append(unit)
            owners.setdefault(j, unit)
            _check_pulse_spacing(unit, checked[j][0])
        groups = [_Group([u for u, r in zip(units, runs) if r[2] == j], checked[j][0], checked[j][2],
                         float(protocols[j][2])) for j in sorted(owners)]
        done = dict(zip((id(u) for g in groups for u in g.units),
                        _run(groups, replace(sim, label="batch"), record, record_dt_ms, {})))
    finally:
        for u in units:
            u.destroy()
    out: list[SimulationResult | None] = []
    for unit, (_, _, j) in zip(units, runs):
        res = done[id(unit)]
        if isinstance(res, NumericalError):
            out.append(None)
            continue
        _, late, trace, notes = checked[j]
        res.warnings[:0] = notes + [w for c in unit.components.values() for w in c.input_warnings(trace, unit.params)]
        res.settings["n_spikes_not_delivered"] = late
        out.append(res)
    return out


def _checked_protocol(spikes_ms: Iterable[float], length: LengthTrace | float, duration_ms: float,
                      record_dt_ms: float, sim: Simulator) -> tuple[np.ndarray, int, LengthTrace, list[str]]:
    """The inputs simulate and simulate_batch share, checked: (spikes before the end (ms), how many were at or
    after it, the length trace, notes for the result's warnings).  InputError names the bad argument."""
    if not np.isfinite(record_dt_ms) or record_dt_ms <= 0:
        raise InputError(f"record_dt_ms must be finite and > 0, got {record_dt_ms}")
    if not np.isfinite(duration_ms) or duration_ms <= 0:
        raise InputError(f"duration_ms must be finite and > 0, got {duration_ms}")
    if sim.method == "fixed" and record_dt_ms < sim.dt_ms:
        raise InputError(f"record_dt_ms = {record_dt_ms} ms is below the fixed step dt_ms = {sim.dt_ms} ms: samples "
                         "between steps would repeat values; give record_dt_ms >= dt_ms")
    spikes = check_spike_times(spikes_ms)
    late = spikes[spikes >= duration_ms]
    notes = []
    if late.size:
        notes.append(f"{late.size} spike(s) at or after the end of the run ({duration_ms:g} ms; the first at "
                     f"{late[0]:g} ms) are not delivered; lengthen duration_ms or drop them")
    return spikes[spikes < duration_ms], int(late.size), as_length_trace(length, duration_ms), notes


def _check_pulse_spacing(unit: MuscleUnit, spikes: np.ndarray) -> None:
    for comp in unit.components.values():
        gap = getattr(comp, "min_interval_ms", None)
        if gap and spikes.size > 1 and np.min(np.diff(spikes)) < gap:
            raise InputError(f"spike times: {type(comp).__name__} pulses last {gap} ms and may not overlap; an "
                             f"interval is {np.min(np.diff(spikes)):.3f} ms")


def _model_description(unit: MuscleUnit) -> dict[str, Any]:
    return {slot: {"component": type(c).__name__, **c.switches()} for slot, c in unit.components.items()}


@dataclass
class _Group:
    """Units that share one protocol in a run: their stimulus times (ms), length trace and duration (ms); the first
    unit owns the length input."""

    units: Sequence[MuscleUnit]
    spikes: np.ndarray
    trace: LengthTrace
    duration_ms: float


def _play_length(owner: MuscleUnit, trace: LengthTrace, duration_ms: float) -> tuple[Any, ...]:
    """Set the unit's length input to the trace's start and, when it moves, play the trace into it; returns the
    vectors NEURON plays (keep them until the run ends, then ``play_remove`` them)."""
    from neuron import h

    t_ms, xm, vm = trace.t_ms, trace.xm_mm, trace.velocity_mm_s
    if abs(t_ms[-1] - duration_ms) <= 1e-9 * max(1.0, duration_ms):
        # continue the last segment 1 ms past the run's end: a played vector that ends at the stop time makes
        # CVODE crawl there (measured: 119 s instead of 2 s for a 700 ms random-length run); the fixed step and
        # every sample up to the stop time are unchanged.  A trace ending earlier is left as NEURON plays it.
        t_ms = np.append(t_ms, duration_ms + 1.0)
        xm = np.append(xm, xm[-1] + vm[-1] * (duration_ms + 1.0 - trace.t_ms[-1]) / 1000.0)
        vm = np.append(vm, vm[-1])
    tvec, xvec, vvec = h.Vector(on_time_grid(t_ms)), h.Vector(xm), h.Vector(vm)  # the recordings' time grid
    length = owner.length
    length.xm = float(trace.xm_mm[0])
    length.vm = float(trace.velocity_mm_s[0])
    if not trace.is_isometric:
        xvec.play(length._ref_xm, tvec, 1)
        vvec.play(length._ref_vm, tvec, 1)
    return tvec, xvec, vvec


def _run(groups: Sequence[_Group], sim: Simulator, record: Sequence[str] | None, record_dt_ms: float,
         extra: dict) -> list[SimulationResult | NumericalError]:
    """Run every group's units in one simulation to the longest group's duration: each unit's result over its own
    group's duration (in the groups' order), or the NumericalError of a unit whose integration failed."""
    movement_events = []
    played = []
    for g in groups:
        for unit in g.units:
            unit.add_spike_times(g.spikes)
            for comp in unit.components.values():
                if g.trace.onset_ms is not None and hasattr(comp, "set_movement_onset"):
                    comp.set_movement_onset(g.trace.onset_ms)
                    if getattr(comp, "uses_movement_clock", False):
                        movement_events.append(g.trace.onset_ms)
        played.append(_play_length(g.units[0], g.trace, g.duration_ms))
    stepwise = sim.dt_ms if sim.method == "fixed" and (sim.nthread > 1 or sim.engine == "coreneuron") else None
    duration_ms = max(g.duration_ms for g in groups)
    recorders = [[Recorder(unit, list(record) if record is not None else default_recordings(unit), record_dt_ms,
                           every_step_dt_ms=stepwise,
                           at_times_until_ms=g.duration_ms if sim.method == "cvode" else None)
                  for unit in g.units] for g in groups]
    try:
        sim.run(duration_ms, units=[u for g in groups for u in g.units], cvode_events_ms=movement_events)
    finally:
        for _, xvec, vvec in played:
            xvec.play_remove()
            vvec.play_remove()
    return [_result(unit, recorder, g.spikes, g.trace, g.duration_ms, sim, record_dt_ms, extra)
            for g, recs in zip(groups, recorders) for unit, recorder in zip(g.units, recs)]


def _result(unit: MuscleUnit, recorder: Recorder, spikes: np.ndarray, trace: LengthTrace, duration_ms: float,
            sim: Simulator, record_dt_ms: float, extra: dict) -> SimulationResult | NumericalError:
    t, traces = recorder.arrays(duration_ms)
    bad = [k for k, v in traces.items() if not np.all(np.isfinite(v))]
    if bad:
        i = int(np.flatnonzero(~np.isfinite(traces[bad[0]]))[0])
        return NumericalError(f"{unit.name}: non-finite {bad[0]} at t = {t[i]:.3f} ms ({sim.method}, dt "
                              f"{sim.dt_ms} ms): the integration failed")
    warnings = [w for c in unit.components.values() for w in c.run_warnings()]
    asym = sum(c.asymptote_steps() for c in unit.components.values() if hasattr(c, "asymptote_steps"))
    settings = {"duration_ms": duration_ms, **sim.settings(), "record_dt_ms": record_dt_ms,
                "model": _model_description(unit), "extensions": list(unit.extension_names),
                "initial_state": unit.initial_state,
                "movement_onset_ms": trace.onset_ms, "n_spikes": int(spikes.size),
                "steps_on_eccentric_saturation": asym if sim.method == "fixed" else None}
    return SimulationResult(
        t_ms=t, traces=traces, units=recorder.units, output=unit.output, params=unit.params, settings=settings,
        warnings=warnings,
        provenance=provenance(settings=settings, parameter_set=unit.params.name, spikes_ms=spikes.tolist(),
                              parameters={k: v for k, v in unit.params.items()}, **extra))
