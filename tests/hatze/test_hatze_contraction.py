"""Triceps surae contraction dynamics (van Zandwijk et al. 1998, eqs 1-2): element relations, integration against an
independent solve_ivp, step convergence, sensitivities, rise time, bad inputs."""

import math

import numpy as np
import pytest
from hatze_twitch_data import S3, STIM, SUBJECTS, T_DATA, THETA
from scipy.integrate import solve_ivp

from neuromuscle.errors import InputError
from neuromuscle.hatze.contraction import (ce_moment_at_velocity, ce_velocity, equilibrium_phi_ce, moment_angle,
                                           moment_rise_time_s, see_extension_at_test, see_moment,
                                           simulate_isometric, simulate_isometric_solution)
from neuromuscle.hatze.excitation import PULSE_DURATION_S, active_state, excitation_rhs, train_times
from neuromuscle.model.hatze_parameters import THETA_NAMES, ExcitationTheta
from neuromuscle.hatze.twitch_fit import twitch_moment


@pytest.fixture(scope="module")
def twitch():
    return twitch_moment(T_DATA, STIM, S3, THETA)[0]


def test_ce_relations():
    assert moment_angle(S3.phi_ce_opt, S3) == pytest.approx(S3.m_max)
    assert moment_angle(S3.phi_ce_opt * (1 + S3.w), S3) == pytest.approx(0.0, abs=1e-12)
    assert moment_angle(3.0, S3) == 0.0
    f0 = 30.0
    a = S3.a_rel * S3.m_max
    # shortening: eq 1 with q M_iso in the numerator and a_rel Mmax in the denominator
    assert ce_velocity(10.0, f0, S3) == pytest.approx((f0 - 10.0) * S3.b / (10.0 + a))
    assert ce_velocity(f0, f0, S3) == 0.0
    # continuity at zero velocity and slope ratio 2 (eccentric / concentric)
    h = 1e-7
    s_con = (ce_velocity(f0 - h, f0, S3) - ce_velocity(f0, f0, S3)) / h
    s_ecc = (ce_velocity(f0, f0, S3) - ce_velocity(f0 + h, f0, S3)) / h
    assert s_con / s_ecc == pytest.approx(2.0, rel=1e-5)
    # lengthening velocity grows steeply towards the 1.5 F0 asymptote and stays finite beyond it
    v = ce_velocity(np.array([1.1, 1.3, 1.39, 1.45, 1.6]) * f0, f0, S3)
    assert np.all(np.diff(v) < 0) and np.all(np.isfinite(v))
    for w in (-2.0, 0.0, 3.0):
        assert ce_velocity(ce_moment_at_velocity(w, f0, S3), f0, S3) == pytest.approx(w, abs=1e-9)
    assert see_moment(-0.1, S3) == 0.0
    assert see_moment(0.2, S3) == pytest.approx(377 * 0.04)


def test_slack_puts_ce_at_optimum_under_mmax():
    for s in SUBJECTS.values():
        assert equilibrium_phi_ce(s, 1.0) == pytest.approx(s.phi_ce_opt, abs=1e-12)
        assert see_moment(see_extension_at_test(s), s) == pytest.approx(s.m_max)


def _reference_twitch(subject, theta, stim, t_eval):
    """Independent reference: the full ODE (z, phi_ce) with Radau, restarted at the pulse edges."""
    scale = np.array([1e-9, 1e-6, 1e-15, 1e-13, 1.0])
    e_test = see_extension_at_test(subject)

    def rhs(t, y):
        x = y * scale
        dz = excitation_rhs(t, x[:4], theta, stim)
        phi = x[4]
        m = see_moment(e_test + subject.phi_ce_opt - phi, subject)
        q = active_state(x[2], phi / subject.phi_ce_opt, theta.theta5)
        dphi = -ce_velocity(m, q * moment_angle(phi, subject), subject)
        return np.concatenate([dz, [dphi]]) / scale

    y = np.zeros(5)
    y[4] = equilibrium_phi_ce(subject, 0.005)
    edges = sorted({0.0, float(t_eval[-1]), *stim, *(s + PULSE_DURATION_S for s in stim)})
    out = np.zeros(t_eval.size)
    for lo, hi in zip(edges[:-1], edges[1:]):
        sol = solve_ivp(rhs, (lo, hi), y, method="Radau", rtol=1e-10, atol=1e-12, dense_output=True)
        sel = (t_eval >= lo) & (t_eval <= hi)
        out[sel] = see_moment(e_test + subject.phi_ce_opt - sol.sol(t_eval[sel])[4], subject)
        y = sol.y[:, -1]
    return out


def test_twitch_matches_independent_solve_ivp(twitch):
    t = T_DATA[::5]
    ref = _reference_twitch(S3, THETA, STIM, t)
    assert np.max(np.abs(twitch[::5] - ref)) < 2e-6 * ref.max()


def test_step_convergence():
    fine = twitch_moment(T_DATA, STIM, S3, THETA, step_s=1.25e-4)[0]
    coarse = twitch_moment(T_DATA, STIM, S3, THETA, step_s=5e-4)[0]
    assert np.max(np.abs(fine - coarse)) < 1e-6 * fine.max()
    s1 = SUBJECTS["1"]                                # stiffest SEE: relaxation after a 24 Hz train
    a = simulate_isometric(train_times(24, 1.0), 1.5, s1, THETA, step_s=5e-4).moment_nm
    b = simulate_isometric(train_times(24, 1.0), 1.5, s1, THETA, step_s=1.25e-4).moment_nm[::4]
    assert np.max(np.abs(a - b)) < 1e-5 * b.max()


def test_moment_sensitivities_match_finite_differences():
    sol = simulate_isometric_solution(STIM, 0.6, S3, THETA, sensitivities=True)
    for k in range(5):
        v = THETA.as_array()
        h = 1e-6 * v[k]
        up, dn = v.copy(), v.copy()
        up[k] += h
        dn[k] -= h
        fd = (simulate_isometric(STIM, 0.6, S3, ExcitationTheta.from_array(up)).moment_nm
              - simulate_isometric(STIM, 0.6, S3, ExcitationTheta.from_array(dn)).moment_nm) / (2 * h)
        an = sol.dmoment_dtheta[:, k]
        assert np.max(np.abs(an - fd)) < 1e-5 * np.max(np.abs(an)), THETA_NAMES[k]


def test_rise_time_under_full_activation():
    """Seed 3.3: with q = 1 the moment's 10-90 % rise time is 200 ms on average over the four subjects."""
    rts = {k: moment_rise_time_s(s) for k, s in SUBJECTS.items()}
    assert np.mean(list(rts.values())) == pytest.approx(0.200, abs=0.01)
    assert rts["1"] == pytest.approx(0.164, abs=0.002) and rts["3"] == pytest.approx(0.244, abs=0.002)


def test_simulation_bad_inputs():
    with pytest.raises(InputError, match="subject must be a Subject"):
        simulate_isometric(STIM, 0.5, {"k_see": 377}, THETA)
    with pytest.raises(InputError, match="joint_angle_rad"):
        simulate_isometric(STIM, 0.5, S3, THETA, joint_angle_rad=math.nan)
    with pytest.raises(InputError, match="step_s"):
        simulate_isometric(STIM, 0.5, S3, THETA, step_s=-1e-3)
