"""Hatze's muscle-tendon complex as an NMODL mechanism (HatzeMTC, mod/HatzeMTC.mod): driven by HatzeExc it
reproduces neuromuscle.hatze.contraction's isometric moment, fixed step and CVODE."""

import gc

import numpy as np
import pytest

from neuromuscle import load_mechanisms
from neuromuscle import Simulator
from neuromuscle.hatze.contraction import (equilibrium_phi_ce, moment_rise_time_s, release_profile,
                                           see_extension_at_test, simulate_release,
                                           simulate_active_state_drive, simulate_isometric)
from neuromuscle.hatze.excitation import rise_time_s
from neuromuscle.model.hatze_parameters import load_subject, load_theta

REC_MS = 0.5          # record interval = Python's RK4 step (0.5 ms), so samples coincide
T_END_S = 0.6
TWITCH_S = np.array([0.01])
TRAIN_S = 0.01 + np.arange(10) / 20.0   # 20 Hz, 10 pulses


@pytest.fixture(scope="module")
def h():
    load_mechanisms()
    from neuron import h as hh

    hh.load_file("stdrun.hoc")
    return hh


def _run(method, duration_ms, dt_ms=0.025, atol=1e-6, rtol=1e-8):
    """The package's Simulator (sets and restores NEURON's integrator; CVODE tolerances per state)."""
    Simulator(method=method, dt_ms=dt_ms, atol=atol, rtol=rtol).run(duration_ms)


def _set_subject(mtc, subject):
    mtc.k_see = subject.k_see
    mtc.phi_ce_opt = subject.phi_ce_opt
    mtc.Mmax = subject.m_max
    mtc.a_rel = subject.a_rel
    mtc.b_rel = subject.b_rel
    mtc.w = subject.w
    mtc.k_pee = subject.k_pee
    mtc.phi_pee0_rel = subject.phi_pee0_rel


def run_stimulated(h, stims_s, t_end_s, subject, theta, method, length_dependent=False, dt_ms=0.025):
    """HatzeExc -> HatzeMTC, stimuli (s) as NetCon events; returns (t_s, M, phi_ce, q) sampled every REC_MS."""
    sec = h.Section(name="hatze_mtc_test")
    exc = h.HatzeExc(sec(0.5))
    for n in ("theta1", "theta2", "theta3", "theta4", "theta5"):
        setattr(exc, n, float(getattr(theta, n)))
    mtc = h.HatzeMTC(sec(0.5))
    _set_subject(mtc, subject)
    h.setpointer(exc._ref_A, "act", mtc)
    if length_dependent:
        mtc.xi_feedback = 1
        h.setpointer(exc._ref_xi, "xi_exc", mtc)
    nc = h.NetCon(None, exc)
    nc.weight[0] = 1.0
    times = [float(s) * 1000.0 for s in stims_s]

    def queue():  # runs at finitialize, before the finally block deletes nc
        for tt in times:
            nc.event(tt)  # noqa: F821

    fih = h.FInitializeHandler(queue)
    recs = {k: h.Vector() for k in ("M", "phi", "q")}
    recs["M"].record(mtc._ref_M, REC_MS)
    recs["phi"].record(mtc._ref_phi_ce, REC_MS)
    recs["q"].record(exc._ref_A, REC_MS)
    try:
        _run(method, t_end_s * 1000.0, dt_ms=dt_ms)
        out = {k: np.array(v) for k, v in recs.items()}
        assert mtc.nbad == 0 and mtc.noeq == 0
    finally:
        del fih, nc, recs, mtc, exc, sec
        gc.collect()
    n = out["M"].size
    return np.arange(n) * REC_MS / 1000.0, out["M"], out["phi"], out["q"]


def run_constant_activation(h, q, t_end_s, subject, q_initial, method, offset_rad=0.0, dt_ms=0.025):
    """HatzeMTC with its POINTER act on a MuscleLength.xm that holds the activation: q_initial at finitialize
    (the CE starts at that equilibrium), stepped to q just after."""
    sec = h.Section(name="hatze_mtc_const")
    holder = h.MuscleLength(sec(0.5))
    holder.xm = q_initial
    mtc = h.HatzeMTC(sec(0.5))
    _set_subject(mtc, subject)
    mtc.phi_mtc_offset = offset_rad
    h.setpointer(holder._ref_xm, "act", mtc)

    def step_q():  # runs at finitialize, before the finally block deletes holder
        holder.xm = q  # noqa: F821

    fih = h.FInitializeHandler(1, step_q)   # type 1: after the INITIAL blocks, before CVODE's re-init
    rec = h.Vector()
    rec.record(mtc._ref_M, REC_MS)
    try:
        _run(method, t_end_s * 1000.0, dt_ms=dt_ms)
        m = np.array(rec)
    finally:
        del fih, rec, mtc, holder, sec
        gc.collect()
    return np.arange(m.size) * REC_MS / 1000.0, m


def _leftover(h):
    return len(list(h.List("HatzeMTC"))), len(list(h.List("HatzeExc"))), len(list(h.List("MuscleLength")))


@pytest.fixture(scope="module")
def subject3():
    return load_subject(3)


@pytest.mark.parametrize("stims", [TWITCH_S, TRAIN_S], ids=["twitch", "20Hz"])
@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_isometric_moment_matches_python(h, subject3, stims, method):
    theta = load_theta()
    ref = simulate_isometric(stims, T_END_S, subject3, theta, length_dependent=False)
    t, m, phi, q = run_stimulated(h, stims, T_END_S, subject3, theta, method)
    n = min(m.size, ref.moment_nm.size)
    assert n >= ref.moment_nm.size - 1
    peak = ref.moment_nm.max()
    assert peak > 1.0
    err = np.max(np.abs(m[:n] - ref.moment_nm[:n]))
    assert err < 5e-3 * peak, f"{method}: max |dM| = {err:.4g} N m = {err / peak:.2%} of peak {peak:.4g}"
    assert np.max(np.abs(phi[:n] - ref.phi_ce_rad[:n])) < 5e-3 * (ref.phi_ce_rad.max() - ref.phi_ce_rad.min())
    assert _leftover(h) == (0, 0, 0)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_length_dependent_activation_by_xi_feedback(h, subject3, method):
    """With xi_feedback, HatzeExc gets xi = phi_ce/phi_ce_opt: eq 9's rho*(xi) as in contraction.py's default."""
    theta = load_theta()
    ref = simulate_isometric(TRAIN_S, T_END_S, subject3, theta, length_dependent=True)
    other = simulate_isometric(TRAIN_S, T_END_S, subject3, theta, length_dependent=False)
    _, m, _, _ = run_stimulated(h, TRAIN_S, T_END_S, subject3, theta, method, length_dependent=True)
    n = min(m.size, ref.moment_nm.size)
    peak = ref.moment_nm.max()
    err = np.max(np.abs(m[:n] - ref.moment_nm[:n]))
    assert err < 5e-3 * peak, f"{method}: {err / peak:.2%} of peak"
    # the feedback matters: without it the two Python references differ by far more than that
    assert np.max(np.abs(other.moment_nm - ref.moment_nm)) > 4 * err
    assert _leftover(h) == (0, 0, 0)


def test_initial_state_is_isometric_equilibrium(h, subject3):
    q = 0.3
    off = 0.05
    sec = h.Section(name="hatze_mtc_init")
    holder = h.MuscleLength(sec(0.5))
    holder.xm = q
    mtc = h.HatzeMTC(sec(0.5))
    _set_subject(mtc, subject3)
    mtc.phi_mtc_offset = off
    h.setpointer(holder._ref_xm, "act", mtc)
    try:
        h.finitialize()  # the state NEURON's initialisation gives, before any step
        phi0, m0, om0, e_test = mtc.phi_ce, mtc.M, mtc.omega_ce, mtc.e_test
        _run("fixed", 20.0)
        phi1 = mtc.phi_ce
    finally:
        del mtc, holder, sec
        gc.collect()
    assert phi0 == pytest.approx(equilibrium_phi_ce(subject3, q, off), abs=1e-12)
    assert e_test == pytest.approx(see_extension_at_test(subject3), rel=1e-14)
    assert abs(om0) < 1e-9 and m0 > 0
    assert abs(phi1 - phi0) < 1e-10          # stays there
    assert _leftover(h) == (0, 0, 0)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
@pytest.mark.parametrize("offset", [0.0, -0.1])
def test_constant_activation_step_matches_python(h, subject3, method, offset):
    """q steps from q0 (rest) to 1 at t = 0 (moment_rise_time_s's protocol), and to 0.4 at a shorter MTC."""
    q0 = 0.005
    for q in (1.0, 0.4):
        ref = simulate_active_state_drive(subject3, 1.0, q, offset, q_initial=q0)
        t, m = run_constant_activation(h, q, 1.0, subject3, q0, method, offset_rad=offset)
        n = min(m.size, ref.moment_nm.size)
        peak = ref.moment_nm.max()
        assert np.max(np.abs(m[:n] - ref.moment_nm[:n])) < 5e-3 * peak
        rt = rise_time_s(t[:n], m[:n])
        rt_ref = rise_time_s(ref.t_s, ref.moment_nm)
        assert rt == pytest.approx(rt_ref, rel=5e-3)
        if q == 1.0 and offset == 0.0:
            assert rt_ref == pytest.approx(moment_rise_time_s(subject3, t_end_s=1.0), rel=1e-9)
    assert _leftover(h) == (0, 0, 0)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_release_by_played_mtc_angle_matches_python(h, subject3, method):
    """phi_mtc_offset driven by Vector.play (continuous): contraction.simulate_release's isokinetic release."""
    vel = 3.0
    ref = simulate_release(subject3, vel, t_end_s=0.3)
    tt_s = np.arange(0.0, 0.3 + 1e-12, 2.5e-5)
    prof = release_profile(tt_s, vel, 0.05, 0.005, 1.0)
    sec = h.Section(name="hatze_mtc_release")
    holder = h.MuscleLength(sec(0.5))
    holder.xm = 1.0
    mtc = h.HatzeMTC(sec(0.5))
    _set_subject(mtc, subject3)
    h.setpointer(holder._ref_xm, "act", mtc)
    tvec = h.Vector(tt_s * 1000.0)
    ovec = h.Vector(prof)
    ovec.play(mtc._ref_phi_mtc_offset, tvec, 1)
    rec = h.Vector()
    rec.record(mtc._ref_M, REC_MS)
    try:
        _run(method, 300.0)
        m = np.array(rec)
    finally:
        ovec.play_remove()
        del rec, ovec, tvec, mtc, holder, sec
        gc.collect()
    # ref is sampled at 2 kHz = every 0.5 ms, as REC_MS
    n = min(m.size, ref.moment_nm.size)
    peak = ref.moment_nm.max()
    assert ref.moment_nm.min() < 0.5 * peak            # the release unloads the MTC
    err = np.max(np.abs(m[:n] - ref.moment_nm[:n]))
    print(f"release {method}: {err / peak:.2e} of peak")
    assert err < 5e-3 * peak
    assert _leftover(h) == (0, 0, 0)
