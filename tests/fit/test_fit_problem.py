"""What to fit (neuromuscle.fit.problem): frozen parameters and input errors."""

import numpy as np
import pytest
from fit_synthetic import OPTS

from neuromuscle.errors import InputError
from neuromuscle.fit import FitProblem, fit
from neuromuscle.measured import Trial


def test_frozen_parameter_stays_fixed(ct09, twitch_trials):
    problem = FitProblem(twitch_trials[:1], ct09, ["C3"], frozen={"C4": -12.0}, options=OPTS)
    res = fit(problem, progress=False, max_iterations=4)
    assert res.parameters["C4"] == -12.0
    assert "C4" not in res.estimates


def test_input_errors(ct09, twitch_trials):
    with pytest.raises(InputError, match="unknown free parameter.*'C9'"):
        FitProblem(twitch_trials, ct09, ["C3", "C9"])
    with pytest.raises(InputError, match="'C3': start 61.206 ms is outside its bounds"):
        FitProblem(twitch_trials, ct09, {"C3": (70.0, 90.0)})
    with pytest.raises(InputError, match="both free and frozen"):
        FitProblem(twitch_trials, ct09, ["C3"], frozen={"C3": 50.0})
    passive = Trial(trial_id="passive", protocol="twitch", time_s=np.arange(0, 0.1, 0.001),
                    force=np.zeros(100), force_unit="N", length_unit="mm", length_const=-8.0)
    with pytest.raises(InputError, match="trial 'passive' has no stimulus.*Module 1/2 parameter.*C1"):
        FitProblem([twitch_trials[0], passive], ct09, ["C1"])
    with pytest.raises(InputError, match="objective"):
        FitProblem(twitch_trials, ct09, ["C3"], objective="mae")
    problem = FitProblem(twitch_trials, ct09, ["C3"], options=OPTS)
    with pytest.raises(InputError, match="method"):
        fit(problem, method="nelder")
    with pytest.raises(InputError, match="not found"):
        fit(problem, checkpoint="/nonexistent/fit.json", resume=True)


def test_free_c0_and_p0_never_cross_the_asymptote(ct09, twitch_trials):
    """Eq 11 needs c0 > -P0: with both free, c0 is searched as a fraction of P0, so every corner of the search box
    (P0 at a tenth of its start, c0 at twice its start) is a valid parameter set."""
    base = ct09.with_values(c0=-0.8 * ct09["P0"])
    problem = FitProblem(twitch_trials[:1], base, ["P0", "c0"], options=OPTS)
    lo, hi = problem.z_bounds()
    for z in ([lo[0], lo[1]], [lo[0], hi[1]], [hi[0], lo[1]], [hi[0], hi[1]]):
        vals = problem.to_values(z)
        assert vals["c0"] / vals["P0"] >= -0.999
        problem.parameters(z)  # admissible: KimForce's check would refuse otherwise
    z = np.array([0.3, -0.2])
    np.testing.assert_allclose(problem.to_z(problem.to_values(z)), z, atol=1e-12)
    assert problem.reference()["c0"]["of"] == "c0/P0"


def test_coupled_search_derivative_matches_finite_differences(ct09, twitch_trials):
    problem = FitProblem(twitch_trials[:1], ct09, ["C3", "P0", "c0"], options=OPTS)
    z = np.array([0.1, 0.2, -0.1])
    jac = problem.dp_dz(z)
    assert jac.shape == (3, 3)
    h = 1e-6
    for j in range(3):
        dz = np.zeros(3)
        dz[j] = h
        up, down = problem.to_values(z + dz), problem.to_values(z - dz)
        np.testing.assert_allclose([(up[n] - down[n]) / (2 * h) for n in problem.free], jac[:, j], rtol=1e-6,
                                   atol=1e-9)


def test_one_of_p0_and_c0_free_keeps_the_asymptote(ct09, twitch_trials):
    base = ct09.with_values(c0=-0.9 * ct09["P0"])
    alone = FitProblem(twitch_trials[:1], base, ["P0"], options=OPTS)
    assert alone.bounds["P0"][0] >= -base["c0"] / 0.999
    assert np.ndim(alone.dp_dz(np.zeros(1))) == 1
    c0_alone = FitProblem(twitch_trials[:1], base, ["c0"], options=OPTS)
    assert c0_alone.bounds["c0"][0] >= -0.999 * base["P0"]
    with pytest.raises(InputError, match="eq 11 needs c0 > -P0"):
        FitProblem(twitch_trials[:1], base, ["P0"], start={"P0": 0.5 * base["P0"]}, options=OPTS)


def test_a_sample_of_weight_zero_leaves_the_objective(ct09, twitch_trials):
    """Per-sample weights scale each residual by their square root: samples of weight 0 contribute nothing, and a
    trial without weights counts every sample."""
    trials = twitch_trials[:2]
    n = trials[0].n_samples
    w = np.ones(n)
    w[n // 2:] = 0.0
    plain = FitProblem(trials, ct09, ["C3"], options=OPTS)
    masked = FitProblem(trials, ct09, ["C3"], options=OPTS, sample_weights=[w, None])
    sims = plain.simulate_trials(plain.to_z(plain.start))
    r_plain, r_masked = plain.residuals_from(sims), masked.residuals_from(sims)
    assert np.all(r_masked[n // 2:n] == 0.0) and np.any(r_plain[n // 2:n] != 0.0)
    assert np.array_equal(r_masked[:n // 2], r_plain[:n // 2]) and np.array_equal(r_masked[n:], r_plain[n:])
    with pytest.raises(InputError, match="one entry per trial"):
        FitProblem(trials, ct09, ["C3"], sample_weights=[w])
    with pytest.raises(InputError, match=f"trial '{trials[1].trial_id}': sample weights must be"):
        FitProblem(trials, ct09, ["C3"], sample_weights=[w, -np.ones(trials[1].n_samples)])
