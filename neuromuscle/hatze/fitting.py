"""Fit of theta1..theta5 to one isometric twitch (seed 000, 2.3.2, eq 5) and prediction of tetanic trains.

Objective (eq 5): Phi(theta) = sum_i (M_exp(t_i) - M_cal(theta, t_i))^2, moments in N m.

Method. Levenberg-Marquardt (``levenberg_marquardt``: Marquardt scaling, QR steps, step length capped) in log-parameters
p_k = ln theta_k, which keeps theta > 0 and balances parameters spanning 1e4 to 1e15. The Jacobian is
dM/dp_k = theta_k dM/dtheta_k from the sensitivity equations integrated alongside the model: exact matrix
exponentials for d(beta, gamma)/dtheta_1..4 (``excitation.excitation_states``) and the variational equation
of the CE angle (``contraction.integrate_mtc``) for theta_1..5; no finite differences.

Confidence intervals (95 %) come from the Jacobian J (in p) at the optimum: cov(p) = s^2 (J^T J)^-1 with
s^2 = Phi/(n - 5), half-width t_{0.975, n-5} sqrt(cov_kk); the interval exp(p_k +/- half-width) is asymmetric
in theta (the seed's intervals are asymmetric too). These intervals measure noise; how well the *data* can
separate the parameters at all is measured by the variance inflation factor VIF_k = [C^-1]_kk, where C is the
correlation-scaled J^T J (VIF = 1 for an orthogonal design). A parameter is flagged poorly identified when its
interval spans more than ``ci_factor_limit`` (upper/lower) or VIF_k > ``vif_limit``.

Identifiability (a finding, see tests/test_hatze_fit.py). The twitch depends on theta only through theta5 times
the impulse response of 1/((s^2 + theta1 s + theta2)(s^2 + theta3 s + theta4)). With Table 2's values the roots
are -3.5e5, -15.94 (eq 6) and -1.85e4, -15.80 1/s (eq 7): the fast roots act as delays of ~3 us and ~54 us, and
the two slow roots are nearly equal. Any re-pairing of the four roots into two quadratics gives exactly the same
twitch, so theta is at best locally identifiable. At Table 2, the singular values of dM/d ln theta for a 1 kHz,
0.8-1 s twitch of subject 3 are about 258, 122, 0.20, 0.011 and 3e-8 N m: the mean slow rate and the gain
theta5/(theta2 theta4) are well determined; the split of the slow roots (it enters squared) and the fast root of
eq 7 are lost in noise of a few 0.01 N m; the fast root of eq 6 (theta1 with theta2 and theta5 scaled along) is
not determined even by noise-free data (a factor 1.4 changes the twitch by < 1e-9 N m). Fixing theta1
(``frozen=("theta1",)``) makes noise-free fits converge to Table 2 (or its slow-root-swapped twin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.stats import t as student_t

from ..errors import InputError, NumericalError
from .contraction import (DEFAULT_STEP_S, TEST_JOINT_ANGLE_RAD, IsometricTrace, simulate_isometric,
                          simulate_isometric_solution)
from .excitation import check_stim_times, train_times
from .parameters import THETA_NAMES, ActiveStateConstants, ExcitationTheta, Subject

_DEFAULT_CONSTANTS = ActiveStateConstants()
#: Stimulation rates of the seed's trains (Fig 7-8), Hz.
SEED_TRAIN_RATES_HZ: tuple[float, ...] = (4.0, 8.0, 12.0, 16.0, 24.0)


@dataclass(frozen=True)
class TwitchFit:
    """Result of ``fit_twitch``.

    ``theta``: estimates; ``lower``/``upper``: 95 % intervals (units of ``parameters.THETA_UNITS``);
    ``poorly_identified``: per-parameter flag; ``vif``: variance inflation factors; ``correlation``: 5x5
    correlation matrix of ln theta; ``rms_nm``: residual RMS (N m); ``n_evaluations``; ``message`` (why the
    iteration stopped); ``frozen``: parameters held fixed.
    """

    theta: ExcitationTheta
    lower: Mapping[str, float]
    upper: Mapping[str, float]
    poorly_identified: Mapping[str, bool]
    vif: Mapping[str, float]
    correlation: NDArray[np.float64]
    rms_nm: float
    n_evaluations: int
    message: str
    frozen: tuple[str, ...] = ()


def _node_indices(t_s: NDArray[np.float64], step_s: float) -> NDArray[np.int64]:
    idx = np.rint(t_s / step_s).astype(np.int64)
    if np.any(np.abs(idx * step_s - t_s) > 1e-6 * step_s) or np.any(idx < 0):
        raise InputError(f"t_s: sample times must be non-negative multiples of step_s = {step_s} s "
                         "(choose step_s dividing the sampling interval)")
    return idx


def _check_data(t_s: ArrayLike, moment_nm: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    t = np.asarray(t_s, dtype=float).ravel()
    m = np.asarray(moment_nm, dtype=float).ravel()
    if t.size != m.size:
        raise InputError(f"t_s and moment_nm differ in length ({t.size} vs {m.size})")
    if t.size < 6:
        raise InputError(f"moment_nm: need at least 6 samples to fit 5 parameters, got {m.size}")
    if not np.all(np.isfinite(t)):
        raise InputError("t_s contains non-finite values")
    if not np.all(np.isfinite(m)):
        raise InputError("moment_nm contains non-finite values")
    if np.any(np.diff(t) <= 0.0):
        raise InputError("t_s must increase strictly")
    return t, m


def twitch_moment(t_s: ArrayLike, stim_times_s: ArrayLike, subject: Subject, theta: ExcitationTheta,
                  step_s: float = DEFAULT_STEP_S, joint_angle_rad: float = TEST_JOINT_ANGLE_RAD,
                  sensitivities: bool = False, constants: ActiveStateConstants = _DEFAULT_CONSTANTS
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Model moment (N m) at the sample times ``t_s`` (s, multiples of ``step_s``) and, optionally, dM/dtheta_k
    (N m per unit of theta_k, shape (n, 5)) from the sensitivity equations."""
    t = np.asarray(t_s, dtype=float).ravel()
    idx = _node_indices(t, step_s)
    t_end = float(idx.max()) * step_s
    sol = simulate_isometric_solution(stim_times_s, t_end, subject, theta, joint_angle_rad, step_s,
                                      sensitivities, True, constants)
    dm = sol.dmoment_dtheta[idx] if sensitivities else None  # type: ignore[index]
    return sol.moment_nm[idx], dm


def _identification(jac: NDArray[np.float64], resid: NDArray[np.float64]
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Half-widths (in ln theta) of the 95 % intervals, VIFs and the correlation matrix."""
    n, p = jac.shape
    dof = max(n - p, 1)
    s2 = float(resid @ resid) / dof
    jtj = jac.T @ jac
    norms = np.sqrt(np.diag(jtj))
    if np.any(norms == 0.0):
        raise NumericalError("a parameter has no influence on the moment (zero Jacobian column)")
    c = jtj / np.outer(norms, norms)
    c_inv = np.linalg.pinv(c, rcond=1e-15)
    cov = s2 * c_inv / np.outer(norms, norms)
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    corr = cov / np.outer(sd, sd) if np.all(sd > 0) else np.eye(p)
    half = float(student_t.ppf(0.975, dof)) * sd
    return half, np.diag(c_inv).copy(), corr


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


def fit_twitch(t_s: ArrayLike, moment_nm: ArrayLike, stim_times_s: ArrayLike, subject: Subject,
               theta_start: ExcitationTheta, step_s: float = DEFAULT_STEP_S,
               joint_angle_rad: float = TEST_JOINT_ANGLE_RAD, frozen: Sequence[str] = (),
               max_evaluations: int = 200, ci_factor_limit: float = 4.0, vif_limit: float = 1e4,
               constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> TwitchFit:
    """Fit theta1..theta5 to an isometric twitch: moment ``moment_nm`` (N m) sampled at ``t_s`` (s).

    ``stim_times_s``: the stimulus onset(s) (s); ``subject``: contraction parameters (Table 1); ``theta_start``:
    initial guess; ``frozen``: names of parameters kept at their ``theta_start`` value (their interval is the
    value itself, VIF nan, never flagged); ``step_s`` (s) must divide the sampling interval.
    Levenberg-Marquardt in ln theta with the sensitivity-equation Jacobian (module docstring).
    """
    t, m_exp = _check_data(t_s, moment_nm)
    check_stim_times(stim_times_s, float(t[-1]) + step_s)
    if not isinstance(theta_start, ExcitationTheta):
        raise InputError(f"theta_start must be an ExcitationTheta, got {type(theta_start).__name__}")
    if isinstance(frozen, str):
        frozen = (frozen,)
    bad = [n for n in frozen if n not in THETA_NAMES]
    if bad:
        raise InputError(f"frozen: unknown parameter(s) {', '.join(map(repr, bad))} (known: {', '.join(THETA_NAMES)})")
    free = np.array([n not in frozen for n in THETA_NAMES])
    if not free.any():
        raise InputError("frozen: all five parameters frozen, nothing to fit")
    _node_indices(t, step_s)
    p_full0 = np.log(theta_start.as_array())
    last: dict[str, object] = {}

    def full(p: NDArray[np.float64]) -> NDArray[np.float64]:
        out = p_full0.copy()
        out[free] = p
        return out

    def evaluate(p: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        key = p.tobytes()
        if last.get("key") != key:
            pf = full(p)
            theta = ExcitationTheta.from_array(np.exp(pf))
            mod, dm = twitch_moment(t, stim_times_s, subject, theta, step_s, joint_angle_rad, True, constants)
            last.update(key=key, r=mod - m_exp, j=(dm * np.exp(pf)[None, :])[:, free])  # type: ignore[index]
        return last["r"], last["j"]  # type: ignore[return-value]

    sol = levenberg_marquardt(evaluate, p_full0[free], max_evaluations)
    r, jac = evaluate(sol.x)
    half_f, vif_f, corr_f = _identification(jac, r)
    p_est = full(sol.x)
    half = np.zeros(5)
    vif = np.full(5, np.nan)
    corr = np.full((5, 5), np.nan)
    half[free], vif[free] = half_f, vif_f
    corr[np.ix_(free, free)] = corr_f
    est = np.exp(p_est)
    est[~free] = theta_start.as_array()[~free]          # frozen values exactly as given
    lo, hi = np.where(free, np.exp(p_est - half), est), np.where(free, np.exp(p_est + half), est)
    names = THETA_NAMES
    flags = {n: bool(free[k] and (hi[k] / lo[k] > ci_factor_limit or vif[k] > vif_limit))
             for k, n in enumerate(names)}
    return TwitchFit(ExcitationTheta.from_array(est), dict(zip(names, lo)), dict(zip(names, hi)), flags,
                     dict(zip(names, vif)), corr, math.sqrt(float(r @ r) / r.size), sol.n_evaluations,
                     sol.message, tuple(n for n in names if n in frozen))


@dataclass(frozen=True)
class TrainPrediction:
    """Isometric response to a regular train: ``rate_hz`` (Hz), ``trace`` and its ``peak_moment_nm`` (N m)."""

    rate_hz: float
    trace: IsometricTrace
    peak_moment_nm: float


def predict_trains(theta: ExcitationTheta, subject: Subject, rates_hz: Sequence[float] = SEED_TRAIN_RATES_HZ,
                   duration_s: float = 1.0, t_end_s: float = 1.5, step_s: float = DEFAULT_STEP_S,
                   joint_angle_rad: float = TEST_JOINT_ANGLE_RAD) -> list[TrainPrediction]:
    """Isometric moment for trains of ``duration_s`` (s) at each rate (Hz), first stimulus at t = 0 (seed 3.2)."""
    out = []
    for rate in rates_hz:
        tr = simulate_isometric(train_times(rate, duration_s), t_end_s, subject, theta, joint_angle_rad, step_s)
        out.append(TrainPrediction(float(rate), tr, float(tr.moment_nm.max())))
    return out
