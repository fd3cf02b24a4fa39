"""``simulate``: one unit, one protocol, one run -- build, play the length, deliver the spikes, record, destroy."""

from __future__ import annotations

from dataclasses import replace
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
        result = _run([unit], spikes, trace, duration_ms, sim, record, record_dt_ms, provenance_extra or {})[0]
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
    extensions) runs, simulated together as units of one fixed-step NEURON run.

    Each unit's result is bit for bit the one :func:`simulate` gives it alone: the units share only their section
    and the length input, and no muscle mechanism writes a current.  What is shared is NEURON's per-step cost of
    each mechanism type, paid once for all the units (a single unit spends most of its step there): eight runs
    of a 12.5 s train cost about a third of eight separate runs.  A unit whose run fails numerically gives None;
    the others are unaffected.  Fixed step only: under CVODE the units would share the integrator's steps.
    excitation/contraction: a model name or a mapping slot -> Component (copied for every unit)."""
    sim = Simulator(method="fixed", dt_ms=dt_ms)
    spikes, late, trace, notes = _checked_protocol(spikes_ms, length, duration_ms, record_dt_ms, sim)
    runs = list(runs)
    for k, run in enumerate(runs):
        if not (isinstance(run, tuple) and len(run) == 2 and isinstance(run[0], ParameterSet)
                and (run[1] is None or isinstance(run[1], Mapping))):
            raise InputError(f"simulate_batch: run {k} must be a (ParameterSet, extensions or None) pair, got "
                             f"{type(run).__name__} {run!r:.80}")
    if not runs:
        return []
    from neuron import h

    section = h.Section(name="batch_muscle")
    units: list[MuscleUnit] = []
    try:
        for k, (params, extensions) in enumerate(runs):
            units.append(MuscleUnit(params, excitation=excitation, contraction=contraction, extensions=extensions,
                                    section=section, length_source=units[0].length if units else None,
                                    name=f"unit {k}", initial_state=initial_state))
            _check_pulse_spacing(units[-1], spikes)
        results = _run(units, spikes, trace, duration_ms, replace(sim, label="batch"), record, record_dt_ms, {})
    finally:
        for u in units:
            u.destroy()
    out: list[SimulationResult | None] = []
    for unit, res in zip(units, results):
        if isinstance(res, NumericalError):
            out.append(None)
            continue
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


def _run(units: Sequence[MuscleUnit], spikes: np.ndarray, trace: LengthTrace, duration_ms: float, sim: Simulator,
         record: Sequence[str] | None, record_dt_ms: float, extra: dict) -> list[SimulationResult | NumericalError]:
    """Run ``units`` (the first owns the length input, the others share it) in one simulation: each unit's
    result, or the NumericalError of a unit whose integration failed."""
    from neuron import h

    movement_events = []
    for unit in units:
        unit.add_spike_times(spikes)
        for comp in unit.components.values():
            if trace.onset_ms is not None and hasattr(comp, "set_movement_onset"):
                comp.set_movement_onset(trace.onset_ms)
                if getattr(comp, "uses_movement_clock", False):
                    movement_events.append(trace.onset_ms)
    t_ms, xm, vm = trace.t_ms, trace.xm_mm, trace.velocity_mm_s
    if abs(t_ms[-1] - duration_ms) <= 1e-9 * max(1.0, duration_ms):
        # continue the last segment 1 ms past the run's end: a played vector that ends at the stop time makes
        # CVODE crawl there (measured: 119 s instead of 2 s for a 700 ms random-length run); the fixed step and
        # every sample up to the stop time are unchanged.  A trace ending earlier is left as NEURON plays it.
        t_ms = np.append(t_ms, duration_ms + 1.0)
        xm = np.append(xm, xm[-1] + vm[-1] * (duration_ms + 1.0 - trace.t_ms[-1]) / 1000.0)
        vm = np.append(vm, vm[-1])
    tvec, xvec, vvec = h.Vector(on_time_grid(t_ms)), h.Vector(xm), h.Vector(vm)  # the recordings' time grid
    length = units[0].length
    length.xm = float(trace.xm_mm[0])
    length.vm = float(trace.velocity_mm_s[0])
    if not trace.is_isometric:
        xvec.play(length._ref_xm, tvec, 1)
        vvec.play(length._ref_vm, tvec, 1)
    stepwise = sim.dt_ms if sim.method == "fixed" and (sim.nthread > 1 or sim.engine == "coreneuron") else None
    recorders = [Recorder(unit, list(record) if record is not None else default_recordings(unit), record_dt_ms,
                          every_step_dt_ms=stepwise, at_times_until_ms=duration_ms if sim.method == "cvode" else None)
                 for unit in units]
    try:
        sim.run(duration_ms, units=units, cvode_events_ms=movement_events)
    finally:
        xvec.play_remove()
        vvec.play_remove()
    return [_result(unit, recorder, spikes, trace, duration_ms, sim, record_dt_ms, extra)
            for unit, recorder in zip(units, recorders)]


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
