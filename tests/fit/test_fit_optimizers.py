"""Optimisers (neuromuscle.fit.optimizers, through fit): recovery of known parameters from synthetic noisy data."""

import numpy as np
import pytest
from fit_synthetic import NOISE_N, OPTS, far_start, synthetic_trial

from neuromuscle.errors import InputError
from neuromuscle.fit import FitProblem, fit
from neuromuscle.fit.optimizers import COST_WINDOW, fd_jacobian, trust_region_least_squares


def test_recovers_C3_C1_from_far_start_inside_ci(ct09, twitch_trials):
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    res = fit(problem, progress=False)
    for name in ("C3", "C1"):
        lo, hi = res.ci95[name]
        assert lo <= ct09[name] <= hi, (name, res.summary())
        assert abs(res.estimates[name] / ct09[name] - 1) < 0.01
    assert res.unidentifiable == []
    assert res.parameters["C3"] == res.estimates["C3"] and res.parameters["C2"] == ct09["C2"]
    assert all(v < 2.0 for v in res.nrmse_percent.values())
    # cost = sum of squared errors, about n * noise^2 at the truth
    n = sum(t.n_samples for t in twitch_trials)
    assert 0.7 * n * NOISE_N ** 2 < res.cost < 1.3 * n * NOISE_N ** 2
    assert res.n_simulations > 0 and res.n_iterations == len(res.history)  # wall time reported, not asserted


def test_recovers_module3_a0_b0_on_isokinetic_trials(ct09):
    def shortening(speed_mm_s):
        return lambda t: -6.0 - speed_mm_s * np.clip(t - 0.1, 0.0, 4.0 / speed_mm_s)
    stim = np.arange(0.0, 0.25, 0.01)
    # (a 95 % interval misses the truth 1 time in 20: with noise seeds 10/40 a0 fell 0.5 % outside)
    trials = [synthetic_trial(ct09, f"iso{v}", stim, length=shortening(v), duration_s=0.25, seed=seed,
                     protocol="isokinetic") for v, seed in ((10, 3), (40, 4))]
    problem = FitProblem(trials, ct09, ["a0", "b0"], start={"a0": 1.5 * ct09["a0"], "b0": 0.7 * ct09["b0"]},
                         options=OPTS, objective="nrmse")
    res = fit(problem, progress=False)
    for name in ("a0", "b0"):
        lo, hi = res.ci95[name]
        assert lo <= ct09[name] <= hi, (name, res.summary())
    assert res.unidentifiable == []


def test_praxis_baseline(ct09, twitch_trials):
    problem = FitProblem(twitch_trials[:1], ct09, ["C3"], start={"C3": 1.3 * ct09["C3"]}, options=OPTS)
    res = fit(problem, method="praxis", progress=False, max_iterations=15)
    assert res.method == "praxis"
    assert abs(res.estimates["C3"] / ct09["C3"] - 1) < 0.005, res.summary()
    lo, hi = res.ci95["C3"]
    assert lo <= ct09["C3"] <= hi


@pytest.mark.parametrize("dt_ms", [0.2, 0.4])
def test_coarse_jacobian_steps_to_the_same_estimate_and_keeps_the_problems_step(ct09, twitch_trials, dt_ms):
    """jacobian_dt_ms: the Jacobian's runs at another step, up to twice the largest step of a result (0.4 ms: only
    differenced); estimate, cost and forces stay at the problem's."""
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    fine = fit(problem, progress=False, fd="forward")
    coarse = fit(problem, progress=False, fd="forward", jacobian_dt_ms=dt_ms)
    for name in ("C3", "C1"):  # the same optimum, to a small fraction of its standard error
        assert abs(coarse.estimates[name] - fine.estimates[name]) < 0.1 * fine.std_errors[name], name
    sims = problem.simulate_trials(coarse.z)  # the forces and the cost are the problem's (0.1 ms), not 0.2 ms
    for t, s in zip(twitch_trials, sims):
        assert np.array_equal(coarse.simulated[t.trial_id], s)
    r = problem.residuals(coarse.z)
    assert coarse.cost == pytest.approx(float(r @ r), rel=1e-12)
    # the Jacobian it used is the coarse one: close to the problem's own, not equal to it
    lo, hi = problem.z_bounds()
    j_fine = fd_jacobian(coarse.z, lo, hi, lambda zs: [problem.residuals(z) for z in zs], "forward", 1e-3, None)[0]
    rel = np.linalg.norm(coarse.jacobian - j_fine) / np.linalg.norm(j_fine)
    assert 0.0 < rel < 0.05, rel


@pytest.mark.parametrize("bad", [0.0, -0.1, float("nan"), 0.5])
def test_jacobian_step_out_of_range_is_refused(ct09, twitch_trials, bad):
    problem = FitProblem(twitch_trials[:1], ct09, ["C3"], options=OPTS)
    with pytest.raises(InputError, match="jacobian_dt_ms"):
        fit(problem, progress=False, jacobian_dt_ms=bad)


class _Costs:
    """A Monitor that keeps the cost at every iteration."""

    def __init__(self) -> None:
        self.best_z, self.best_cost, self.costs = None, float("inf"), []

    def iteration(self, z, cost):
        self.costs.append(cost)
        if cost < self.best_cost:
            self.best_z, self.best_cost = z, cost


def _rosenbrock(zs):
    return [np.array([10.0 * (z[1] - z[0] ** 2), 1.0 - z[0]]) for z in zs]


def test_a_cost_tolerance_stops_a_fit_whose_last_iterations_together_gain_less_than_it():
    """cost_tol is absolute: the fit stops, converged, at the first iterate where the last COST_WINDOW iterations
    together lowered the cost by less than cost_tol, and returns that iterate with its Jacobian; without it the same
    fit runs on to scipy's own tolerance."""
    lo, hi, z0 = np.full(2, -5.0), np.full(2, 5.0), np.array([-1.2, 1.0])
    free = _Costs()
    z_free, message, _ = trust_region_least_squares(z0, lo, hi, _rosenbrock, free, "central", 1e-6, 200, 1e-12)
    assert "max_iterations" not in message and "settled" not in message
    assert np.allclose(z_free, [1.0, 1.0], atol=1e-6)
    gains = -np.diff(free.costs)
    window = [free.costs[k - COST_WINDOW] - free.costs[k] for k in range(COST_WINDOW, len(free.costs))]
    tol = float(np.median(window))  # settles part of the way along the valley
    stop = next(k for k in range(COST_WINDOW, len(free.costs)) if free.costs[k - COST_WINDOW] - free.costs[k]
                < tol)
    settled = _Costs()
    z, message, jr = trust_region_least_squares(z0, lo, hi, _rosenbrock, settled, "central", 1e-6, 200, 1e-12,
                                                cost_tol=tol)
    assert "the cost settled" in message and len(settled.costs) == stop + 1 < len(free.costs)
    assert settled.costs == free.costs[:stop + 1] and np.all(gains[:stop] >= 0)
    j, r = jr
    assert np.array_equal(r, _rosenbrock([z])[0]) and j.shape == (2, 2)
    assert float(r @ r) == settled.costs[-1]


@pytest.mark.parametrize("bad", [0.0, -1.0, "1"])
def test_a_cost_tolerance_that_is_not_a_positive_number_is_refused(ct09, twitch_trials, bad):
    problem = FitProblem(twitch_trials[:1], ct09, ["C3"], options=OPTS)
    with pytest.raises(InputError, match="cost_tolerance"):
        fit(problem, progress=False, cost_tolerance=bad)


@pytest.mark.parametrize("first, offset", [(1.5, 0.0), (-1.0, 0.0), (1.5, 7e-11)])
def test_a_fit_that_stops_where_it_began_on_a_bound_is_started_again_from_inside(first, offset):
    """A linear least-squares problem started on the lower bound of its first parameter (offset 0) or where a
    previous fit left it, a hair inside (offset, a share of the range): scipy's first trust region is about 2e-5 in
    z there, and the fit meets its tolerances at once where it began.  It is started again from RESTART_MARGIN
    inside and reaches the optimum, inside the bounds (first = 1.5) or on the bound it started on (first = -1.0,
    the optimum beyond it)."""
    from neuromuscle.fit.optimizers import RESTART_MARGIN

    a = np.random.default_rng(0).normal(size=(40, 4))
    target = np.array([first, 2.0, -1.0, 0.5])

    def linear(zs):
        return [100.0 * a @ (z - target) for z in zs]

    lo, hi = np.array([0.0, -5.0, -5.0, -5.0]), np.full(4, 5.0)
    costs = _Costs()
    z0 = np.array([offset * (hi - lo)[0], 0.0, 0.0, 0.0])
    z, message, _ = trust_region_least_squares(z0, lo, hi, linear, costs, "forward", 1e-6, 30, 1e-4)
    assert "started again" in message and "max_iterations" not in message
    expected = target.copy()
    if first < 0:  # the bounded optimum: the first parameter on its bound, the others refitted for it
        expected[0] = 0.0
        rest = np.linalg.lstsq(a[:, 1:], a @ target, rcond=None)[0]
        expected[1:] = rest
    np.testing.assert_allclose(z, expected, atol=1e-3)
    assert len(costs.costs) > 2  # it iterated after the start again
    assert RESTART_MARGIN * (hi - lo)[0] < 0.01


def test_a_fit_that_moves_from_a_start_on_a_bound_is_not_started_again():
    """The restart is for a fit that stopped where it began: one whose first steps move keeps its own result."""
    costs = _Costs()
    lo, hi = np.array([-1.2, 0.0]), np.full(2, 5.0)
    z, message, _ = trust_region_least_squares(np.array([-1.2, 0.0]), lo, hi, _rosenbrock, costs, "forward", 1e-6,
                                               200, 1e-10)
    assert "started again" not in message
    np.testing.assert_allclose(z, [1.0, 1.0], atol=1e-3)
