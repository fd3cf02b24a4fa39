"""neuromuscle.analysis.inverse: activation A(t) from force and length, against an independent forward Module 3."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from neuromuscle.analysis.inverse import inverse_activation
from neuromuscle.errors import InputError

#: Module 3 of CT09 (Table 1): N, mm^-1, mm, N, mm/s.
CT09_M3 = dict(P0=23.0, KSE=0.4, g1=-8.0, g2=21.4, a0=2.35, b0=24.35, c0=-7.4, d0=30.3)


def _ce_velocity(force, fc, p):
    """Eqs 10/11: CE velocity (mm/s) under force F (N) with contractile force Fc (N)."""
    if force <= fc:
        return -p["b0"] * (fc - force) / (force + p["a0"] * fc / p["P0"])
    return -p["d0"] * (fc - force) / (2.0 * fc - force + p["c0"] * fc / p["P0"])


def _activation(t_ms):
    """A known smooth activation between 0.05 and 0.55."""
    return 0.05 + 0.5 * 0.5 * (1.0 - np.cos(2.0 * np.pi * t_ms / 800.0))


def _length(t_ms):
    """A slowly varying length (mm) around the optimum: up to 12.6 mm/s."""
    return -8.0 + 3.0 * np.sin(2.0 * np.pi * t_ms / 1500.0)


def _simulate_module3(t_ms, p):
    """Forward Module 3 with SciPy: F = P0 KSE (Xm - XCE), dXCE/dt = v(F, Fc) / 1000 per ms, Fc = P0 g A."""
    stiffness = p["P0"] * p["KSE"]

    def contractile(t):
        return p["P0"] * np.exp(-(((_length(t) - p["g1"]) / p["g2"]) ** 2)) * _activation(t)

    def rhs(t, y):
        force = stiffness * (_length(t) - y[0])
        return [_ce_velocity(force, contractile(t), p) / 1000.0]

    xce0 = _length(0.0) - contractile(0.0) / stiffness  # start in isometric equilibrium
    sol = solve_ivp(rhs, (t_ms[0], t_ms[-1]), [xce0], method="DOP853", rtol=1e-11, atol=1e-12,
                    dense_output=True, max_step=1.0)
    assert sol.success
    xce = sol.sol(t_ms)[0]
    force = stiffness * (_length(t_ms) - xce)
    assert np.all(force > 0.0)
    return force, np.gradient(xce, t_ms) * 1000.0


@pytest.fixture(scope="module")
def module3_run():
    t = np.arange(0.0, 2000.0 + 1e-9, 0.1)
    force, v_ce = _simulate_module3(t, CT09_M3)
    return t, force, v_ce


def test_forward_run_uses_both_branches(module3_run):
    _, _, v_ce = module3_run
    assert v_ce.min() < -1.0 and v_ce.max() > 1.0


def test_inverse_activation_round_trip(module3_run):
    t, force, _ = module3_run
    estimate = inverse_activation(t, force, _length(t), CT09_M3)
    assert isinstance(estimate, np.ndarray) and estimate.shape == t.shape
    truth = _activation(t)
    np.testing.assert_allclose(estimate, truth, rtol=1e-2)
    assert np.max(np.abs(estimate / truth - 1.0)) < 1e-4  # noise-free: far better than 1 %


def test_inverse_activation_round_trip_non_uniform_time(module3_run):
    rng = np.random.default_rng(0)
    t = np.sort(np.concatenate(([0.0, 2000.0], rng.uniform(0.0, 2000.0, 15000))))
    force, _ = _simulate_module3(t, CT09_M3)
    estimate = inverse_activation(t, force, _length(t), CT09_M3)
    np.testing.assert_allclose(estimate, _activation(t), rtol=1e-2)


def test_inverse_activation_wrong_time_unit_fails(module3_run):
    """Guards the ms -> s conversion: a time base in seconds mistaken for ms gives a visibly wrong A."""
    t, force, _ = module3_run
    estimate = inverse_activation(t / 1000.0, force, _length(t), CT09_M3)
    assert np.nanmax(np.abs(estimate / _activation(t) - 1.0)) > 0.1


def test_inverse_activation_smoothing(module3_run):
    t, force, _ = module3_run
    truth = _activation(t)
    clean = inverse_activation(t, force, _length(t), CT09_M3, smooth_ms=5.0)
    np.testing.assert_allclose(clean, truth, rtol=1e-2)
    noisy = force + np.random.default_rng(1).normal(0.0, 2e-3, t.size)  # 2 mN noise

    def error(estimate):  # the first and last half-window of the filter are less reliable
        inner = (t >= 20.0) & (t <= t[-1] - 20.0)
        return np.max(np.abs(estimate[inner] / truth[inner] - 1.0))

    raw_error = error(inverse_activation(t, noisy, _length(t), CT09_M3))
    smooth_error = error(inverse_activation(t, noisy, _length(t), CT09_M3, smooth_ms=20.0))
    assert smooth_error < 0.01 < 0.1 < raw_error


def test_inverse_activation_isometric_is_static():
    t = np.arange(0.0, 100.0, 0.5)
    force = np.full(t.size, 5.0)
    estimate = inverse_activation(t, force, np.full(t.size, -16.0), CT09_M3)
    np.testing.assert_allclose(estimate, 5.0 / (23.0 * np.exp(-((8.0 / 21.4) ** 2))))


def test_inverse_activation_beyond_hill_asymptote_is_nan():
    t = np.arange(0.0, 10.0, 0.1)
    vmax = CT09_M3["b0"] * CT09_M3["P0"] / CT09_M3["a0"]  # mm/s
    length = -8.0 - 1.5 * vmax * t / 1000.0
    estimate = inverse_activation(t, np.full(t.size, 2.0), length, CT09_M3)
    assert np.all(np.isnan(estimate))


@pytest.mark.parametrize("change, culprit", [
    (dict(t_ms=[0.0, 1.0, 1.0, 2.0]), "t_ms"),
    (dict(t_ms=[0.0, 1.0]), "t_ms"),
    (dict(force_N=[1.0, np.nan, 1.0, 1.0]), "force_N"),
    (dict(length_mm=[-8.0, -8.0, -8.0]), "length_mm"),
    (dict(params={k: v for k, v in CT09_M3.items() if k != "KSE"}), "KSE"),
    (dict(params={**CT09_M3, "P0": -1.0}), "P0"),
    (dict(params={**CT09_M3, "c0": np.nan}), "c0"),
    (dict(smooth_ms=-1.0), "smooth_ms"),
    (dict(smooth_ms=0.5), "smooth_ms"),
    (dict(t_ms=[0.0, 1.0, 3.0, 4.0], smooth_ms=2.0), "uniform"),
])
def test_inverse_activation_bad_inputs(change, culprit):
    args = dict(t_ms=[0.0, 1.0, 2.0, 3.0], force_N=[1.0, 1.0, 1.0, 1.0], length_mm=[-8.0] * 4,
                params=CT09_M3, smooth_ms=None)
    args.update(change)
    with pytest.raises(InputError, match=culprit):
        inverse_activation(**args)

