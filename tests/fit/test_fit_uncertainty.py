"""Uncertainty and identifiability (neuromuscle.fit.uncertainty): the flags of a fit; both fitting engines speak
one vocabulary and agree on a linear least-squares problem."""

import numpy as np
from fit_synthetic import OPTS
from scipy.stats import t as student_t

from neuromuscle.fit import FitProblem, Rules, Uncertainty, estimate_uncertainty, fit, levenberg_marquardt
from neuromuscle.fit.optimizers import fd_jacobian


def test_parameter_without_effect_is_flagged(ct09, twitch_trials):
    # beta acts only during movement (eq 20): an isometric twitch says nothing about it
    problem = FitProblem(twitch_trials[:1], ct09, ["C3", "beta"], options=OPTS)
    res = fit(problem, progress=False, max_iterations=10)
    assert res.unidentifiable == ["beta"]
    assert "no effect" in res.flags["beta"]
    assert res.std_errors["beta"] == np.inf
    assert res.identifiable["C3"]


def test_near_singular_pair_is_flagged(ct09, twitch_trials):
    # C4 and C5 only shape tau(x) = C3 / cosh((x - C4) / (2 C5)) far from its peak: one twitch sees one
    # combination of them
    problem = FitProblem(twitch_trials[:1], ct09, ["C4", "C5"], options=OPTS)
    res = fit(problem, progress=False, max_iterations=5)
    assert set(res.unidentifiable) == {"C4", "C5"}
    assert res.singular_values[-1] < 1e-3 * res.singular_values[0]


# ------------------------------------------------------------------------ one vocabulary for both engines

def _linear_problem():
    """y = X b + e with a known design X (n = 40, k = 3, columns of very different scale) and noise e: the
    least-squares estimate, s^2 = |r|^2 / (n - k) and its covariance s^2 (X^T X)^-1 are exact."""
    rng = np.random.default_rng(11)
    x = np.column_stack([np.ones(40), np.linspace(0.0, 2.0, 40), 50.0 * rng.normal(size=40)])
    y = x @ np.array([1.5, -0.7, 0.02]) + rng.normal(0.0, 0.1, 40)
    b, *_ = np.linalg.lstsq(x, y, rcond=None)
    r = x @ b - y
    cov = float(r @ r) / (40 - 3) * np.linalg.inv(x.T @ x)
    return x, y, b, cov


def _identity(z):
    return np.asarray(z, dtype=float)


def test_both_engines_agree_on_linear_least_squares():
    """The muscle fit (finite-difference Jacobian, Rules.for_fit) and the twitch fit (Levenberg-Marquardt with
    the analytic Jacobian, Rules.for_twitch_fit) give the same Uncertainty on a linear problem, equal to the
    textbook covariance s^2 (X^T X)^-1 and intervals b +/- t_{0.975, n-k} SE."""
    x, y, b, cov = _linear_problem()
    names = ("b0", "b1", "b2")
    k = len(names)
    big = np.full(k, 1e3)

    def run_all(zs):
        return [x @ z - y for z in zs]

    jac, r = fd_jacobian(b, -big, big, run_all, "central", 1e-3, None)
    muscle = estimate_uncertainty(names, b, jac, r, _identity, np.ones(k), Rules.for_fit())
    lm = levenberg_marquardt(lambda p: (x @ p - y, x), np.zeros(k))
    twitch = estimate_uncertainty(names, lm.x, x, x @ lm.x - y, _identity, np.ones(k), Rules.for_twitch_fit())
    assert type(muscle) is type(twitch) is Uncertainty
    se = np.sqrt(np.diag(cov))
    tq = student_t.ppf(0.975, 40 - k)
    for u in (muscle, twitch):
        assert u.dof == 40 - k and u.flags == {} and all(u.identifiable.values())
        np.testing.assert_allclose([u.estimates[n] for n in names], b, rtol=1e-9)
        np.testing.assert_allclose([u.std_errors[n] for n in names], se, rtol=1e-7)
        np.testing.assert_allclose([u.ci95[n] for n in names], np.column_stack([b - tq * se, b + tq * se]),
                                   rtol=1e-7)
        np.testing.assert_allclose(u.correlation, cov / np.outer(se, se), rtol=1e-7, atol=1e-12)
        np.testing.assert_allclose(u.residual_sigma ** 2, float((x @ b - y) @ (x @ b - y)) / (40 - k), rtol=1e-9)
    for field in ("std_errors", "vif"):
        np.testing.assert_allclose(list(getattr(muscle, field).values()), list(getattr(twitch, field).values()),
                                   rtol=1e-7)
    np.testing.assert_allclose(muscle.singular_values, twitch.singular_values, rtol=1e-7)


def test_rules_differ_where_documented():
    """Exactly collinear columns: the muscle fit's rule gives infinite SEs and flags the pair as a near-singular
    direction; the twitch fit's pseudo-inverse drops that direction (finite SEs and VIFs)."""
    x, y, b, _ = _linear_problem()
    x = np.column_stack([x, 2.0 * x[:, 1]])
    names = ("b0", "b1", "b2", "b3")
    z = np.append(b, 0.0)
    r = x @ z - y
    muscle = estimate_uncertainty(names, z, x, r, _identity, np.ones(4), Rules.for_fit())
    twitch = estimate_uncertainty(names, z, x, r, _identity, np.ones(4), Rules.for_twitch_fit())
    assert muscle.std_errors["b1"] == muscle.std_errors["b3"] == np.inf
    assert set(muscle.flags) == {"b1", "b3"} and "near-singular" in muscle.flags["b1"]
    assert muscle.identifiable["b0"] and muscle.identifiable["b2"]
    assert all(np.isfinite(v) for v in twitch.std_errors.values())
    assert all(np.isfinite(v) for v in twitch.vif.values())


def test_covariance_through_a_coupled_map():
    """D cov_z D^T for a full dp/dz; an unidentified z makes every parameter it reaches unidentified."""
    from neuromuscle.fit.uncertainty import _to_parameter_units

    cov_z = np.array([[0.04, 0.01], [0.01, 0.09]])
    d = np.array([[2.0, 0.0], [0.5, 3.0]])
    np.testing.assert_allclose(_to_parameter_units(cov_z, d), d @ cov_z @ d.T)
    np.testing.assert_allclose(_to_parameter_units(cov_z, np.array([2.0, 3.0])), cov_z * np.outer([2, 3], [2, 3]))
    cov_z[0, 0] = np.inf
    out = _to_parameter_units(cov_z, d)
    assert np.all(np.isinf(out))
    d[1, 0] = 0.0
    out = _to_parameter_units(cov_z, d)
    assert np.isinf(out[0, 0]) and np.isfinite(out[1, 1])
