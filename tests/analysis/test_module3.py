"""neuromuscle.analysis.module3: eqs 10-12 and their inverse forms, checked against the spec's linear forms and
against each other."""

import numpy as np
import pytest

from neuromuscle.analysis.module3 import (ce_velocity, contractile_force, force_length, hill_tension,
                                          hill_velocity, mashima_tension, mashima_velocity)

#: Module 3 of CT09 (Table 1): N, N, mm/s, N, mm/s.
P = dict(P0=23.0, a0=2.35, b0=24.35, c0=-7.4, d0=30.3)


def test_force_length_is_a_gaussian_with_its_peak_at_g1():
    assert force_length(-8.0, -8.0, 21.4) == 1.0
    assert force_length(-8.0 + 21.4, -8.0, 21.4, 23.0) == pytest.approx(23.0 / np.e, rel=1e-15)
    np.testing.assert_array_equal(force_length([-16.0, 0.0], -8.0, 21.4), force_length([0.0, -16.0], -8.0, 21.4))


def test_velocities_satisfy_the_linear_forms_of_eqs_10_11():
    """V (F + a0 Fc/P0) = -b0 (Fc - F) and V (2 Fc - F + c0 Fc/P0) = -d0 (Fc - F)."""
    fc = 17.0
    for f in (0.0, 5.0, 16.9):
        v = hill_velocity(f, fc, P["a0"], P["b0"], P["P0"])
        assert v * (f + P["a0"] * fc / P["P0"]) == pytest.approx(-P["b0"] * (fc - f), rel=1e-12)
    for f in (17.1, 20.0, 26.0):
        v = mashima_velocity(f, fc, P["c0"], P["d0"], P["P0"])
        assert v * (2.0 * fc - f + P["c0"] * fc / P["P0"]) == pytest.approx(-P["d0"] * (fc - f), rel=1e-12)
    assert hill_velocity(fc, fc, P["a0"], P["b0"], P["P0"]) == 0.0
    assert mashima_velocity(fc, fc, P["c0"], P["d0"], P["P0"]) == 0.0


def test_tension_of_velocity_inverts_the_velocity_at_full_capacity():
    v_short, v_long = np.array([-160.0, -20.0, -1.0]), np.array([1.0, 20.0, 80.0])
    t_short = hill_tension(v_short, P["a0"], P["b0"], P["P0"])
    t_long = mashima_tension(v_long, P["c0"], P["d0"], P["P0"])
    np.testing.assert_allclose(hill_velocity(t_short, P["P0"], P["a0"], P["b0"], P["P0"]), v_short, rtol=1e-12)
    np.testing.assert_allclose(mashima_velocity(t_long, P["P0"], P["c0"], P["d0"], P["P0"]), v_long, rtol=1e-12)
    assert hill_tension(0.0, P["a0"], P["b0"], P["P0"]) == P["P0"] == mashima_tension(0.0, P["c0"], P["d0"], P["P0"])


def test_contractile_force_inverts_the_velocity_on_both_branches():
    force = np.array([3.0, 10.0, 12.0, 20.0])
    fc = np.array([9.0, 11.0, 10.0, 15.0])
    v = np.array([ce_velocity(f, c, P) for f, c in zip(force, fc)])
    assert v[0] < 0 < v[3]
    np.testing.assert_allclose(contractile_force(force, v, P), fc, rtol=1e-12)
    vmax = P["b0"] * P["P0"] / P["a0"]  # the Hill asymptote (mm/s): no finite Fc shortens faster
    assert np.isnan(contractile_force(np.array([2.0]), np.array([-1.01 * vmax]), P)[0])


def test_ce_velocity_branches_tangent_continuation_and_cap():
    fc = 10.0
    fa = (2.0 + P["c0"] / P["P0"]) * fc  # Mashima asymptote (N)
    fl = fc + 0.95 * (fa - fc)
    assert ce_velocity(5.0, fc, P) == hill_velocity(5.0, fc, P["a0"], P["b0"], P["P0"])
    assert ce_velocity(fl, fc, P) == mashima_velocity(fl, fc, P["c0"], P["d0"], P["P0"])
    above = ce_velocity(fl * (1 + 1e-9), fc, P)
    assert above == pytest.approx(ce_velocity(fl, fc, P), rel=1e-6)  # continuous at the switch
    assert np.isfinite(ce_velocity(fa, fc, P)) and ce_velocity(fa, fc, P) > above  # no blow-up at Fa
    assert ce_velocity(1e9, fc, P) == 1e5
    assert ce_velocity(1.0, 0.0, P) == 1e5 and ce_velocity(0.0, 0.0, P) == 0.0
