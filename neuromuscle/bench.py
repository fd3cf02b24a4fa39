"""Benchmarks (``neuromuscle bench unit``): wall time per simulated unit-second, and the speed-up over the
authors' way of integrating the same unit (derivimplicit + spike-history loop, mechanism KimPublished)."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from .errors import NumericalError
from .mechanisms import load_mechanisms
from .metrics import twitch_metrics
from .parameters import ParameterSet
from .protocols import constant_rate
from .unit import MuscleUnit, _NeuronRun


def _published_unit(params: ParameterSet, seg: Any, length: Any) -> tuple[Any, Any]:
    from neuron import h

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
    return m12, force


def _build(scheme: str, params: ParameterSet, n_units: int) -> tuple[list[Any], list[Any], list[Any]]:
    """n_units units of one scheme on one muscle section sharing one MuscleLength (as in a pool)."""
    from neuron import h

    load_mechanisms()
    sec = h.Section(name="bench_muscle")
    length = h.MuscleLength(sec(0.5))
    length.xm = params["g1"]
    keep: list[Any] = [sec, length]
    targets, forces = [], []
    for i in range(n_units):
        if scheme == "ours":
            u = MuscleUnit(params, section=sec, length_source=length, name=f"bench{i}")
            keep.append(u)
            targets.append(u.ca)
            forces.append(u.force)
        else:
            m12, f = _published_unit(params, sec(0.5), length)
            keep += [m12, f]
            targets.append(m12)
            forces.append(f)
    return keep, targets, forces


def _time_run(scheme: str, params: ParameterSet, spikes: np.ndarray, duration_ms: float, dt_ms: float,
              n_units: int = 1, record: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    """Wall time (s) of a fixed-step run of n_units units, each receiving ``spikes`` (ms)."""
    from neuron import h

    keep, targets, forces = _build(scheme, params, n_units)
    ncs = [h.NetCon(None, tg) for tg in targets]
    for nc in ncs:
        nc.weight[0] = 1.0
    fih = h.FInitializeHandler(1, lambda: [nc.event(float(t)) for nc in ncs for t in spikes])
    tv, fv = h.Vector(), h.Vector()
    if record:
        tv.record(h._ref_t, dt_ms)
        fv.record(forces[0]._ref_F, dt_ms)
    with _NeuronRun("fixed", dt_ms, 0.0, 0.0) as hh:
        hh.finitialize()
        pc = hh.ParallelContext()
        pc.set_maxstep(10.0)
        t0 = time.perf_counter()
        pc.psolve(duration_ms)
        wall = time.perf_counter() - t0
    if scheme == "published" and any(tg.overflow for tg in targets):
        raise NumericalError("KimPublished: spike history (10000) overflowed; shorten the benchmark")
    del fih, ncs, keep
    return wall, np.array(tv), np.array(fv)


def bench_unit(params: ParameterSet, duration_ms: float = 10_000.0, dt_ms: float = 0.025,
               repeats: int = 3, pool_units: int = 10, published_repeats: int = 1) -> dict[str, Any]:
    """Wall time (s) per simulated unit-second at 1 Hz and 100 Hz over duration_ms (ms), best of repeats,
    for this package's unit and for the authors' scheme (derivimplicit + spike-history loop), measured for
    one unit alone (NEURON's fixed per-step cost included) and per unit in a pool of pool_units units on one
    section; plus both schemes' twitch errors (%) at dt_ms against the SciPy reference.  The authors' scheme
    is timed published_repeats times (it is 4-100x slower, so its noise matters less)."""
    load_mechanisms()
    out: dict[str, Any] = {"duration_ms": duration_ms, "dt_ms": dt_ms, "repeats": repeats,
                           "pool_units": pool_units, "parameter_set": params.name}
    unit_seconds = duration_ms / 1000.0
    for label, n in (("single", 1), ("pool", pool_units)):
        for rate in (1, 100):
            spikes = constant_rate(rate, duration_ms, start_ms=0.0)
            for scheme, reps in (("ours", repeats), ("published", published_repeats)):
                best = min(_time_run(scheme, params, spikes, duration_ms, dt_ms, n)[0] for _ in range(reps))
                out[f"{label}_{scheme}_s_per_unit_s_{rate}hz"] = best / (unit_seconds * n)
            out[f"{label}_speedup_{rate}hz"] = (out[f"{label}_published_s_per_unit_s_{rate}hz"]
                                                / out[f"{label}_ours_s_per_unit_s_{rate}hz"])
        out[f"{label}_ours_100hz_over_1hz"] = (out[f"{label}_ours_s_per_unit_s_100hz"]
                                               / out[f"{label}_ours_s_per_unit_s_1hz"])
    from .reference import reference_simulate

    ref = reference_simulate(params, np.array([500.0]), params["g1"], 750.0)
    m_ref = twitch_metrics(ref.t_ms, ref.force_N, 500.0)
    for scheme in ("ours", "published"):
        _, t, f = _time_run(scheme, params, np.array([500.0]), 750.0, dt_ms, 1, record=True)
        m = twitch_metrics(t, f, 500.0)
        out[f"{scheme}_twitch_peak_error_pct"] = 100 * abs(m.peak_N / m_ref.peak_N - 1)
        out[f"{scheme}_twitch_ttp_error_pct"] = 100 * abs(m.time_to_peak_ms / m_ref.time_to_peak_ms - 1)
        out[f"{scheme}_twitch_half_relaxation_error_pct"] = 100 * abs(
            m.half_relaxation_ms / m_ref.half_relaxation_ms - 1)
    return out


def synthetic_module2_set(params: ParameterSet, noise_N: float = 0.02, seed: int = 0) -> list:
    """The standard synthetic calibration set: a twitch and 10/20/40 Hz 0.5 s trains at the optimum (g1),
    1 ms samples over 0.9 s, simulated with ``params`` plus Gaussian noise (sd noise_N, N) from ``seed``."""
    from .fit import trial_simulation
    from .measured import Trial

    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 0.9, 0.001)
    trials = []
    for tid, stims in (("twitch", [0.05]), ("train10", np.arange(0.05, 0.55, 0.1)),
                       ("train20", np.arange(0.05, 0.55, 0.05)), ("train40", np.arange(0.05, 0.55, 0.025))):
        tr = Trial(trial_id=tid, protocol="twitch" if tid == "twitch" else "train", time_s=t,
                   force=np.zeros_like(t), force_unit="N", length_unit="mm", length_const=params["g1"],
                   stimulus_times_s=np.asarray(stims, dtype=float))
        f = trial_simulation(params, tr, 0.05, settle_ms=300.0)
        tr.force = f + rng.normal(0.0, noise_N, f.size)
        trials.append(tr)
    return trials


def bench_fit(params: ParameterSet, free: tuple[str, ...] = ("C1", "C2", "C3", "alpha"),
              start_factor: float = 1.25, workers: tuple[int, ...] = (1, 2)) -> dict[str, Any]:
    """Module 2 calibration on ``synthetic_module2_set``: wall time (s) and simulations, serial and in
    parallel, starting every free parameter at start_factor times its true value; checks that the parallel
    estimates equal the serial ones."""
    from .fit import FitProblem, SimulationOptions, fit

    trials = synthetic_module2_set(params)
    problem = FitProblem(trials, params, list(free), start={n: params[n] * start_factor for n in free},
                         options=SimulationOptions(dt_ms=0.05, settle_ms=300.0))
    out: dict[str, Any] = {"parameter_set": params.name, "free": list(free), "start_factor": start_factor,
                           "trials": [tr.trial_id for tr in trials]}
    estimates = {}
    for w in workers:
        res = fit(problem, workers=w, progress=False)
        out[f"workers_{w}_wall_s"] = res.wall_time_s
        out[f"workers_{w}_simulations"] = res.n_simulations
        out[f"workers_{w}_iterations"] = res.n_iterations
        estimates[w] = res.estimates
        out[f"workers_{w}_relative_error"] = {n: res.estimates[n] / params[n] - 1 for n in free}
    out["parallel_equals_serial"] = all(estimates[w] == estimates[workers[0]] for w in workers)
    return out
