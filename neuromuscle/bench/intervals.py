"""``neuromuscle bench intervals``: do the fit's 95 % intervals hold the true values?  A coverage study.

Data as real data come: the standard Module 2 set (:func:`.fit.module2_protocol`: twitch, 10/20/40 Hz at the
optimum, 1 kHz) made by the independent SciPy reference integration (:mod:`neuromuscle.reference`, not the
NEURON scheme the fit uses), once per true parameter set, plus in every draw autocorrelated noise as force
transducers give: AR(1) with correlation time ``tau_ms`` (ms) and marginal sd ``noise_N`` (N), seeded.  Each draw
is fitted as the README does (free C1, C2, C3, alpha from the base set; NRMSE; dt 0.05 ms, recording every
0.5 ms, 300 ms settling) and its intervals are made by every method of ``INTERVAL_METHODS`` from that one fit,
so the methods are compared on the same draws.  Reported per method and parameter: coverage (fraction of
draws whose interval holds the truth, with its exact binomial 95 % range), median half-width (% of the truth),
and the SE's honesty (mean SE / SD of the estimates over draws); per parameter, the bias (mean relative error,
%, with its SE over draws).

``data="example"`` replaces the reference set by the protocols of the package's example file, made the way it
is made (NEURON at dt 0.025 ms, :mod:`neuromuscle.measured.example`; base set ``example.BASE``): does a fit of
that file hold the truth as often as it should?
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import time
from dataclasses import replace
from typing import Any, Mapping, Sequence

import numpy as np
from scipy.stats import binomtest

from ..errors import InputError
from ..measured.simulation import ar1_noise
from ..measured import Trial
from ..parameters import ParameterSet
from .fit import MODULE2_SETTLE_MS, module2_protocol

FREE = ("C1", "C2", "C3", "alpha")
DATASETS = {"reference": "SciPy reference integration (neuromuscle.reference) of the standard Module 2 set, 1 kHz",
            "example": "the example file's protocols as it is made (NEURON, dt 0.025 ms), 1 kHz"}
DT_MS = 0.05
RECORD_DT_MS = 0.5


def reference_module2_set(params: ParameterSet) -> list[Trial]:
    """The standard Module 2 set at the optimum (g1), noise-free, by the SciPy reference integration at the
    trials' own samples (forces in N, after MODULE2_SETTLE_MS of settling)."""
    from ..reference import reference_simulate

    time_s, protocol = module2_protocol()
    sample_ms = 1000.0 * float(time_s[1] - time_s[0])
    t_ms = MODULE2_SETTLE_MS + 1000.0 * time_s
    trials = []
    for tid, stims in protocol:
        ref = reference_simulate(params, MODULE2_SETTLE_MS + 1000.0 * stims, params["g1"], float(t_ms[-1]),
                                 record_dt_ms=sample_ms)
        trials.append(Trial(trial_id=tid, protocol="twitch" if tid == "twitch" else "train", time_s=time_s,
                            force=np.interp(t_ms, ref.t_ms, ref.force_N), force_unit="N", length_unit="mm",
                            length_const=params["g1"], stimulus_times_s=stims))
    return trials


def fit_draw(base: ParameterSet, clean: Sequence[Trial], draw: int, seed: int, noise_N: float, tau_ms: float,
             objective: str) -> dict[str, Any]:
    """One draw: noise (seeded by (seed, draw)) on the noise-free trials ``clean``, the README's fit from
    ``base``, and the intervals of every interval method from that fit."""
    from ..fit import INTERVAL_METHODS, FitProblem, SimulationOptions, fit, fit_uncertainty

    rng = np.random.default_rng([seed, draw])
    trials = [replace(t, force=t.force + ar1_noise(t.n_samples, noise_N, tau_ms,
                                                   1000.0 * float(t.time_s[1] - t.time_s[0]), rng))
              for t in clean]
    options = SimulationOptions(dt_ms=DT_MS, record_dt_ms=RECORD_DT_MS, settle_ms=MODULE2_SETTLE_MS)
    problem = FitProblem(trials, base, list(FREE), objective=objective, options=options)
    res = fit(problem, progress=False, max_iterations=30)
    sims = [res.simulated[t.trial_id] for t in trials]
    out: dict[str, Any] = {"draw": draw, "estimates": res.estimates, "message": res.message,
                           "iterations": res.n_iterations, "wall_s": res.wall_time_s}
    for m in INTERVAL_METHODS:
        u = res.uncertainty if m == res.interval_method else fit_uncertainty(problem, res.z, res.jacobian, sims, m)
        out[m] = {"ci95": u.ci95, "se": u.std_errors, "numerical_bias": u.numerical_bias}
    return out


def _fit_draw_star(args: tuple) -> dict[str, Any]:
    return fit_draw(*args)


def noise_free_trials(base: ParameterSet, true_values: Mapping[str, float], data: str) -> list[Trial]:
    """The noise-free trials of ``data`` (a key of ``DATASETS``) made with ``base`` moved to ``true_values``."""
    if data == "reference":
        return reference_module2_set(base.with_values(**dict(true_values)))
    from ..measured import example

    if data != "example" or base.name != example.BASE:
        raise InputError(f"data must be one of {list(DATASETS)} ('example' with base {example.BASE}), got "
                         f"{data!r} with base {base.name}")
    return list(example.example_data(true_values, noise_N=0.0).trials.values())


def coverage_study(base: ParameterSet, true_values: Mapping[str, float], draws: int = 8, workers: int = 2,
                   noise_N: float = 0.02, tau_ms: float = 10.0, seed: int = 0, objective: str = "nrmse",
                   data: str = "reference") -> dict[str, Any]:
    """``draws`` fits of ``data`` (``DATASETS``) made with ``base`` moved to ``true_values`` plus AR(1) noise
    (noise_N, N; tau_ms, ms), ``workers`` draws at a time; the coverage, half-width and bias of each interval
    method (module docstring) and every draw's numbers."""
    from ..fit import INTERVAL_METHODS

    truth = base.with_values(**dict(true_values))
    t0 = time.perf_counter()
    clean = noise_free_trials(base, true_values, data)
    data_s = time.perf_counter() - t0
    jobs = [(base, clean, d, seed, noise_N, tau_ms, objective) for d in range(draws)]
    if workers > 1:
        with concurrent.futures.ProcessPoolExecutor(
                workers, mp_context=multiprocessing.get_context("spawn")) as pool:
            results = list(pool.map(_fit_draw_star, jobs))
    else:
        results = [_fit_draw_star(j) for j in jobs]
    true = {n: float(truth[n]) for n in FREE}
    est = np.array([[r["estimates"][n] for n in FREE] for r in results])
    rel = 100.0 * (est / np.array([true[n] for n in FREE]) - 1.0)
    summary: dict[str, Any] = {m: _method_summary([r[m] for r in results], true, est) for m in INTERVAL_METHODS}
    return {
        "base_parameters": base.name, "true_values": true, "free": list(FREE), "objective": objective,
        "data": DATASETS[data],
        "noise": {"kind": "AR(1)", "sd_N": noise_N, "correlation_time_ms": tau_ms, "seed": seed},
        "fit": {"dt_ms": DT_MS, "record_dt_ms": RECORD_DT_MS, "settle_ms": MODULE2_SETTLE_MS,
                "start": {n: float(base[n]) for n in FREE}},
        "draws": draws, "workers": workers,
        "bias_percent": {n: float(np.mean(rel[:, i])) for i, n in enumerate(FREE)},
        "bias_se_percent": {n: float(np.std(rel[:, i], ddof=1) / np.sqrt(draws)) if draws > 1 else float("nan")
                            for i, n in enumerate(FREE)},
        "sd_percent": {n: float(np.std(rel[:, i], ddof=1)) if draws > 1 else float("nan")
                       for i, n in enumerate(FREE)},
        "methods": summary, "data_s": data_s, "wall_s": time.perf_counter() - t0,
        "per_draw": results,
    }


def _method_summary(draws: list[dict[str, Any]], true: dict[str, float], est: np.ndarray) -> dict[str, Any]:
    """Coverage (with its exact binomial 95 % range), median half-width (% of truth) and mean SE / SD of the
    estimates, per parameter, of one interval method over the draws."""
    out: dict[str, Any] = {"coverage": {}, "coverage_range": {}, "median_half_width_percent": {},
                           "mean_se_over_sd": {}}
    for i, n in enumerate(true):
        held = sum(d["ci95"][n][0] <= true[n] <= d["ci95"][n][1] for d in draws)
        ci = binomtest(held, len(draws)).proportion_ci(0.95)
        half = [50.0 * (d["ci95"][n][1] - d["ci95"][n][0]) / abs(true[n]) for d in draws]
        sd = float(np.std(est[:, i], ddof=1)) if len(draws) > 1 else float("nan")
        out["coverage"][n] = held / len(draws)
        out["coverage_range"][n] = [float(ci.low), float(ci.high)]
        out["median_half_width_percent"][n] = float(np.median(half))
        out["mean_se_over_sd"][n] = float(np.mean([d["se"][n] for d in draws])) / sd if sd > 0 else float("nan")
    return out


def coverage_lines(res: dict[str, Any]) -> list[str]:
    """The study as text: one line per interval method and parameter."""
    noise = res["noise"]
    lines = [f"{res['draws']} draws, AR(1) noise sd {noise['sd_N']} N, correlation time "
             f"{noise['correlation_time_ms']} ms, objective {res['objective']}, {res['wall_s']:.0f} s",
             f"data: {res['data']}",
             f"{'method':16s} {'param':6s} {'coverage':>8s} {'(95 % range)':>14s} {'half-width %':>12s} "
             f"{'SE/SD':>6s} {'bias %':>7s}"]
    for m, s in res["methods"].items():
        for n in res["free"]:
            lo, hi = s["coverage_range"][n]
            lines.append(f"{m:16s} {n:6s} {s['coverage'][n]:8.2f} {f'({lo:.2f}-{hi:.2f})':>14s} "
                         f"{s['median_half_width_percent'][n]:12.3f} {s['mean_se_over_sd'][n]:6.2f} "
                         f"{res['bias_percent'][n]:7.3f}")
    return lines
