"""``neuromuscle bench unit``: wall time per simulated unit-second of this package's unit and of the authors'
scheme (derivimplicit + spike-history loop, mod/KimPublished.mod), alone and per unit in a pool."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.metrics import twitch_metrics
from ..errors import NumericalError
from ..model.mechanisms import load_mechanisms
from ..sim.unit import MuscleUnit
from ..parameters import ParameterSet
from ..protocols import constant_rate
from ..sim import Simulator

_PUBLISHED_M12 = ("K1", "K2", "K3", "K4", "K5i", "K6i", "K", "Rmax", "Umax", "tau1", "tau2", "CS0", "B0", "T0",
                  "CaSR0", "phi1", "phi2", "phi3", "phi4", "C1", "C2", "C3", "C4", "C5", "alpha")


class _PublishedUnit:
    """The authors' Modules 1-2 (KimPublished) driving a KimForce: the benchmark's comparison."""

    def __init__(self, params: ParameterSet, seg: Any, length: Any) -> None:
        from neuron import h

        self.m12 = h.KimPublished(seg)
        for n in _PUBLISHED_M12:
            setattr(self.m12, n, params[n])
        self.m12.xopt = params["g1"]
        self.m12._ref_xm = length._ref_xm
        self.force = h.KimForce(seg)
        for n in ("P0", "KSE", "g1", "g2", "a0", "b0", "c0", "d0"):
            setattr(self.force, n, params[n])
        self.force._ref_act = self.m12._ref_A
        self.force._ref_xm = length._ref_xm
        self.force._ref_force_offset = self.force._ref_zero
        self.receiver = self.m12


def _build(scheme: str, params: ParameterSet, n_units: int) -> tuple[list[Any], list[Any], list[Any]]:
    """n_units units of one scheme on one muscle section sharing one MuscleLength (as in a pool)."""
    from neuron import h

    load_mechanisms()
    sec = h.Section(name="bench_muscle")
    length = h.MuscleLength(sec(0.5))
    length.xm = params["g1"]
    keep: list[Any] = [sec, length]
    receivers, forces = [], []
    for i in range(n_units):
        if scheme == "ours":
            u = MuscleUnit(params, section=sec, length_source=length, name=f"bench{i}")
            receivers.append(u.receiver)
            forces.append(u["force"].obj)
        else:
            u = _PublishedUnit(params, sec(0.5), length)
            receivers.append(u.receiver)
            forces.append(u.force)
        keep.append(u)
    return keep, receivers, forces


def time_run(scheme: str, params: ParameterSet, spikes_ms: np.ndarray, duration_ms: float, dt_ms: float,
             n_units: int = 1, record: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    """Wall time (s) of a fixed-step run (dt_ms, ms) of n_units units of ``scheme`` ("ours" or "published"),
    each receiving ``spikes_ms``; with ``record`` also t (ms) and the first unit's force (N)."""
    from neuron import h

    keep, receivers, forces = _build(scheme, params, n_units)
    ncs = [h.NetCon(None, r) for r in receivers]
    for nc in ncs:
        nc.weight[0] = 1.0
    fih = h.FInitializeHandler(1, lambda: [nc.event(float(t)) for nc in ncs for t in spikes_ms])
    fv = h.Vector()
    if record:
        fv.record(forces[0]._ref_F, dt_ms)
    wall = Simulator(method="fixed", dt_ms=dt_ms).run(duration_ms)
    del fih  # the handler queued the spikes at initialisation
    if scheme == "published" and any(r.overflow for r in receivers):
        raise NumericalError("KimPublished: spike history (10000) overflowed; shorten the benchmark")
    f = np.array(fv)
    return wall, np.arange(f.size) * dt_ms, f


def bench_unit(params: ParameterSet, duration_ms: float = 3000.0, dt_ms: float = 0.025, repeats: int = 2,
               pool_units: int = 10, full: bool = False) -> dict[str, Any]:
    """Wall time (s) per simulated unit-second at 1 Hz and 100 Hz over duration_ms (ms), best of ``repeats``,
    for one unit alone and per unit in a pool of ``pool_units`` on one section; the authors' scheme is timed
    once, and in the pool at 100 Hz only with ``full`` (it costs minutes there).  Also both schemes' twitch
    errors (%) at dt_ms against the SciPy reference."""
    from ..reference import reference_simulate

    load_mechanisms()
    out: dict[str, Any] = {"duration_ms": duration_ms, "dt_ms": dt_ms, "repeats": repeats,
                           "pool_units": pool_units, "parameter_set": params.name, "full": full}
    unit_seconds = duration_ms / 1000.0
    for label, n in (("single", 1), ("pool", pool_units)):
        for rate in (1, 100):
            spikes = constant_rate(rate, duration_ms, start_ms=0.0)
            schemes = [("ours", repeats)]
            if full or not (label == "pool" and rate == 100):
                schemes.append(("published", 1))
            for scheme, reps in schemes:
                best = min(time_run(scheme, params, spikes, duration_ms, dt_ms, n)[0] for _ in range(reps))
                out[f"{label}_{scheme}_s_per_unit_s_{rate}hz"] = best / (unit_seconds * n)
            if len(schemes) == 2:
                out[f"{label}_speedup_{rate}hz"] = (out[f"{label}_published_s_per_unit_s_{rate}hz"]
                                                    / out[f"{label}_ours_s_per_unit_s_{rate}hz"])
        out[f"{label}_ours_100hz_over_1hz"] = (out[f"{label}_ours_s_per_unit_s_100hz"]
                                               / out[f"{label}_ours_s_per_unit_s_1hz"])
    ref = reference_simulate(params, np.array([500.0]), params["g1"], 750.0)
    m_ref = twitch_metrics(ref.t_ms, ref.force_N, 500.0)
    for scheme in ("ours", "published"):
        _, t, f = time_run(scheme, params, np.array([500.0]), 750.0, dt_ms, 1, record=True)
        m = twitch_metrics(t, f, 500.0)
        out[f"{scheme}_twitch_peak_error_pct"] = 100 * abs(m.peak_N / m_ref.peak_N - 1)
        out[f"{scheme}_twitch_ttp_error_pct"] = 100 * abs(m.time_to_peak_ms / m_ref.time_to_peak_ms - 1)
        out[f"{scheme}_twitch_half_relaxation_error_pct"] = 100 * abs(
            m.half_relaxation_ms / m_ref.half_relaxation_ms - 1)
    return out
