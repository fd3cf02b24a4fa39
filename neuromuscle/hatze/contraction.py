"""Contraction dynamics of the triceps surae muscle-tendon complex (MTC) in angular coordinates
(van Zandwijk et al. 1998, section 2.1.1).

Angles are "lengths as angles" (rad), moments in N m, velocities in rad/s, time in s. The MTC is a CE in parallel
with a PEE, in series with an SEE: phi_mtc = phi_ce + phi_see, M_mtc = M_see = M_ce + M_pee.

* CE moment-angle (parabola): M_iso(phi_ce) = Mmax (1 - ((phi_ce/phi_ce_opt - 1)/w)^2), clipped at 0.
* Active state: the CE's isometric moment is F0 = q M_iso(phi_ce). In eq 1 the paper writes the shortening branch
  for full activation, omega_ce = (M_max(phi_ce) - M) b / (M + a_rel Mmax); as in the model it builds on
  (Van Soest & Bobbert 1993) the active state enters by replacing the isometric moment M_max(phi_ce) with
  q M_iso(phi_ce) and *only there*: a = a_rel Mmax stays fixed (the paper's denominator has Mmax without an angle
  argument), so the maximal shortening velocity q M_iso b/(a_rel Mmax) falls with q. (VSB93's extra scaling of b
  at q < 0.3 is not in the paper and is not used.)
* CE shortening (eq 1, omega_ce > 0 is shortening): omega_ce = (F0 - M) b / (M + a_rel Mmax), b = b_rel phi_ce_opt.
* CE lengthening (not in the paper; the standard eccentric hyperbola of Van Soest & Bobbert 1993): with D = M - F0
  > 0 and lengthening velocity v = -omega_ce, M = F0 (1.5 - 0.5 b_e/(v + b_e)), i.e. v = b_e r/(1 - r) with
  r = D/(0.5 F0). Asymptote 1.5 F0; b_e = F0 b / (4 (F0 + a)) makes dM/dv at v = 0 twice the concentric slope
  (F0 + a)/b, and both branches give M = F0 at v = 0 (continuous). From r = 0.8 (M = 1.4 F0) on, v is continued
  linearly in M with the hyperbola's slope there (C1), so the CE can lengthen at a finite rate when q falls
  faster than the SEE unloads (relaxation) and at F0 = 0; r = 0.8 rather than closer to the asymptote keeps the
  slope (25 times the hyperbola's at v = 0) moderate, so that the explicit integrator stays stable.
* SEE (eq 2): M_see = k_see e^2 for extension e = phi_see - phi_see0 > 0, else 0.
* PEE: M_pee = k_pee (phi_ce - phi_pee0)^2 for phi_ce > phi_pee0 (k_pee = 0 by default, as in the paper).
* SEE slack: chosen so that CE sits at phi_ce_opt exerting Mmax when the MTC is at the test angle (ankle 100 deg):
  the SEE extension there is e_test = sqrt((Mmax + M_pee(phi_ce_opt))/k_see). The MTC angle enters through its
  offset from the test angle, ``mtc_offset_rad`` (> 0: MTC longer); in angular coordinates a change of the
  ankle angle is the opposite change of the MTC angle (plantarflexion shortens the triceps surae).

Integration: the single state phi_ce (plus, for fitting, its sensitivities d phi_ce/d theta_k, the variational
equations integrated alongside) is advanced by the classical 4th-order Runge-Kutta method with a fixed step h on a
grid where the drive (gamma from the exact excitation solution, or q, and the MTC angle) is known exactly at the
nodes and half-steps. A fixed step makes the computed moment a smooth function of theta, and RK4 applied to
state + variational equations gives exactly the derivative of the discrete solution, so Levenberg-Marquardt
sees a consistent Jacobian. The default h = 0.5 ms agrees with h/4 to < 1e-6 relative for a twitch and < 1e-5
for a tetanus (tested; RK4 loses order where the CE passes zero velocity, at the slope jump of the
moment-velocity relation); the stiffest
mode (eccentric branch against the SEE, up to ~1300 1/s for subject 1) keeps h*lambda below RK4's limit 2.8.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from ..errors import InputError, NumericalError
from .excitation import active_state_of_x, excitation_states, rise_time_s, uniform_grid
from ..model.hatze_parameters import ActiveStateConstants, ExcitationTheta, Subject, check_positive

#: Ankle angle (tibia to sole of the foot) of the paper's isometric experiments, rad (100 deg).
TEST_JOINT_ANGLE_RAD: float = math.radians(100.0)
#: Eccentric asymptote relative to F0 = q M_iso.
ECC_ASYMPTOTE: float = 1.5
#: Ratio of the eccentric to the concentric slope dM/d|omega| at zero velocity.
ECC_SLOPE_FACTOR: float = 2.0
#: Fraction r of the way from F0 to the asymptote beyond which the eccentric branch is continued linearly.
ECC_LINEAR_FROM: float = 0.8
#: Default RK4 step, s.
DEFAULT_STEP_S: float = 5e-4

_DEFAULT_CONSTANTS = ActiveStateConstants()
OffsetInput = float | Callable[[NDArray[np.float64]], ArrayLike]


class IsometricTrace(NamedTuple):
    """Isometric MTC simulation on the grid ``t_s`` (s): ``moment_nm`` (N m), ``q`` (1), ``phi_ce_rad`` (rad)."""

    t_s: NDArray[np.float64]
    moment_nm: NDArray[np.float64]
    q: NDArray[np.float64]
    phi_ce_rad: NDArray[np.float64]


@dataclass(frozen=True)
class MTCSolution:
    """Nodes of an MTC integration: ``t_s`` (s), ``phi_ce_rad`` (rad), ``moment_nm`` (N m, MTC = SEE moment),
    ``q`` (1), ``mtc_offset_rad`` (rad) and, when requested, ``dmoment_dtheta`` (N m per unit of theta_k,
    shape (n, 5)) and ``dphi_dtheta`` (rad per unit of theta_k)."""

    t_s: NDArray[np.float64]
    phi_ce_rad: NDArray[np.float64]
    moment_nm: NDArray[np.float64]
    q: NDArray[np.float64]
    mtc_offset_rad: NDArray[np.float64]
    dmoment_dtheta: NDArray[np.float64] | None = None
    dphi_dtheta: NDArray[np.float64] | None = None


# ------------------------------------------------------------------------------------------- element relations

def moment_angle(phi_ce_rad: ArrayLike, subject: Subject) -> NDArray[np.float64]:
    """Isometric CE moment at full activation, M_iso(phi_ce) (N m), parabola of width w, >= 0."""
    x = (np.asarray(phi_ce_rad, dtype=float) / subject.phi_ce_opt - 1.0) / subject.w
    return subject.m_max * np.maximum(1.0 - x * x, 0.0)


def see_extension_at_test(subject: Subject) -> float:
    """SEE extension (rad) at the test angle with the CE at phi_ce_opt exerting Mmax (plus PEE there)."""
    return math.sqrt((subject.m_max + _pee(subject.phi_ce_opt, subject)[0]) / subject.k_see)


def see_slack_angle(subject: Subject, mtc_test_angle_rad: float) -> float:
    """SEE slack angle phi_see0 (rad) for an MTC test angle (rad): phi_mtc_test - phi_ce_opt - e_test."""
    return float(mtc_test_angle_rad) - subject.phi_ce_opt - see_extension_at_test(subject)


def see_moment(extension_rad: ArrayLike, subject: Subject) -> NDArray[np.float64]:
    """SEE moment (N m, eq 2): k_see e^2 for SEE extension e > 0 (rad), else 0."""
    e = np.maximum(np.asarray(extension_rad, dtype=float), 0.0)
    return subject.k_see * e * e


def pee_moment(phi_ce_rad: ArrayLike, subject: Subject) -> NDArray[np.float64]:
    """PEE moment (N m): k_pee (phi_ce - phi_pee0)^2 beyond the slack angle phi_pee0 = phi_pee0_rel phi_ce_opt."""
    d = np.maximum(np.asarray(phi_ce_rad, dtype=float) - subject.phi_pee0_rel * subject.phi_ce_opt, 0.0)
    return subject.k_pee * d * d


def mtc_offset_from_joint_angle(joint_angle_rad: float) -> float:
    """MTC angle offset (rad) from the test angle for an ankle angle (rad, tibia to sole; larger = plantarflexed)."""
    return TEST_JOINT_ANGLE_RAD - float(joint_angle_rad)


def _pee(phi: float, s: Subject) -> tuple[float, float]:
    d = phi - s.phi_pee0_rel * s.phi_ce_opt
    if d <= 0.0 or s.k_pee == 0.0:
        return 0.0, 0.0
    return s.k_pee * d * d, 2.0 * s.k_pee * d


def _ce_velocity_partials(m: float, f0: float, a: float, b: float) -> tuple[float, float, float]:
    """omega_ce (rad/s, shortening > 0) and its partials d/dM, d/dF0 (rad/(s N m))."""
    if m <= f0:
        den = m + a
        if den <= 0.0:
            raise NumericalError(f"CE moment {m} N m below -a_rel Mmax: Hill's equation is singular")
        w = (f0 - m) * b / den
        return w, -b * (f0 + a) / (den * den), b / den
    d = m - f0
    fa = f0 + a
    ce = b / (2.0 * fa)                       # = b_e r / D
    dce = -ce / fa                            # d ce / d F0
    rc = ECC_LINEAR_FROM
    if 2.0 * d < rc * f0:                     # hyperbola
        den = f0 - 2.0 * d
        v = ce * d * f0 / den
        dv_dd = ce * f0 * f0 / (den * den)
        dv_df0_d = dce * d * f0 / den - 2.0 * ce * d * d / (den * den)
    else:                                     # linear continuation (C1)
        k1 = 1.0 / (1.0 - rc) - 1.0 / (1.0 - rc) ** 2
        k2 = 1.0 / (1.0 - rc) ** 2
        v = ce * (0.5 * f0 * rc * k1 + d * k2)
        dv_dd = ce * k2
        dv_df0_d = dce * (0.5 * f0 * rc * k1 + d * k2) + ce * 0.5 * rc * k1
    return -v, -dv_dd, -(dv_df0_d - dv_dd)


def ce_velocity(moment_nm: ArrayLike, active_moment_nm: ArrayLike, subject: Subject) -> NDArray[np.float64]:
    """CE angular velocity omega_ce (rad/s, shortening > 0) under CE moment M (N m) given F0 = q M_iso (N m).

    Shortening (M <= F0): eq 1; lengthening (M > F0): the eccentric branch of the module docstring.
    """
    m, f0 = np.broadcast_arrays(np.asarray(moment_nm, dtype=float), np.asarray(active_moment_nm, dtype=float))
    a = subject.a_rel * subject.m_max
    out = np.array([_ce_velocity_partials(float(mm), max(float(ff), 0.0), a, subject.b)[0]
                    for mm, ff in zip(m.ravel(), f0.ravel())])
    return out.reshape(m.shape)


def ce_moment_at_velocity(omega_ce_rad_s: float, active_moment_nm: float, subject: Subject) -> float:
    """Inverse of ``ce_velocity``: the CE moment (N m) at velocity omega_ce (rad/s, shortening > 0)."""
    f0 = float(active_moment_nm)
    a = subject.a_rel * subject.m_max
    w = float(omega_ce_rad_s)
    if w >= 0.0:
        return (f0 * subject.b - a * w) / (subject.b + w)
    return brentq(lambda m: _ce_velocity_partials(m, f0, a, subject.b)[0] - w, f0, f0 + 1e3 * (f0 + a),
                  xtol=1e-13)


# ------------------------------------------------------------------------------------------- integration

def equilibrium_phi_ce(subject: Subject, q: float, mtc_offset_rad: float = 0.0) -> float:
    """CE angle (rad) at isometric equilibrium, M_see - M_pee = q M_iso(phi_ce), for active state q (1)."""
    e_test = see_extension_at_test(subject)
    phi_top = mtc_offset_rad + e_test + subject.phi_ce_opt   # CE angle at which the SEE is slack

    def g(phi: float) -> float:
        e = phi_top - phi
        m_see = subject.k_see * e * e if e > 0 else 0.0
        return m_see - _pee(phi, subject)[0] - q * float(moment_angle(phi, subject))

    span = math.sqrt(4.0 * subject.m_max / subject.k_see) + 1e-9
    lo = phi_top - span
    if g(lo) <= 0.0:
        raise InputError(f"no isometric equilibrium for q = {q}, mtc_offset_rad = {mtc_offset_rad}")
    return brentq(g, lo, phi_top, xtol=1e-15, rtol=4 * np.finfo(float).eps)


def _offset_on_grid(mtc_offset: OffsetInput, t: NDArray[np.float64]) -> NDArray[np.float64]:
    if callable(mtc_offset):
        val = np.asarray(mtc_offset(t), dtype=float)
    else:
        val = np.full(t.shape, float(mtc_offset))
    if val.shape != t.shape or not np.all(np.isfinite(val)):
        raise InputError("mtc_offset must be a finite number (rad) or a callable of t (s) returning finite angles")
    return val


def integrate_mtc(subject: Subject, t_half_s: NDArray[np.float64], mtc_offset_half_rad: NDArray[np.float64], *,
                  q_half: NDArray[np.float64] | None = None, gamma_half: NDArray[np.float64] | None = None,
                  theta5: float | None = None, dgamma_dtheta_half: NDArray[np.float64] | None = None,
                  length_dependent: bool = True, constants: ActiveStateConstants = _DEFAULT_CONSTANTS,
                  phi0_rad: float | None = None) -> MTCSolution:
    """RK4 on the nodes t_half_s[::2] (s) with the drive known on the half-step grid ``t_half_s`` (s).

    Drive: either ``q_half`` (active state, 1) or ``gamma_half`` (s^4) with ``theta5`` (1/s^4) through eq 9,
    with rho*(phi_ce/phi_ce_opt) when ``length_dependent`` (else xi = 1). ``mtc_offset_half_rad``: MTC angle
    offset from the test angle (rad). With ``dgamma_dtheta_half`` (shape (n, 4), s^4 per unit theta_1..4) the
    sensitivity equations for theta_1..5 are integrated alongside. The initial CE angle is the isometric
    equilibrium at the initial q unless ``phi0_rad`` is given.
    """
    n_half = t_half_s.size
    if n_half < 3 or n_half % 2 == 0:
        raise InputError("t_half_s must hold an odd number (>= 3) of points: nodes and half-steps")
    if (q_half is None) == (gamma_half is None):
        raise InputError("give exactly one drive: q_half or gamma_half (with theta5)")
    if gamma_half is not None and theta5 is None:
        raise InputError("gamma_half needs theta5")
    sens = dgamma_dtheta_half is not None
    if sens and gamma_half is None:
        raise InputError("sensitivities need the gamma drive")
    h = float(t_half_s[2] - t_half_s[0])
    s = subject
    a = s.a_rel * s.m_max
    b = s.b
    k_see = s.k_see
    e_test = see_extension_at_test(s)
    popt, mmax, w = s.phi_ce_opt, s.m_max, s.w
    q0, m1, m2 = constants.q0, constants.m1, constants.m2
    kq = (1.0 - q0) / (m1 - m2)
    xc, sx = constants.xi_check, constants.s
    rho_num = xc ** sx - 1.0
    th5 = float(theta5) if theta5 is not None else 0.0
    offs = [float(v) for v in mtc_offset_half_rad]
    drv = [float(v) for v in (gamma_half if gamma_half is not None else q_half)]  # type: ignore[union-attr]
    use_gamma = gamma_half is not None
    dg = np.asarray(dgamma_dtheta_half, dtype=float).tolist() if sens else None

    def stage(phi: float, j: int) -> tuple[float, float, float, float, float]:
        """f, df/dphi, df/dgamma, df/dtheta5 and q at half-grid index j."""
        e = offs[j] + e_test + popt - phi
        if e > 0.0:
            m_see, dm_see = k_see * e * e, 2.0 * k_see * e
        else:
            m_see, dm_see = 0.0, 0.0
        m_pee, dm_pee = _pee(phi, s)
        m_ce = m_see - m_pee
        dm_dphi = -dm_see - dm_pee
        xr = (phi / popt - 1.0) / w
        if abs(xr) < 1.0:
            miso, dmiso = mmax * (1.0 - xr * xr), -2.0 * mmax * xr / (w * popt)
        else:
            miso, dmiso = 0.0, 0.0
        if use_gamma:
            xi = phi / popt
            if length_dependent:
                if not 0.0 < xi < xc:
                    raise NumericalError(f"relative CE length xi = {xi} left (0, xi_check = {xc})")
                r = (xc / xi) ** sx
                rho = rho_num / (r - 1.0)
                drho = rho_num * sx * r / (xi * (r - 1.0) ** 2) / popt   # d rho / d phi
            else:
                rho, drho = 1.0, 0.0
            g = drv[j]
            x = rho * th5 * g
            em1, em2 = math.exp(m1 * x), math.exp(m2 * x)
            q = 1.0 - kq * (m1 * em2 - m2 * em1)
            qx = kq * (em1 - em2)
            dq_dphi = qx * th5 * g * drho
            dq_dg = qx * rho * th5
            dq_dth5 = qx * rho * g
        else:
            q, dq_dphi, dq_dg, dq_dth5 = drv[j], 0.0, 0.0, 0.0
        f0 = q * miso
        if f0 < 0.0:
            f0, df0_dphi, df0_dg, df0_dth5 = 0.0, 0.0, 0.0, 0.0
        else:
            df0_dphi = q * dmiso + miso * dq_dphi
            df0_dg = miso * dq_dg
            df0_dth5 = miso * dq_dth5
        om, om_m, om_f0 = _ce_velocity_partials(m_ce, f0, a, b)
        # dphi/dt = -omega_ce
        return (-om, -(om_m * dm_dphi + om_f0 * df0_dphi), -om_f0 * df0_dg, -om_f0 * df0_dth5, q)

    n_nodes = (n_half - 1) // 2 + 1
    if phi0_rad is None:
        q_init = drv[0] if not use_gamma else (float(active_state_of_x(0.0, constants)) if drv[0] == 0.0
                                               else None)
        if q_init is None:
            raise InputError("with a gamma drive the integration must start from rest (gamma = 0) or get phi0_rad")
        phi = equilibrium_phi_ce(s, q_init, offs[0])
    else:
        phi = float(phi0_rad)
    phis = np.empty(n_nodes)
    qs = np.empty(n_nodes)
    sens_out = np.zeros((n_nodes, 5)) if sens else None
    sv = [0.0] * 5

    def sens_rhs(svec: list[float], fp: float, fg: float, ft5: float, j: int) -> list[float]:
        row = dg[j]  # type: ignore[index]
        return [fp * svec[0] + fg * row[0], fp * svec[1] + fg * row[1], fp * svec[2] + fg * row[2],
                fp * svec[3] + fg * row[3], fp * svec[4] + ft5]

    for n in range(n_nodes):
        j = 2 * n
        k1 = stage(phi, j)
        phis[n] = phi
        qs[n] = k1[4]
        if sens:
            sens_out[n] = sv  # type: ignore[index]
        if n == n_nodes - 1:
            break
        k2 = stage(phi + 0.5 * h * k1[0], j + 1)
        k3 = stage(phi + 0.5 * h * k2[0], j + 1)
        k4 = stage(phi + h * k3[0], j + 2)
        if sens:
            s1 = sens_rhs(sv, k1[1], k1[2], k1[3], j)
            s2 = sens_rhs([sv[i] + 0.5 * h * s1[i] for i in range(5)], k2[1], k2[2], k2[3], j + 1)
            s3 = sens_rhs([sv[i] + 0.5 * h * s2[i] for i in range(5)], k3[1], k3[2], k3[3], j + 1)
            s4 = sens_rhs([sv[i] + h * s3[i] for i in range(5)], k4[1], k4[2], k4[3], j + 2)
            sv = [sv[i] + h / 6.0 * (s1[i] + 2.0 * s2[i] + 2.0 * s3[i] + s4[i]) for i in range(5)]
        phi = phi + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
        if not math.isfinite(phi):
            raise NumericalError(f"CE angle became non-finite at t = {t_half_s[j + 2]} s; reduce step_s")
    t_nodes = np.asarray(t_half_s[::2], dtype=float)
    off_nodes = np.asarray(mtc_offset_half_rad[::2], dtype=float)
    ext = off_nodes + e_test + popt - phis
    moment = see_moment(ext, s)
    dmom = dphi = None
    if sens:
        dphi = sens_out
        dmom = (-2.0 * k_see * np.maximum(ext, 0.0))[:, None] * sens_out  # type: ignore[index]
    return MTCSolution(t_nodes, phis, moment, qs, off_nodes, dmom, dphi)


def _half_grid(t_end_s: float, step_s: float) -> NDArray[np.float64]:
    check_positive("step_s", step_s)
    return uniform_grid(t_end_s, 0.5 * step_s)


def simulate_isometric_solution(stim_times_s: ArrayLike, t_end_s: float, subject: Subject, theta: ExcitationTheta,
                                joint_angle_rad: float = TEST_JOINT_ANGLE_RAD, step_s: float = DEFAULT_STEP_S,
                                sensitivities: bool = False, length_dependent: bool = True,
                                constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> MTCSolution:
    """Isometric contraction from rest driven by stimuli at ``stim_times_s`` (s); the full ``MTCSolution``.

    With ``sensitivities`` also dM/dtheta_k (k = 1..5) from the sensitivity equations.
    """
    if not isinstance(subject, Subject):
        raise InputError(f"subject must be a Subject, got {type(subject).__name__}")
    t_half = _half_grid(t_end_s, step_s)
    ex = excitation_states(stim_times_s, t_end_s, theta, 0.5 * step_s, sensitivities=sensitivities)
    offset = mtc_offset_from_joint_angle(check_positive("joint_angle_rad", joint_angle_rad))
    dgh = ex.dz_dtheta[:, 2, :] if sensitivities else None  # type: ignore[index]
    return integrate_mtc(subject, t_half, np.full(t_half.shape, offset), gamma_half=ex.z[:, 2],
                         theta5=theta.theta5, dgamma_dtheta_half=dgh, length_dependent=length_dependent,
                         constants=constants)


def simulate_isometric(stim_times_s: ArrayLike, t_end_s: float, subject: Subject, theta: ExcitationTheta,
                       joint_angle_rad: float = TEST_JOINT_ANGLE_RAD, step_s: float = DEFAULT_STEP_S,
                       length_dependent: bool = True,
                       constants: ActiveStateConstants = _DEFAULT_CONSTANTS) -> IsometricTrace:
    """Isometric MTC moment after stimuli at ``stim_times_s`` (s), from rest, on the grid 0, step_s, ..., t_end_s.

    ``joint_angle_rad``: ankle angle (rad; default the paper's 100 deg test angle, where the SEE slack puts the CE
    at phi_ce_opt under Mmax). q follows eq 9 with xi = phi_ce/phi_ce_opt (``length_dependent``) or xi = 1.
    Returns t (s), moment (N m), q (1), phi_ce (rad).
    """
    sol = simulate_isometric_solution(stim_times_s, t_end_s, subject, theta, joint_angle_rad, step_s, False,
                                      length_dependent, constants)
    return IsometricTrace(sol.t_s, sol.moment_nm, sol.q, sol.phi_ce_rad)


def simulate_active_state_drive(subject: Subject, t_end_s: float, q_of_t: float | Callable[[NDArray], ArrayLike],
                                mtc_offset_rad: OffsetInput = 0.0, step_s: float = DEFAULT_STEP_S,
                                q_initial: float | None = None, phi0_rad: float | None = None) -> MTCSolution:
    """MTC driven by a prescribed active state q(t) (1) and MTC offset (rad, number or callable of t in s).

    The CE starts at isometric equilibrium under ``q_initial`` (default q(0)) unless ``phi0_rad`` is given.
    """
    t_half = _half_grid(t_end_s, step_s)
    q = np.asarray(q_of_t(t_half), dtype=float) if callable(q_of_t) else np.full(t_half.shape, float(q_of_t))
    if q.shape != t_half.shape or not np.all(np.isfinite(q)) or np.any(q < 0.0) or np.any(q > 1.0):
        raise InputError("q_of_t must give finite active states in [0, 1]")
    offs = _offset_on_grid(mtc_offset_rad, t_half)
    if phi0_rad is None and q_initial is not None:
        phi0_rad = equilibrium_phi_ce(subject, check_positive("q_initial", q_initial), float(offs[0]))
    return integrate_mtc(subject, t_half, offs, q_half=q, phi0_rad=phi0_rad)


def moment_rise_time_s(subject: Subject, t_end_s: float = 1.5, step_s: float = DEFAULT_STEP_S,
                       q_rest: float = ActiveStateConstants().q0) -> float:
    """Rise time (s, 10 % to 90 % of the maximum) of the isometric moment at the test angle under q = 1.

    The active state steps from ``q_rest`` (the equilibrium before t = 0) to 1 at t = 0 (the paper's section 3.3,
    Fig 9).
    """
    sol = simulate_active_state_drive(subject, t_end_s, 1.0, 0.0, step_s, q_initial=q_rest)
    return rise_time_s(sol.t_s, sol.moment_nm)


class ReleaseData(NamedTuple):
    """One isokinetic release: ``t_s`` (s), ``mtc_angle_rad`` (rad, MTC angle relative to its initial value;
    decreasing = MTC shortening) and ``moment_nm`` (N m)."""

    t_s: NDArray[np.float64]
    mtc_angle_rad: NDArray[np.float64]
    moment_nm: NDArray[np.float64]


def release_profile(t_s: ArrayLike, velocity_rad_s: float, t_release_s: float, ramp_s: float,
                    displacement_rad: float) -> NDArray[np.float64]:
    """MTC angle (rad, relative to start) of a release: hold, a smooth velocity ramp of ``ramp_s`` (s) to
    ``velocity_rad_s`` (shortening > 0), constant velocity until ``displacement_rad`` is reached, then hold."""
    t = np.asarray(t_s, dtype=float) - t_release_s
    v = velocity_rad_s
    tr = ramp_s
    # ramp: velocity v (1 - cos(pi tau/tr))/2, displacement v (tau/2 - tr/(2 pi) sin(pi tau/tr))
    ramp_disp = v * (np.clip(t, 0, tr) / 2.0 - tr / (2.0 * math.pi) * np.sin(math.pi * np.clip(t, 0, tr) / tr))
    disp = np.where(t <= tr, ramp_disp, v * tr / 2.0 + v * (t - tr))
    disp = np.where(t <= 0.0, 0.0, disp)
    return -np.minimum(disp, displacement_rad)


def simulate_release(subject: Subject, velocity_rad_s: float, t_end_s: float = 0.4, t_release_s: float = 0.05,
                     ramp_s: float = 0.005, displacement_rad: float = 1.0, sample_rate_hz: float = 2000.0,
                     step_s: float = 2.5e-4) -> ReleaseData:
    """Synthetic isokinetic release at q = 1 from isometric equilibrium at the test angle (the paper's section 2.2.2).

    Returns samples at ``sample_rate_hz`` of t (s), MTC angle relative to the start (rad) and moment (N m).
    """
    check_positive("velocity_rad_s", velocity_rad_s)
    dt_sample = 1.0 / check_positive("sample_rate_hz", sample_rate_hz)
    ratio = dt_sample / step_s
    if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
        raise InputError(f"step_s = {step_s} s must divide the sampling interval {dt_sample} s")

    def offset(t: NDArray[np.float64]) -> NDArray[np.float64]:
        return release_profile(t, velocity_rad_s, t_release_s, ramp_s, displacement_rad)

    sol = simulate_active_state_drive(subject, t_end_s, 1.0, offset, step_s)
    every = int(round(ratio))
    return ReleaseData(sol.t_s[::every], sol.mtc_offset_rad[::every], sol.moment_nm[::every])
