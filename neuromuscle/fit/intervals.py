"""How a fit's 95 % intervals are made (``fit(..., intervals=)``), on the shared vocabulary of :mod:`.uncertainty`.

* ``"hac+integrator"`` (default): a HAC covariance of the residuals, trial by trial (autocorrelated transducer
  noise; trials whose residuals differ in variance, as under the NRMSE objective), widened by the fixed-step
  integrator's own error.  That error is estimated by re-running the fitted model at half the step: the scheme
  is first order (README, Numerics), so F_dt - F_exact ~ 2 (F_dt - F_dt/2) (Richardson); its effect on the
  estimates is ``Uncertainty.numerical_bias``.  One extra simulation of every trial at dt/2.
* ``"hac"``: the HAC covariance alone.
* ``"iid"``: s^2 (J^T J)^-1, the textbook intervals: right only for independent noise of one variance
  and data from the fit's own integrator (too narrow otherwise, see docs/validation/intervals.md).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Sequence

import numpy as np

from ..errors import InputError
from .evaluate import SimulationOptions
from .problem import FitProblem
from .uncertainty import Rules, Uncertainty, estimate_uncertainty

INTERVAL_METHODS = ("hac+integrator", "hac", "iid")


#: simulate(z, options) -> every trial's force (N): how the half-step re-run is made (default
#: ``FitProblem.simulate_trials``, in this process; ``fit`` passes its worker pool's).
Simulate = Callable[[np.ndarray, SimulationOptions], Sequence[np.ndarray]]


def integrator_error(problem: FitProblem, z: np.ndarray, sims: Sequence[np.ndarray],
                     simulate: Simulate | None = None) -> np.ndarray:
    """The estimated error of the fixed-step residuals at z (residual units, :mod:`.objectives`):
    2 (r_dt - r_dt/2), from ``sims`` (N, the trials simulated at z with the problem's options) and a re-run
    at half the step."""
    half = replace(problem.options, dt_ms=problem.options.dt_ms / 2.0)
    rerun = (simulate or problem.simulate_trials)(z, half)
    return 2.0 * (problem.residuals_from(sims) - problem.residuals_from(rerun))


def fit_uncertainty(problem: FitProblem, z: np.ndarray, jac: np.ndarray, sims: Sequence[np.ndarray],
                    intervals: str = INTERVAL_METHODS[0], rules: Rules | None = None,
                    simulate: Simulate | None = None) -> Uncertainty:
    """The :class:`Uncertainty` of ``problem``'s estimate z from the Jacobian ``jac`` (dr/dz) and the simulated
    forces ``sims`` (N) at z, by the interval method ``intervals`` (module docstring); rules: default
    ``Rules.for_fit()``; simulate: how the half-step re-run is made (:data:`Simulate`)."""
    if intervals not in INTERVAL_METHODS:
        raise InputError(f"intervals must be one of {INTERVAL_METHODS}, got {intervals!r}")
    covariance, _, extra = intervals.partition("+")
    r = problem.residuals_from(sims)
    error = integrator_error(problem, z, sims, simulate) if extra else None

    def to_p(zz: np.ndarray) -> np.ndarray:
        return np.array(list(problem.to_values(zz).values()))

    return estimate_uncertainty(problem.free, z, jac, r, to_p, problem.dp_dz(z), rules or Rules.for_fit(),
                                covariance=covariance, segments=problem.segments, model_error=error)
