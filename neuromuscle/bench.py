"""Benchmarks (``neuromuscle bench unit``): wall time per simulated unit-second, and the speed-up over the
authors' way of integrating the same unit (derivimplicit + spike-history loop, mechanism KimPublished)."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from .mechanisms import load_mechanisms
from .metrics import twitch_metrics
from .parameters import ParameterSet
from .protocols import constant_rate
from .unit import MuscleUnit, _NeuronRun


def _published_unit(params: ParameterSet, xm_mm: float) -> tuple[Any, ...]:
    from neuron import h

    sec = h.Section(name="published_muscle")
    seg = sec(0.5)
    length = h.MuscleLength(seg)
    length.xm = xm_mm
    m12 = h.KimPublished(seg)
    for n in ("K1", "K2", "K3", "K4", "K5i", "K6i", "K", "Rmax", "Umax", "tau1", "tau2", "CS0", "B0", "T0",
              "CaSR0", "phi1", "phi2", "phi3", "phi4", "C1", "C2", "C3", "C4", "C5", "alpha"):
        setattr(m12, n, params[n])
    m12.xopt = params["g1"]
    m12._ref_xm = length._ref_xm
    force = h.KimForce(seg)
    for n in ("P0", "KSE", "g1", "g2", "a0", "b0", "c0", "d0"):
        setattr(force, n, params[n])
    force._ref_act = m12._ref_A
    force._ref_xm = length._ref_xm
    return sec, length, m12, force


def _time_run(target: Any, force: Any, spikes: np.ndarray, duration_ms: float, dt_ms: float,
              record: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    from neuron import h

    nc = h.NetCon(None, target)
    nc.weight[0] = 1.0
    fih = h.FInitializeHandler(1, lambda: [nc.event(float(t)) for t in spikes])
    tv, fv = h.Vector(), h.Vector()
    if record:
        tv.record(h._ref_t, dt_ms)
        fv.record(force._ref_F, dt_ms)
    with _NeuronRun("fixed", dt_ms, 0.0, 0.0) as hh:
        hh.finitialize()
        t0 = time.perf_counter()
        pc = hh.ParallelContext()
        pc.set_maxstep(10.0)
        pc.psolve(duration_ms)
        wall = time.perf_counter() - t0
    del fih, nc
    return wall, np.array(tv), np.array(fv)


def _ours(params: ParameterSet, spikes: np.ndarray, duration_ms: float, dt_ms: float,
          record: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    unit = MuscleUnit(params, name="bench")
    unit.length.xm = params["g1"]
    try:
        return _time_run(unit.ca, unit.force, spikes, duration_ms, dt_ms, record)
    finally:
        unit.destroy()


def _published(params: ParameterSet, spikes: np.ndarray, duration_ms: float, dt_ms: float,
               record: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    sec, length, m12, force = _published_unit(params, params["g1"])
    return _time_run(m12, force, spikes, duration_ms, dt_ms, record)


def bench_unit(params: ParameterSet, duration_ms: float = 10_000.0, dt_ms: float = 0.025,
               repeats: int = 3) -> dict[str, Any]:
    """Wall time (s) per simulated unit-second at 1 Hz and 100 Hz over duration_ms (ms), best of repeats,
    for this package's unit and for the authors' scheme; plus both schemes' twitch accuracy at dt_ms."""
    load_mechanisms()
    out: dict[str, Any] = {"duration_ms": duration_ms, "dt_ms": dt_ms, "repeats": repeats,
                           "parameter_set": params.name}
    sec_per = duration_ms / 1000.0
    for rate in (1, 100):
        spikes = constant_rate(rate, duration_ms, start_ms=0.0)
        ours = min(_ours(params, spikes, duration_ms, dt_ms)[0] for _ in range(repeats)) / sec_per
        pub = min(_published(params, spikes, duration_ms, dt_ms)[0] for _ in range(repeats)) / sec_per
        out[f"ours_s_per_unit_s_{rate}hz"] = ours
        out[f"published_s_per_unit_s_{rate}hz"] = pub
        out[f"speedup_{rate}hz"] = pub / ours
    out["ours_100hz_over_1hz"] = out["ours_s_per_unit_s_100hz"] / out["ours_s_per_unit_s_1hz"]
    # accuracy at the benchmark step, against the independent SciPy integration
    from .reference import reference_simulate

    ref = reference_simulate(params, np.array([500.0]), params["g1"], 750.0)
    m_ref = twitch_metrics(ref.t_ms, ref.force_N, 500.0)
    for name, fn in (("ours", _ours), ("published", _published)):
        _, t, f = fn(params, np.array([500.0]), 750.0, dt_ms, record=True)
        m = twitch_metrics(t, f, 500.0)
        out[f"{name}_twitch_peak_error_pct"] = 100 * abs(m.peak_N / m_ref.peak_N - 1)
        out[f"{name}_twitch_ttp_error_pct"] = 100 * abs(m.time_to_peak_ms / m_ref.time_to_peak_ms - 1)
        out[f"{name}_twitch_half_relaxation_error_pct"] = 100 * abs(
            m.half_relaxation_ms / m_ref.half_relaxation_ms - 1)
    return out
