"""``neuromuscle bench fit``: the Module 2 calibration on a standard synthetic set, serial and in parallel."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..parameters import ParameterSet


#: Settling time (ms) before the standard set's trials, in making them and in fitting them.
MODULE2_SETTLE_MS = 300.0


def module2_protocol() -> tuple[np.ndarray, list[tuple[str, np.ndarray]]]:
    """The standard calibration set's sample times (s: 1 ms over 0.9 s) and its trials: id and stimulus times
    (s) of a twitch and 10/20/40 Hz 0.5 s trains."""
    return np.arange(0.0, 0.9, 0.001), [
        ("twitch", np.array([0.05])), ("train10", np.arange(0.05, 0.55, 0.1)),
        ("train20", np.arange(0.05, 0.55, 0.05)), ("train40", np.arange(0.05, 0.55, 0.025))]


def synthetic_module2_set(params: ParameterSet, noise_N: float = 0.02, seed: int = 0) -> list:
    """The standard synthetic calibration set (:func:`module2_protocol`) at the optimum (g1), simulated with
    ``params`` plus Gaussian noise (sd noise_N, N) from ``seed``."""
    from ..fit import synthetic_trial

    rng = np.random.default_rng(seed)
    t, trials = module2_protocol()
    return [synthetic_trial(params, tid, t, stims, protocol="twitch" if tid == "twitch" else "train",
                            length_mm=params["g1"], noise_N=noise_N, rng=rng, settle_ms=MODULE2_SETTLE_MS)
            for tid, stims in trials]


def bench_fit(params: ParameterSet, free: tuple[str, ...] = ("C1", "C2", "C3", "alpha"),
              start_factor: float = 1.25, workers: tuple[int, ...] = (1, 2)) -> dict[str, Any]:
    """Module 2 calibration on ``synthetic_module2_set``: wall time (s) and simulations, serial and in
    parallel, starting every free parameter at start_factor times its true value; checks that the parallel
    estimates equal the serial ones."""
    from ..fit import FitProblem, SimulationOptions, fit

    trials = synthetic_module2_set(params)
    problem = FitProblem(trials, params, list(free), start={n: params[n] * start_factor for n in free},
                         options=SimulationOptions(dt_ms=0.05, settle_ms=MODULE2_SETTLE_MS))
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
