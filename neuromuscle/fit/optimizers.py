"""Optimisers of a sum of squared residuals: scipy's trust-region least squares with a finite-difference
Jacobian, NEURON's PRAXIS (the optimiser of Kim et al. 2015), and Levenberg-Marquardt with an analytic Jacobian.

* **Finite-difference Jacobian** (:func:`fd_jacobian`): central differences in z (step h, default 1e-3, i.e.
  0.1 % for log parameters; one-sided at a bound; ``fd="forward"`` halves the cost).  All candidates of one
  Jacobian go through one call of ``run_all`` in a fixed order.
* **Levenberg-Marquardt** (:func:`levenberg_marquardt`): for models whose Jacobian comes with the residuals
  (e.g. from sensitivity equations, the Hatze twitch fit); no finite differences.

``run_all(zs)`` evaluates a list of search vectors and returns their residual vectors; ``monitor`` (a
:class:`Monitor`, e.g. :class:`.checkpoint.Tracker`) is told of each iteration and keeps the best point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, NumericalError

RunAll = Callable[[list[np.ndarray]], list[np.ndarray]]


class Monitor(Protocol):
    """What the optimisers report to and read from: the best evaluated point and the end of each iteration."""

    best_z: np.ndarray | None
    best_cost: float

    def iteration(self, z: np.ndarray, cost: float) -> None: ...


def fd_jacobian(z: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: RunAll, fd: str, h: float,
                r0: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Finite-difference Jacobian of the residuals in z (central, one-sided at a bound); also r(z).

    All candidates go through one run_all call, in the order [z (if r0 is None), then per parameter +h, -h]."""
    k = z.size
    plan: list[tuple[int, float, float]] = []  # (index, step up, step down) (down = 0: one-sided)
    for i in range(k):
        up = h if z[i] + h <= hi[i] else -h
        if fd == "central" and z[i] - h >= lo[i] and z[i] + h <= hi[i]:
            plan.append((i, h, -h))
        else:
            plan.append((i, up, 0.0))
    zs: list[np.ndarray] = [] if r0 is not None else [z.copy()]
    for i, a, b in plan:
        for step in (a, b) if b != 0.0 else (a,):
            zz = z.copy()
            zz[i] += step
            zs.append(zz)
    rs = run_all(zs)
    if r0 is None:
        r0, rs = rs[0], rs[1:]
    jac = np.empty((r0.size, k))
    pos = 0
    for i, a, b in plan:
        if b != 0.0:
            jac[:, i] = (rs[pos] - rs[pos + 1]) / (a - b)
            pos += 2
        else:
            jac[:, i] = (rs[pos] - r0) / a
            pos += 1
    if not np.all(np.isfinite(jac)):
        raise NumericalError("the Jacobian has non-finite entries: a candidate simulation failed near "
                             "the current parameters")
    return jac, r0


class _IterationLimit(Exception):
    """Raised inside the optimiser's Jacobian callback when the iteration budget of this run is spent."""


class _CostSettled(Exception):
    """Raised inside the optimiser's Jacobian callback when the last iterations lowered the cost by less than the
    absolute cost tolerance."""

    def __init__(self, z: np.ndarray) -> None:
        super().__init__()
        self.z = z


#: Iterations over which an absolute cost tolerance is measured.
COST_WINDOW = 3
#: A start on a bound is moved 1e-10 of its range inside (trf keeps its iterates strictly inside), and a fit that
#: continues from another's estimate often starts that close to one.  scipy's trf sizes its first trust region by
#: the start's distance to the bounds, about 2e-5 in z from there, and can then meet its tolerances at once: a fit
#: that started within RESTART_MARGIN of its range of a bound and ends converged having moved no coordinate by
#: more than that is run again from a start RESTART_MARGIN of the range inside, whose first trust region (about
#: 0.07 in z) is of the problem's scale.  A fit that moved keeps its result.
RESTART_MARGIN = 1e-3


def trust_region_least_squares(z0: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: RunAll,
                               monitor: Monitor, fd: str, h: float, max_iterations: int,
                               tol: float, jacobian_run_all: RunAll | None = None,
                               cost_tol: float | None = None
                               ) -> tuple[np.ndarray, str, tuple[np.ndarray, np.ndarray] | None]:
    """scipy's trust-region reflective least squares in z within [lo, hi], Jacobian by :func:`fd_jacobian`;
    tol is scipy's ftol/xtol/gtol; returns z, a message and (J, r) at z if known.  One iteration = one
    Jacobian; after ``max_iterations`` the monitor's best point is returned.  cost_tol: also stop, converged, at
    an iterate where the last ``COST_WINDOW`` iterations together lowered the cost |r|^2 by less than this
    (absolute: a chi-square for residuals weighted by 1/sd); scipy's relative ftol alone lets a fit crawl along a
    flat valley for many iterations, each lowering the cost by a part in 10^4 that no decision can see.
    jacobian_run_all: evaluates the Jacobian's candidates and its own base point (e.g. simulations at a coarser
    step, whose error cancels in the differences); the residuals minimised, the monitor's best point and r at z
    stay ``run_all``'s."""
    from scipy.optimize import least_squares

    cache: dict[bytes, np.ndarray] = {}
    last: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
    done = [0]
    costs: list[float] = []

    def fun(z: np.ndarray) -> np.ndarray:
        key = np.asarray(z, dtype=float).tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = run_all([np.array(z, dtype=float)])[0]
        r = cache[key]
        return r if np.all(np.isfinite(r)) else np.full(r.size, 1e150)

    def jac(z: np.ndarray) -> np.ndarray:
        if done[0] >= max_iterations:
            raise _IterationLimit
        z = np.array(z, dtype=float)
        r0 = fun(z)
        if jacobian_run_all is None:
            j, _ = fd_jacobian(z, lo, hi, run_all, fd, h, r0)
        else:
            j, _ = fd_jacobian(z, lo, hi, jacobian_run_all, fd, h, None)
        last.clear()
        last[z.tobytes()] = (j, r0)
        done[0] += 1
        cost = float(r0 @ r0)
        monitor.iteration(z, cost)
        costs.append(cost)
        settled = len(costs) > COST_WINDOW and costs[-1 - COST_WINDOW] - cost < (cost_tol or 0.0)
        if cost_tol is not None and settled:
            raise _CostSettled(z)
        return j

    def solve(start: np.ndarray) -> tuple[np.ndarray, str]:
        sol = least_squares(fun, start, jac=jac, bounds=(lo, hi), method="trf", x_scale=1.0, ftol=tol, xtol=tol,
                            gtol=tol, max_nfev=max(10 * max_iterations, 50))
        return np.asarray(sol.x, dtype=float), str(sol.message)

    # trf keeps iterates strictly inside the bounds: a start on a bound is nudged inside
    z_in = np.clip(z0, lo + 1e-10 * (hi - lo), hi - 1e-10 * (hi - lo))
    near_bound = bool(np.any(np.minimum(z0 - lo, hi - z0) <= RESTART_MARGIN * (hi - lo)))
    try:
        z, message = solve(z_in)
        if near_bound and np.all(np.abs(z - z_in) <= RESTART_MARGIN * (hi - lo)):
            # stopped where it began (module constant RESTART_MARGIN): started again from inside
            costs.clear()
            z, message = solve(np.clip(z0, lo + RESTART_MARGIN * (hi - lo), hi - RESTART_MARGIN * (hi - lo)))
            message = f"{message} (started again {RESTART_MARGIN:g} of the range inside the bound it stopped by)"
    except _IterationLimit:
        z = monitor.best_z if monitor.best_z is not None else z_in
        message = f"stopped after max_iterations = {max_iterations} iterations (resume to continue)"
    except _CostSettled as settled:
        z = settled.z
        message = (f"the cost settled: the last {COST_WINDOW} iterations lowered it by "
                   f"{costs[-1 - COST_WINDOW] - costs[-1]:.3g} < {cost_tol:g}")
    return z, message, last.get(z.tobytes())


def praxis(z0: np.ndarray, lo: np.ndarray, hi: np.ndarray, run_all: RunAll, monitor: Monitor,
           max_iterations: int, tol: float) -> tuple[np.ndarray, str]:
    """NEURON's principal-axis method on cost(z) = |r(z)|^2 (tolerance tol in z); outside the bounds the cost is
    that of the clipped point plus a quadratic penalty.  Reproducible (fixed mcell_ran4 index).  Stops after
    max_iterations principal-axis rounds (2k+2 evaluations each)."""
    from neuron import h

    h.attr_praxis(1)
    h.attr_praxis(tol, 0.5, 0)
    n_eval = [0]
    per_round = max(2 * z0.size + 2, 4)

    def efun(v: Any) -> float:
        z = np.array([v[i] for i in range(int(v.size()))])
        zc = np.clip(z, lo, hi)
        r = run_all([zc])[0]
        c = float(r @ r) if np.all(np.isfinite(r)) else 1e300
        c *= 1.0 + 1e3 * float(np.sum((z - zc) ** 2))
        n_eval[0] += 1
        if n_eval[0] % per_round == 0:
            monitor.iteration(monitor.best_z if monitor.best_z is not None else zc, monitor.best_cost)
            if n_eval[0] // per_round >= max_iterations:
                h.stoprun = 1
        return c

    vec = h.Vector(list(map(float, z0)))
    h.stoprun = 0
    try:
        h.fit_praxis(efun, vec)
    finally:
        h.stoprun = 0
    z = np.clip(np.array([vec[i] for i in range(int(vec.size()))]), lo, hi)
    if monitor.best_z is not None and monitor.best_cost < float(np.sum(run_all([z])[0] ** 2)):
        z = monitor.best_z
    return z, f"praxis finished after {n_eval[0]} evaluations"


@dataclass(frozen=True)
class LMResult:
    """Outcome of ``levenberg_marquardt``: parameters ``x``, ``cost`` = 0.5 |r|^2, evaluations, message."""

    x: NDArray[np.float64]
    cost: float
    n_evaluations: int
    converged: bool
    message: str


def levenberg_marquardt(evaluate: Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]],
                        x0: ArrayLike, max_evaluations: int = 400, max_step: float = 1.0, xtol: float = 1e-12,
                        ftol: float = 1e-15) -> LMResult:
    """Minimise 0.5 |r(x)|^2 by Levenberg-Marquardt with Marquardt's scaling diag(J^T J).

    ``evaluate(x)`` returns residuals r and Jacobian J = dr/dx (e.g. from sensitivity equations). Each step
    solves [J; sqrt(lambda D)] dx = [-r; 0] by least squares (QR, no normal equations: J^T J may be
    ill-conditioned beyond 1e12), is shortened to |dx|_inf <= ``max_step`` and is accepted if it lowers the
    cost; lambda falls by 3 after a success and rises by 10 after a failure or a model error (NumericalError /
    InputError from a wild trial point). Stops when |dx|_inf < ``xtol``, the relative cost decrease of an
    accepted step is < ``ftol``, or the cost is 0.
    """
    x = np.asarray(x0, dtype=float).copy()
    r, jac = evaluate(x)
    cost = 0.5 * float(r @ r)
    n_eval, lam = 1, 1e-3
    while n_eval < max_evaluations:
        if cost == 0.0:
            return LMResult(x, cost, n_eval, True, "zero residual")
        d = np.maximum(np.sum(jac * jac, axis=0), 1e-300)
        aug = np.vstack([jac, np.diag(np.sqrt(lam * d))])
        rhs = np.concatenate([-r, np.zeros(x.size)])
        dx = np.linalg.lstsq(aug, rhs, rcond=None)[0]
        big = float(np.max(np.abs(dx)))
        if big > max_step:
            dx *= max_step / big
        if float(np.max(np.abs(dx))) < xtol:
            return LMResult(x, cost, n_eval, True, "step below xtol")
        try:
            r_new, j_new = evaluate(x + dx)
            n_eval += 1
            cost_new = 0.5 * float(r_new @ r_new)
            ok = math.isfinite(cost_new) and cost_new < cost
        except (NumericalError, InputError, FloatingPointError, OverflowError):
            n_eval += 1
            ok = False
        if ok:
            decrease = (cost - cost_new) / cost
            x, r, jac, cost = x + dx, r_new, j_new, cost_new
            lam = max(lam / 3.0, 1e-12)
            if decrease < ftol:
                return LMResult(x, cost, n_eval, True, "relative cost decrease below ftol")
        else:
            lam *= 10.0
            if lam > 1e16:
                return LMResult(x, cost, n_eval, True, "no further decrease (lambda > 1e16)")
    return LMResult(x, cost, n_eval, False, "maximum number of evaluations reached")
