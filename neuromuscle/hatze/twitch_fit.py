"""Fit of theta1..theta5 to one isometric twitch (van Zandwijk et al. 1998, section 2.3.2, eq 5) and prediction of
tetanic trains.

Objective (eq 5): Phi(theta) = sum_i (M_exp(t_i) - M_cal(theta, t_i))^2, moments in N m.

Method. Levenberg-Marquardt (``fit.optimizers.levenberg_marquardt``: Marquardt scaling, QR steps, step length
capped) in log-parameters p_k = ln theta_k, which keeps theta > 0 and balances parameters spanning 1e4 to 1e15. The
Jacobian is dM/dp_k = theta_k dM/dtheta_k from the sensitivity equations integrated alongside the model: exact
matrix exponentials for d(beta, gamma)/dtheta_1..4 (``excitation.excitation_states``) and the variational equation
of the CE angle (``contraction.integrate_mtc``) for theta_1..5; no finite differences.

Confidence intervals (95 %) come from the Jacobian J (in p) at the optimum (``fit.uncertainty``, the rules
``Rules.for_twitch_fit``): cov(p) = s^2 (J^T J)^-1 with s^2 = Phi/(n - k), half-width t_{0.975, n-k} sqrt(cov_kk);
the interval exp(p_k +/- half-width) is asymmetric in theta (the paper's intervals are asymmetric too). These
intervals measure noise; how well the *data* can separate the parameters at all is measured by the variance
inflation factor VIF_k = [C^-1]_kk, where C is the correlation-scaled J^T J (VIF = 1 for an orthogonal design).
A parameter is flagged poorly identified when its interval spans more than ``ci_factor_limit`` (upper/lower) or
VIF_k > ``vif_limit``.

Identifiability (a finding, see tests/hatze/test_hatze_twitch_fit.py). The twitch depends on theta only through
theta5 times the impulse response of 1/((s^2 + theta1 s + theta2)(s^2 + theta3 s + theta4)). With Table 2's values
the roots are -3.5e5, -15.94 (eq 6) and -1.85e4, -15.80 1/s (eq 7): the fast roots act as delays of ~3 us and ~54
us, and the two slow roots are nearly equal. Any re-pairing of the four roots into two quadratics gives exactly the
same twitch, so theta is at best locally identifiable. At Table 2, the singular values of dM/d ln theta for a 1 kHz,
0.8-1 s twitch of subject 3 are about 258, 122, 0.20, 0.011 and 3e-8 N m: the mean slow rate and the gain
theta5/(theta2 theta4) are well determined; the split of the slow roots (it enters squared) and the fast root of eq
7 are lost in noise of a few 0.01 N m; the fast root of eq 6 (theta1 with theta2 and theta5 scaled along) is not
determined even by noise-free data (a factor 1.4 changes the twitch by < 1e-9 N m). Fixing theta1
(``frozen=("theta1",)``) makes noise-free fits converge to Table 2 (or its slow-root-swapped twin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..fit import Rules, Uncertainty, estimate_uncertainty, levenberg_marquardt
from .contraction import (DEFAULT_STEP_S, TEST_JOINT_ANGLE_RAD, IsometricTrace, simulate_isometric,
                          simulate_isometric_solution)
from .excitation import check_stim_times, train_times
from ..model.hatze_parameters import THETA_NAMES, ActiveStateConstants, ExcitationTheta, Subject

_DEFAULT_CONSTANTS = ActiveStateConstants()
#: Stimulation rates of the paper's trains (Fig 7-8), Hz.
SEED_TRAIN_RATES_HZ: tuple[float, ...] = (4.0, 8.0, 12.0, 16.0, 24.0)


@dataclass(frozen=True)
class TwitchFit:
    """Result of ``fit_twitch``.

    ``theta``: estimates (frozen ones as given); ``uncertainty``: intervals, VIFs, correlation and
    identifiability flags of the free parameters; ``rms_nm``: residual RMS (N m); ``n_evaluations``;
    ``message`` (why the iteration stopped); ``frozen``: parameters held fixed.  ``lower``, ``upper``,
    ``poorly_identified`` and ``vif`` list all five parameters, a frozen one with its value as interval, VIF nan,
    never flagged.
    """

    theta: ExcitationTheta
    uncertainty: Uncertainty
    rms_nm: float
    n_evaluations: int
    message: str
    frozen: tuple[str, ...] = ()

    def _all(self, free_values: dict[str, float], frozen_value: float | None = None) -> dict[str, float]:
        """All five parameters: a free one from ``free_values``, a frozen one ``frozen_value`` (None: its value)."""
        def frozen(n: str) -> float:
            return float(getattr(self.theta, n)) if frozen_value is None else frozen_value
        return {n: frozen(n) if n in self.frozen else free_values[n] for n in THETA_NAMES}

    @property
    def lower(self) -> dict[str, float]:
        """Lower ends of the 95 % intervals (units of ``parameters.THETA_UNITS``)."""
        return self._all({n: lo for n, (lo, _) in self.uncertainty.ci95.items()})

    @property
    def upper(self) -> dict[str, float]:
        """Upper ends of the 95 % intervals (units of ``parameters.THETA_UNITS``)."""
        return self._all({n: hi for n, (_, hi) in self.uncertainty.ci95.items()})

    @property
    def vif(self) -> dict[str, float]:
        """Variance inflation factors (nan for a frozen parameter)."""
        return self._all(self.uncertainty.vif, math.nan)

    @property
    def poorly_identified(self) -> dict[str, bool]:
        """True for the parameters flagged in ``uncertainty.flags``."""
        return {n: n in self.uncertainty.flags for n in THETA_NAMES}


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
    names = [n for n, f in zip(THETA_NAMES, free) if f]
    unc = estimate_uncertainty(names, sol.x, jac, r, np.exp, np.exp(sol.x),
                               Rules.for_twitch_fit(ci_factor_limit, vif_limit))
    est = np.exp(full(sol.x))
    est[~free] = theta_start.as_array()[~free]          # frozen values exactly as given
    return TwitchFit(ExcitationTheta.from_array(est), unc, math.sqrt(float(r @ r) / r.size), sol.n_evaluations,
                     sol.message, tuple(n for n in THETA_NAMES if n in frozen))


@dataclass(frozen=True)
class TrainPrediction:
    """Isometric response to a regular train: ``rate_hz`` (Hz), ``trace`` and its ``peak_moment_nm`` (N m)."""

    rate_hz: float
    trace: IsometricTrace
    peak_moment_nm: float


def predict_trains(theta: ExcitationTheta, subject: Subject, rates_hz: Sequence[float] = SEED_TRAIN_RATES_HZ,
                   duration_s: float = 1.0, t_end_s: float = 1.5, step_s: float = DEFAULT_STEP_S,
                   joint_angle_rad: float = TEST_JOINT_ANGLE_RAD) -> list[TrainPrediction]:
    """Isometric moment for trains of ``duration_s`` (s) at each rate (Hz), first stimulus at t = 0 (the paper's
    section 3.2)."""
    out = []
    for rate in rates_hz:
        tr = simulate_isometric(train_times(rate, duration_s), t_end_s, subject, theta, joint_angle_rad, step_s)
        out.append(TrainPrediction(float(rate), tr, float(tr.moment_nm.max())))
    return out
