"""Hatze's excitation dynamics (van Zandwijk et al. 1998, Appendix eqs 6-10), integrated exactly.

Equations (time t in s; alpha dimensionless, beta in s^2, gamma in s^4, theta in ``parameters.THETA_UNITS``)::

    beta''  + theta1 beta'  + theta2 beta  = alpha(t)                                   (eq 6)
    gamma'' + theta3 gamma' + theta4 gamma = beta(t)                                    (eq 7)
    alpha(t) = sum_k sin(pi (t - t_k) / T_p)   for t_k <= t < t_k + T_p,  T_p = 1 ms    (eq 8)
    q(gamma, xi) = 1 - (1 - q0)/(m1 - m2) (m1 exp(m2 x) - m2 exp(m1 x)),
        x = rho*(xi) theta5 gamma,  m1,2 = -rho2 +/- sqrt(rho2^2 - 1),
        rho*(xi) = (xicheck^s - 1) / ((xicheck/xi)^s - 1),  xi = phi_ce / phi_ce_opt     (eq 9)
    dgamma/dt = m (c nu - gamma),  nu = stimulation rate / 100 Hz                        (eq 10, trend)

Method (``excitation_states``). Eqs 6-7 are linear and time-invariant; the half-sine input is itself the output
of the linear oscillator u = (sin w tau, cos w tau), u' = [[0, w], [-w, 0]] u, w = pi/T_p, so state and input
together obey X' = M X with a constant matrix M on every interval in which the set of active pulses does not
change. The state is therefore propagated *exactly* by matrix exponentials, X(t + h) = expm(M h) X(t): over a
whole grid step with one cached expm, and across pulse starts/ends by splitting the step at the event. After
each step the oscillator part is reset to its analytic value (sum over active pulses), so no error
accumulates in the input. The sensitivities d(beta, beta', gamma, gamma')/d theta_k (k = 1-4) obey
S_k' = A S_k + (dA/dtheta_k) z and are appended to M (block-triangular, Van Loan's construction), so they are
exact too. M is diagonally balanced (powers of two, ``scipy.linalg.matrix_balance``) before ``expm``: the
companion matrices mix entries from ~1 to ~1e7 and the state components span ~1e-9 (beta) to ~1e-15 (gamma).
The only errors are those of ``expm`` (~1e-12 relative after 0.3 s; checked against solve_ivp and against an
mpmath reference at 40 digits).

For a NEURON check: ``alpha_input`` is the drive, ``excitation_rhs`` the right-hand side, ``active_state`` eq 9,
and ``simulate_excitation`` gives beta, gamma, q on a uniform grid that an NMODL implementation must match.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm, matrix_balance
from scipy.optimize import least_squares
from scipy.stats import t as student_t

from ..errors import InputError, NumericalError
from ..validate import check_spike_times
from ..model.hatze_parameters import ActiveStateConstants, ExcitationTheta, TrendParameters, check_positive

#: Duration of one stimulus (half-sine) of alpha, s (eq 8).
PULSE_DURATION_S: float = 1e-3
#: Stimulation rate taken as nu = 1 (eq 10), Hz.
NU_REFERENCE_RATE_HZ: float = 100.0
_OMEGA = math.pi / PULSE_DURATION_S  # rad/s

_DEFAULT_CONSTANTS = ActiveStateConstants()

XiInput = float | ArrayLike | Callable[[NDArray[np.float64]], ArrayLike]


class ExcitationTrace(NamedTuple):
    """Result of ``simulate_excitation`` on the uniform grid ``t_s`` (s).

    ``beta`` T-tubule depolarisation (s^2), ``gamma`` free Ca2+ on the raw scale of eq 7 (s^4), ``q`` active state
    (dimensionless, eq 9).
    """

    t_s: NDArray[np.float64]
    beta: NDArray[np.float64]
    gamma: NDArray[np.float64]
    q: NDArray[np.float64]


@dataclass(frozen=True)
class ExcitationStates:
    """Full linear state on the grid ``t_s`` (s).

    ``z[:, 0:4]`` = beta (s^2), dbeta/dt (s), gamma (s^4), dgamma/dt (s^3). ``dz_dtheta[:, :, k]`` is dz/dtheta_{k+1}
    for k = 0..3 (theta5 does not enter eqs 6-7), or None when sensitivities were not requested.
    """

    t_s: NDArray[np.float64]
    z: NDArray[np.float64]
    dz_dtheta: NDArray[np.float64] | None


# ------------------------------------------------------------------------------------------- inputs

def check_stim_times(stim_times_s: ArrayLike, t_end_s: float) -> NDArray[np.float64]:
    """Validate stimulus onset times (s): the package's one rule for spike times (1-D, finite, >= 0, strictly
    increasing: unsorted or repeated onsets are refused, never sorted) and before t_end_s (s)."""
    t_end = check_positive("t_end_s", t_end_s)
    stim = check_spike_times(stim_times_s, "stim_times_s", unit="s")
    if stim.size and stim[-1] >= t_end:
        raise InputError(f"stim_times_s must lie in [0, t_end_s = {t_end}) s; got range "
                         f"[{stim[0]}, {stim[-1]}]")
    return stim


def uniform_grid(t_end_s: float, dt_s: float) -> NDArray[np.float64]:
    """Grid 0, dt, ..., t_end (s); t_end_s must be a whole multiple of dt_s."""
    t_end = check_positive("t_end_s", t_end_s)
    dt = check_positive("dt_s", dt_s)
    n = int(round(t_end / dt))
    if n < 1 or abs(n * dt - t_end) > 1e-9 * t_end:
        raise InputError(f"dt_s = {dt} s must divide t_end_s = {t_end} s into a whole number of steps")
    return np.arange(n + 1) * dt


def train_times(rate_hz: float, duration_s: float, start_s: float = 0.0) -> NDArray[np.float64]:
    """Stimulus onsets (s) of a regular train: start_s + n/rate_hz for n/rate_hz < duration_s (eq 8)."""
    rate = check_positive("rate_hz", rate_hz)
    dur = check_positive("duration_s", duration_s)
    start = check_positive("start_s", start_s, allow_zero=True)
    n = int(math.floor(dur * rate - 1e-9)) + 1
    return start + np.arange(n) / rate


def alpha_input(t_s: ArrayLike, stim_times_s: ArrayLike) -> NDArray[np.float64]:
    """Neural drive alpha(t) (dimensionless, eq 8): one half-sine of 1 ms per stimulus onset, summed."""
    t = np.asarray(t_s, dtype=float)
    stim = np.asarray(stim_times_s, dtype=float).ravel()
    out = np.zeros_like(t)
    for t0 in stim:
        tau = t - t0
        on = (tau >= 0.0) & (tau < PULSE_DURATION_S)
        out = out + np.where(on, np.sin(_OMEGA * np.where(on, tau, 0.0)), 0.0)
    return out


# ------------------------------------------------------------------------------------------- model functions

def excitation_matrix(theta: ExcitationTheta) -> NDArray[np.float64]:
    """A (4x4) of z' = A z + e2 alpha with z = (beta, dbeta/dt, gamma, dgamma/dt), eqs 6-7."""
    return np.array([[0.0, 1.0, 0.0, 0.0],
                     [-theta.theta2, -theta.theta1, 0.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0],
                     [1.0, 0.0, -theta.theta4, -theta.theta3]])


def excitation_rhs(t_s: float, z: ArrayLike, theta: ExcitationTheta,
                   stim_times_s: ArrayLike) -> NDArray[np.float64]:
    """dz/dt of eqs 6-7 at time t_s (s) for z = (beta s^2, dbeta/dt s, gamma s^4, dgamma/dt s^3)."""
    zz = np.asarray(z, dtype=float)
    dz = excitation_matrix(theta) @ zz
    dz[1] += float(alpha_input(np.array([t_s]), stim_times_s)[0])
    return dz


def rho_star(xi: ArrayLike, constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> NDArray[np.float64]:
    """Length factor rho*(xi) of eq 9 (dimensionless); xi = CE length / optimum must lie in (0, xi_check)."""
    x = np.asarray(xi, dtype=float)
    if not np.all(np.isfinite(x)) or np.any(x <= 0.0) or np.any(x >= constants.xi_check):
        raise InputError(f"xi must lie in (0, xi_check = {constants.xi_check}); got range "
                         f"[{np.nanmin(x)}, {np.nanmax(x)}]")
    s = constants.s
    return (constants.xi_check ** s - 1.0) / ((constants.xi_check / x) ** s - 1.0)


def rho_star_derivative(xi: ArrayLike, constants: ActiveStateConstants = _DEFAULT_CONSTANTS
                        ) -> NDArray[np.float64]:
    """d rho*/d xi (dimensionless)."""
    x = np.asarray(xi, dtype=float)
    s, xc = constants.s, constants.xi_check
    r = (xc / x) ** s
    return (xc ** s - 1.0) * s * r / (x * (r - 1.0) ** 2)


def active_state_of_x(x: ArrayLike, constants: ActiveStateConstants = _DEFAULT_CONSTANTS
                      ) -> NDArray[np.float64]:
    """Eq 9 as a function of x = rho*(xi) theta5 gamma (dimensionless): q0 at x = 0, -> 1 as x -> inf."""
    xx = np.asarray(x, dtype=float)
    m1, m2 = constants.m1, constants.m2
    return 1.0 - (1.0 - constants.q0) / (m1 - m2) * (m1 * np.exp(m2 * xx) - m2 * np.exp(m1 * xx))


def active_state_slope(x: ArrayLike, constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> NDArray[np.float64]:
    """dq/dx of eq 9 (uses m1 m2 = 1): (1 - q0) (exp(m1 x) - exp(m2 x)) / (m1 - m2)."""
    xx = np.asarray(x, dtype=float)
    m1, m2 = constants.m1, constants.m2
    return (1.0 - constants.q0) * (np.exp(m1 * xx) - np.exp(m2 * xx)) / (m1 - m2)


def active_state(gamma: ArrayLike, xi: ArrayLike, theta5: float,
                 constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> NDArray[np.float64]:
    """Active state q (dimensionless, eq 9) from gamma (s^4), relative CE length xi (1) and theta5 (1/s^4)."""
    return active_state_of_x(rho_star(xi, constants) * theta5 * np.asarray(gamma, dtype=float), constants)


# ------------------------------------------------------------------------------------------- exact integration

def _augmented_matrix(theta: ExcitationTheta, sensitivities: bool) -> NDArray[np.float64]:
    """M for X = (z, [S_1..S_4], u); see the module docstring."""
    a = excitation_matrix(theta)
    nz = 4 * (5 if sensitivities else 1)
    m = np.zeros((nz + 2, nz + 2))
    for blk in range(nz // 4):
        m[4 * blk:4 * blk + 4, 4 * blk:4 * blk + 4] = a
    m[1, nz] = 1.0  # alpha = u_sin drives beta''
    if sensitivities:
        # dA/dtheta_k: -1 at (1,1) for theta1, (1,0) theta2, (3,3) theta3, (3,2) theta4
        for k, (r, c) in enumerate([(1, 1), (1, 0), (3, 3), (3, 2)]):
            m[4 * (k + 1) + r, c] = -1.0
    m[nz, nz + 1] = _OMEGA
    m[nz + 1, nz] = -_OMEGA
    return m


def excitation_states(stim_times_s: ArrayLike, t_end_s: float, theta: ExcitationTheta, dt_s: float = 1e-4,
                      sensitivities: bool = False) -> ExcitationStates:
    """Exact solution of eqs 6-7 from rest (z = 0 at t = 0) on the grid 0, dt_s, ..., t_end_s (s).

    With ``sensitivities`` also dz/dtheta_k for k = 1..4 (units of z divided by those of theta_k).
    """
    if not isinstance(theta, ExcitationTheta):
        raise InputError(f"theta must be an ExcitationTheta, got {type(theta).__name__}")
    stim = check_stim_times(stim_times_s, t_end_s)
    t = uniform_grid(t_end_s, dt_s)
    dt = float(t[1] - t[0]) if t.size > 1 else float(dt_s)
    m_full = _augmented_matrix(theta, sensitivities)
    _, (scale, _) = matrix_balance(m_full, permute=False, separate=True)
    m_bal = m_full * (1.0 / scale)[:, None] * scale[None, :]   # D^-1 M D
    nu_ = m_full.shape[0] - 2
    cache: dict[float, NDArray[np.float64]] = {}

    def phi(h: float) -> NDArray[np.float64]:
        if h not in cache:
            cache[h] = expm(m_bal * h)
        return cache[h]

    def osc(at: float, active: list[float]) -> NDArray[np.float64]:
        tau = at - np.asarray(active)
        return np.array([np.sin(_OMEGA * tau).sum(), np.cos(_OMEGA * tau).sum()]) / scale[nu_:]

    starts = [(float(s), 0, float(s)) for s in stim]
    ends = [(float(s) + PULSE_DURATION_S, 1, float(s)) for s in stim]
    events = sorted(starts + ends)           # at equal times: starts (0) before ends (1) - both instantaneous
    active: list[float] = []
    w = np.zeros(m_full.shape[0])
    out = np.empty((t.size, nu_))
    out[0] = 0.0
    now = 0.0
    ev = 0
    phi_dt = phi(dt)
    for i in range(1, t.size):
        t_next = float(t[i])
        while ev < len(events) and events[ev][0] < t_next:
            te, kind, t0 = events[ev]
            if te > now:
                w = phi(te - now) @ w
                now = te
            if kind == 0:
                active.append(t0)
            else:
                active.remove(t0)
            w[nu_:] = osc(now, active)
            ev += 1
        w = (phi_dt if now == float(t[i - 1]) else phi(t_next - now)) @ w
        now = t_next
        w[nu_:] = osc(now, active) if active else 0.0
        out[i] = w[:nu_] * scale[:nu_]
    if not np.all(np.isfinite(out)):
        raise NumericalError("excitation state became non-finite (theta far outside its physical range?)")
    z = out[:, :4]
    dz = out[:, 4:].reshape(t.size, 4, 4).transpose(0, 2, 1) if sensitivities else None
    return ExcitationStates(t, z, dz)


def _xi_on_grid(xi: XiInput, t: NDArray[np.float64]) -> NDArray[np.float64]:
    if callable(xi):
        val = np.asarray(xi(t), dtype=float)
    else:
        val = np.asarray(xi, dtype=float)
    if val.ndim == 0:
        return np.full(t.shape, float(val))
    if val.shape != t.shape:
        raise InputError(f"xi must be a number, a callable of t (s) or an array of {t.size} grid values; "
                         f"got shape {val.shape}")
    return val


def simulate_excitation(stim_times_s: ArrayLike, t_end_s: float, theta: ExcitationTheta, dt_s: float = 1e-4,
                        xi: XiInput = 1.0, constants: ActiveStateConstants = _DEFAULT_CONSTANTS
                        ) -> ExcitationTrace:
    """Beta (s^2), gamma (s^4) and q (1) on the grid 0, dt_s, ..., t_end_s (s) after stimuli at ``stim_times_s``.

    ``xi`` (CE length / optimum, dimensionless) is a number (default 1), an array on the grid or a callable
    xi(t_s). The linear part is exact at the grid points (see module docstring).
    """
    st = excitation_states(stim_times_s, t_end_s, theta, dt_s)
    xi_grid = _xi_on_grid(xi, st.t_s)
    q = active_state(st.z[:, 2], xi_grid, theta.theta5, constants)
    return ExcitationTrace(st.t_s, st.z[:, 0].copy(), st.z[:, 2].copy(), q)


# ------------------------------------------------------------------------------------------- trend model (eq 10)

def trend_gamma(t_s: ArrayLike, m_per_s: float, c: float, nu: float = 1.0, train_end_s: float | None = None,
                gamma0: float = 0.0) -> NDArray[np.float64]:
    """Exact solution of eq 10 with nu constant from t = 0 to ``train_end_s`` (s) and 0 afterwards.

    gamma has the unit of ``c``; m in 1/s; nu = stimulation rate / 100 Hz (dimensionless).
    """
    t = np.asarray(t_s, dtype=float)
    g_on = c * nu + (gamma0 - c * nu) * np.exp(-m_per_s * t)
    if train_end_s is None:
        return g_on
    g_end = c * nu + (gamma0 - c * nu) * math.exp(-m_per_s * train_end_s)
    return np.where(t <= train_end_s, g_on, g_end * np.exp(-m_per_s * (t - train_end_s)))


@dataclass(frozen=True)
class TrendFit:
    """Least-squares fit of eq 10 to a gamma(t) history.

    ``params.m`` (1/s) and ``params.c`` (unit of the fitted gamma: s^4 for the raw gamma of eqs 6-7), 95 %
    intervals ``m_ci``/``c_ci`` (linearised, t-distribution), ``rms`` residual (unit of gamma) and the fit window.
    """

    params: TrendParameters
    m_ci: tuple[float, float]
    c_ci: tuple[float, float]
    rms: float
    window_s: tuple[float, float]


def fit_trend(t_s: ArrayLike, gamma: ArrayLike, nu: float = 1.0, train_end_s: float | None = None,
              window_s: tuple[float, float] | None = None) -> TrendFit:
    """Fit m (1/s) and c (unit of gamma) of eq 10 (gamma(0) = 0) to ``gamma`` sampled at ``t_s`` (s).

    ``train_end_s``: stimulation stops there (nu = 0 afterwards); ``window_s``: only samples in [t0, t1] are used.
    Confidence intervals: residual variance * (J^T J)^-1 with Student's t at 95 %.
    """
    t = np.asarray(t_s, dtype=float).ravel()
    g = np.asarray(gamma, dtype=float).ravel()
    if t.size != g.size or t.size < 3:
        raise InputError(f"t_s and gamma must have the same length >= 3 (got {t.size}, {g.size})")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(g))):
        raise InputError("t_s or gamma contains non-finite values")
    nu = check_positive("nu", nu)
    lo, hi = window_s if window_s is not None else (float(t[0]), float(t[-1]))
    sel = (t >= lo) & (t <= hi)
    if sel.sum() < 3:
        raise InputError(f"window_s = {window_s} holds fewer than 3 samples")
    tt, gg = t[sel], g[sel]
    scale = float(np.max(np.abs(gg)))
    if scale <= 0.0:
        raise InputError("gamma is identically zero in the fit window")

    def resid(p: NDArray[np.float64]) -> NDArray[np.float64]:
        return trend_gamma(tt, math.exp(p[0]), math.exp(p[1]), nu, train_end_s) - gg / scale

    mean_rise = float(np.trapezoid(1.0 - gg / gg.max(), tt)) if gg.max() > 0 else 0.1
    p0 = np.array([math.log(1.0 / max(mean_rise, 1e-3)), math.log(gg.max() / scale / nu)])
    sol = least_squares(resid, p0, method="lm", xtol=1e-14, ftol=1e-14, gtol=1e-14)
    m, c_rel = math.exp(sol.x[0]), math.exp(sol.x[1])
    r = sol.fun
    dof = max(tt.size - 2, 1)
    s2 = float(r @ r) / dof
    jac = sol.jac * np.array([m, c_rel])          # d resid / d (m, c_rel)
    cov = s2 * np.linalg.pinv(jac.T @ jac)
    tq = float(student_t.ppf(0.975, dof))
    hw = tq * np.sqrt(np.diag(cov))
    return TrendFit(TrendParameters(m, c_rel * scale), (m - hw[0], m + hw[0]),
                    ((c_rel - hw[1]) * scale, (c_rel + hw[1]) * scale), math.sqrt(s2) * scale, (lo, hi))


def fit_trend_to_full_model(theta: ExcitationTheta, rate_hz: float = NU_REFERENCE_RATE_HZ,
                            train_duration_s: float = 1.0, t_end_s: float | None = None,
                            dt_s: float = 1e-4, window_s: tuple[float, float] | None = None) -> TrendFit:
    """Table 3's procedure: fit eq 10 to gamma(t) of eqs 6-8 for a ``rate_hz`` train lasting ``train_duration_s``.

    gamma is on the raw scale of eq 7 (s^4), so ``c`` comes out in s^4 (theta5 * c is the dimensionless x of eq 9
    at steady state); ``m`` (1/s) is scale-free. ``t_end_s`` (default: end of the train) beyond the train includes
    the relaxation (nu = 0) in the fit.

    m depends on the window, because gamma of eqs 6-7 rises like a nearly critically damped pair of slow roots,
    not exponentially. Subject 3 (Table 2 theta, 100 Hz): m = 6.67, 7.63, 7.85, 7.89, 7.93, 7.95 1/s for trains of
    0.5, 1, 2, 3, 5, 10 s; Table 3's 7.94 (7.90-7.96) is met for windows of about 3-10 s. c_raw = 3.91e-14 s^4
    (theta5 c_raw = 17.9), so Table 3's c = 1.57e-4 mol/L implies gamma[mol/L] = 4.0e9 * gamma[s^4].
    """
    t_end = train_duration_s if t_end_s is None else t_end_s
    stim = train_times(rate_hz, train_duration_s)
    st = excitation_states(stim, t_end, theta, dt_s)
    nu = rate_hz / NU_REFERENCE_RATE_HZ
    end = None if t_end <= train_duration_s else train_duration_s
    return fit_trend(st.t_s, st.z[:, 2], nu, end, window_s)


def rise_time_s(t_s: ArrayLike, y: ArrayLike, low: float = 0.1, high: float = 0.9) -> float:
    """Time (s) for ``y`` to rise from ``low`` to ``high`` times its maximum (the paper's section 3.3: 10 % to 90 %).

    First upward crossings, linearly interpolated; the levels are fractions of the maximum itself (no baseline
    subtraction, as in the paper), so a resting level above ``low`` * max gives a crossing at t_s[0].
    """
    t = np.asarray(t_s, dtype=float)
    v = np.asarray(y, dtype=float)
    top = float(np.max(v))
    if not top > 0.0:
        raise InputError("y never rises above 0; rise time undefined")

    def crossing(level: float) -> float:
        idx = int(np.argmax(v >= level))
        if idx == 0:
            return float(t[0])
        frac = (level - v[idx - 1]) / (v[idx] - v[idx - 1])
        return float(t[idx - 1] + frac * (t[idx] - t[idx - 1]))

    return crossing(high * top) - crossing(low * top)


def trend_active_state_rise_time_s(m_per_s: float, x_steady: float, duration_s: float = 2.0, dt_s: float = 1e-4,
                                   constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> float:
    """Rise time (10-90 %, s) of q for the trend model from rest at a stimulation level giving x = ``x_steady``.

    x = rho*(xi) theta5 gamma at steady state (dimensionless; = rho* theta5 c nu on the raw gamma scale).
    """
    t = uniform_grid(duration_s, dt_s)
    q = active_state_of_x(trend_gamma(t, m_per_s, x_steady, 1.0), constants)
    return rise_time_s(t, q)


def stim_pulse_integral() -> float:
    """Integral of one half-sine of alpha, s: 2 T_p / pi."""
    return 2.0 * PULSE_DURATION_S / math.pi


def steady_gamma_mean(theta: ExcitationTheta, rate_hz: float) -> float:
    """Mean gamma (s^4) in the steady state of a regular train: rate * pulse integral / (theta2 theta4)."""
    return check_positive("rate_hz", rate_hz) * stim_pulse_integral() / (theta.theta2 * theta.theta4)


__all__: Sequence[str] = (
    "PULSE_DURATION_S", "NU_REFERENCE_RATE_HZ", "ExcitationTrace", "ExcitationStates", "TrendFit",
    "check_stim_times", "uniform_grid", "train_times", "alpha_input", "excitation_matrix", "excitation_rhs",
    "rho_star", "rho_star_derivative", "active_state_of_x", "active_state_slope", "active_state",
    "excitation_states", "simulate_excitation", "trend_gamma", "fit_trend", "fit_trend_to_full_model",
    "rise_time_s", "trend_active_state_rise_time_s", "stim_pulse_integral", "steady_gamma_mean",
)
