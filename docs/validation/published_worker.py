"""Run the authors' published muscle mechanisms (ModelDB 266732: CaSP = Modules 1-2, fHill = Module 3, Xm = the
length) in a process of their own; compare_published.py starts it.  Needs only NEURON and NumPy.

Run:  python published_worker.py SPEC.json OUT.npz
SPEC.json: library (path of the compiled libnrnmech), units, duration_ms, dt_ms, length_mm, pulses_ms (pulse
onsets, ms), range {mechanism: {name: value}}, globals {hoc name: value}.
Each unit is the authors' muscle_unit section (L = diam = 10 um, cm = 20 uF/cm2, pas 2e-3 S/cm2) with CaSP,
fHill and an Xm at length_mm; the published code detects a spike when the section's v rises above vth
(-40 mV), so a voltage clamp lifts v from -70 to 0 mV for 1 ms at each pulse onset.  All units get the same
pulses.  OUT.npz: t_ms, force_N (units x samples, every step), spikes_ms (unit 0's spike times as the
published code stored them), spike_counts (per unit), wall_s and cpu_s (integration only), defaults (JSON: the
published values of every parameter set from SPEC, before setting), release_over_own (per unit: the release R
the published code computed at the last step over the unit's own sum of eq 3 at that step, CaSR Rmax sum of
kernels; 1 for a correct release).
"""

from __future__ import annotations

import json
import sys
import time
from typing import Any

import numpy as np
from neuron import h

V_REST_MV, V_PULSE_MV, PULSE_MS = -70.0, 0.0, 1.0


def build_unit(i: int, spec: dict[str, Any], defaults: dict[str, float]) -> dict[str, Any]:
    """One published muscle unit with its clamp; fills ``defaults`` (published values) on the first call."""
    sec = h.Section(name=f"muscle_unit{i}")
    sec.L = sec.diam = 10.0
    sec.cm = 20.0
    sec.insert("pas")
    sec(0.5).pas.g = 2e-3
    sec(0.5).pas.e = V_REST_MV
    seg = sec(0.5)
    for mech, values in spec["range"].items():
        sec.insert(mech)
        for name, value in values.items():
            defaults.setdefault(f"{mech}.{name}", getattr(getattr(seg, mech), name))
            setattr(getattr(seg, mech), name, value)
    xm = h.Xm(seg)
    xm.amp = spec["length_mm"]
    clamp = h.SEClamp(seg)
    clamp.dur1, clamp.rs, clamp.amp1 = 1e9, 1e-3, V_REST_MV
    onsets = np.asarray(spec["pulses_ms"], dtype=float)
    tv = h.Vector(np.ravel(np.column_stack([onsets, onsets + PULSE_MS])))
    av = h.Vector(np.ravel(np.column_stack([np.full(onsets.size, V_PULSE_MV), np.full(onsets.size, V_REST_MV)])))
    av.play(clamp._ref_amp1, tv)
    force = h.Vector().record(seg._ref_F_fHill)
    return {"sec": sec, "xm": xm, "clamp": clamp, "tv": tv, "av": av, "force": force}


def run(spec: dict[str, Any]) -> dict[str, Any]:
    """Build spec["units"] units, integrate with the fixed step and return the arrays of OUT.npz."""
    h.nrn_load_dll(spec["library"])
    h.load_file("stdrun.hoc")
    defaults: dict[str, float] = {}
    for name, value in spec["globals"].items():
        defaults[name] = getattr(h, name)
        setattr(h, name, value)
    h.cli0_cl_ion = spec["length_mm"]  # the published length channel (cl ion) holds the length from t = 0
    units = [build_unit(i, spec, defaults) for i in range(spec["units"])]
    index = h.Vector().record(units[0]["sec"](0.5)._ref_spk_index_CaSP)
    tvec = h.Vector().record(h._ref_t)
    h.cvode_active(0)
    h.secondorder = 0
    h.dt = spec["dt_ms"]
    h.steps_per_ms = 1.0 / spec["dt_ms"]
    pc = h.ParallelContext()
    pc.set_maxstep(10.0)
    h.finitialize(V_REST_MV)
    start, start_cpu = time.perf_counter(), time.process_time()
    pc.psolve(spec["duration_ms"])
    wall, cpu = time.perf_counter() - start, time.process_time() - start_cpu
    t = np.array(tvec)
    stored = np.flatnonzero(np.diff(np.array(index)) > 0) + 1  # steps at whose end a spike was stored
    spikes = t[stored] + units[0]["sec"](0.5).CaSP.t_axon
    mechs = [u["sec"](0.5).CaSP for u in units]
    return {"t_ms": t, "force_N": np.array([np.array(u["force"]) for u in units]), "spikes_ms": spikes,
            "spike_counts": np.array([m.spk_index for m in mechs]), "wall_s": np.array(wall), "cpu_s": np.array(cpu),
            "defaults": np.array(json.dumps(defaults)),
            "release_over_own": np.array([m.R / own_release(m, spikes, t[-1]) for m in mechs])}


def own_release(m: Any, spikes_ms: np.ndarray, t_ms: float) -> float:
    """Eq 3 for one unit at t_ms (ms): CaSR Rmax sum over its spikes of (1 - exp(-d/t1)) exp(-d/t2) (M/ms)."""
    d = t_ms - spikes_ms
    return m.CaSR * m.Rmax * float(np.sum((1.0 - np.exp(-d / m.t1)) * np.exp(-d / m.t2)))


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        np.savez(sys.argv[2], **run(json.load(f)))
