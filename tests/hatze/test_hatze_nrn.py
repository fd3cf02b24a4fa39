"""Hatze's excitation as an NMODL mechanism (HatzeExc): agrees with the exact SciPy integration and drives
Module 3 through the same interface as Kim's Modules 1-2."""

import numpy as np
import pytest

from neuromuscle import InputError, simulate
from neuromuscle.hatze.excitation import simulate_excitation
from neuromuscle.model.hatze_parameters import load_theta

STIMS_S = np.array([0.05, 0.15, 0.16, 0.2])


@pytest.fixture(scope="module")
def exact():
    return simulate_excitation(STIMS_S, 0.4, load_theta(), dt_s=1e-4)


@pytest.mark.parametrize("method, tol", [("fixed", 2e-3), ("cvode", 1e-4)])
def test_active_state_matches_exact_solution(ct09, exact, method, tol):
    t_s, _, gamma, q = exact
    r = simulate(ct09, STIMS_S * 1000.0, -8.0, 400.0, method=method, record_dt_ms=0.1, excitation="hatze",
                 rtol=1e-8, record=("force.F", "act.A", "act.g"))
    n = min(r.A.size, q.size)
    assert np.max(np.abs(r.A[:n] - q[:n])) < tol * q.max()
    assert np.max(np.abs(r["act.g"][:n] - gamma[:n])) < 2 * tol * gamma.max()  # gamma (s^4), by its name
    assert r.settings["model"]["act"]["component"] == "HatzeExcitation" and r.ca_M == {}
    with pytest.raises(InputError, match="no trace 'act.atil'"):
        r.atil  # noqa: B018 (Hatze's excitation has no Atil: nothing else is passed off under that name)


def test_hatze_activation_drives_module_3(ct09):
    spikes = np.arange(100.0, 600.0, 50.0)
    fixed = simulate(ct09, spikes, -8.0, 800.0, excitation="hatze")
    cv = simulate(ct09, spikes, -8.0, 800.0, excitation="hatze", method="cvode")
    assert fixed.force_N.max() > 0.3 * ct09["P0"]
    n = min(fixed.force_N.size, cv.force_N.size)
    assert np.max(np.abs(fixed.force_N[:n] - cv.force_N[:n])) < 0.005 * cv.force_N.max()
    # the same spikes through Kim's Modules 1-2 give a different activation
    kim = simulate(ct09, spikes, -8.0, 800.0)
    assert abs(kim.force_N.max() - fixed.force_N.max()) > 0.01


def test_overlapping_pulses_and_unknown_model_are_refused(ct09):
    with pytest.raises(InputError, match="may not overlap"):
        simulate(ct09, [100.0, 100.5], -8.0, 300.0, excitation="hatze")
    with pytest.raises(InputError, match="excitation must be"):
        simulate(ct09, [100.0], -8.0, 300.0, excitation="huxley")


def test_trend_mechanism_matches_exact_solution_and_drives_module_3(ct09):
    """HatzeTrend (eq 10) against its closed-form solution; its A feeds KimForce like any excitation."""
    from neuron import h

    from neuromuscle import MuscleUnit
    from neuromuscle.hatze.excitation import active_state, trend_gamma
    from neuromuscle import Simulator

    th = load_theta()
    with MuscleUnit(ct09, excitation="hatze", name="trend") as unit:
        tr = h.HatzeTrend(unit._sec(0.5))
        tr.m, tr.c, tr.theta5 = 7.94, 3.91e-14, th.theta5
        unit.force._ref_act = tr._ref_A
        unit.length.xm = -8.0
        nu = h.Vector([0.0, 0.0, 0.5, 0.5, 0.0, 0.0])
        tv = h.Vector([0.0, 100.0, 100.0, 1100.0, 1100.0, 1600.0])
        nu.play(tr._ref_nu, tv, 1)
        g, f = h.Vector().record(tr._ref_g, 1.0), h.Vector().record(unit.force._ref_F, 1.0)
        Simulator(dt_ms=0.025).run(1600.0)
        nu.play_remove()
        g, f = np.array(g), np.array(f)
        del tr
    t_s = np.arange(g.size) * 1e-3
    on = (t_s >= 0.1)
    exact = np.where(on, trend_gamma(np.maximum(t_s - 0.1, 0.0), 7.94, 3.91e-14, nu=0.5, train_end_s=1.0), 0.0)
    assert np.max(np.abs(g - exact)) < 2e-3 * exact.max()
    q_end = active_state(exact[1099], 1.0, th.theta5)
    assert f[1099] == pytest.approx(ct09["P0"] * q_end, rel=0.02)  # isometric plateau = P0 g(opt) q


def test_kim_activation_drives_the_angular_complex(ct09):
    """Kim's Modules 1-2 in front of Hatze's muscle-tendon complex: a 40 Hz train gives a fused moment."""
    from neuron import h

    from neuromuscle import MuscleUnit
    from neuromuscle import Simulator

    with MuscleUnit(ct09, name="kim_mtc") as unit:
        unit.length.xm = -8.0
        mtc = h.HatzeMTC(unit._sec(0.5))
        mtc._ref_act = unit.act._ref_A
        unit.add_spike_times(np.arange(100.0, 600.0, 25.0))
        unit.prepare()
        m = h.Vector().record(mtc._ref_M, 1.0)
        a = h.Vector().record(unit.act._ref_A, 1.0)
        Simulator(dt_ms=0.025).run(900.0)
        m, a = np.array(m), np.array(a)
        mmax = mtc.Mmax
        del mtc
    assert 0.8 * mmax < m[550] <= 1.05 * mmax * a[550] + 1e-6
    assert m[850] < 0.2 * m[550]  # relaxes after the train


@pytest.mark.parametrize("excitation", ["kim", "hatze"])
def test_models_are_picked_by_name(ct09, excitation):
    """Any excitation in front of any contraction model, by name; the output reference follows the model."""
    from neuron import h

    from neuromuscle import MuscleUnit
    from neuromuscle import Simulator

    peaks = {}
    for contraction in ("kim", "hatze"):
        with MuscleUnit(ct09, excitation=excitation, contraction=contraction, name="pick") as unit:
            unit.length.xm = -8.0
            unit.add_spike_times(np.arange(100.0, 400.0, 50.0))
            unit.prepare()
            out = h.Vector().record(unit.ref(unit.output), 1.0)
            Simulator(dt_ms=0.025).run(500.0)
            peaks[contraction] = (unit.output, float(np.array(out).max()))
    assert peaks["kim"][0] == "force.F" and peaks["hatze"][0] == "force.M"
    assert peaks["kim"][1] > 1.0 and peaks["hatze"][1] > 1.0
    with pytest.raises(InputError, match="contraction must be"):
        MuscleUnit(ct09, contraction="huxley")
