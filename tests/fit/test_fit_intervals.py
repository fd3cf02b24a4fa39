"""Interval methods (neuromuscle.fit.uncertainty covariances, neuromuscle.fit.intervals): the HAC covariance holds
its nominal coverage under AR(1) noise where the iid one does not; the integrator's error widens the interval on
the side of the truth; a fit names its interval method."""

import json

import numpy as np
import pytest
from fit_synthetic import OPTS
from scipy.signal import lfilter

from neuromuscle.errors import InputError
from neuromuscle.fit import (INTERVAL_METHODS, FitProblem, Rules, describe_method, estimate_uncertainty, fit,
                             fit_uncertainty)

NAMES = ("b0", "b1", "b2")
TRUE_B = np.array([1.0, -0.5, 0.3])


def _design(segments=3, m=300):
    """Three smooth regressors (constant, ramp, a sine shifted per segment) over ``segments`` series of m."""
    t = np.linspace(0.0, 1.0, m)
    return np.vstack([np.column_stack([np.ones(m), t, np.sin(3.0 * t + i)]) for i in range(segments)])


def _ar1(n, phi, rng, sd=0.1):
    x = sd * rng.standard_normal(n)
    x[1:] *= np.sqrt(1.0 - phi * phi)
    return lfilter([1.0], [1.0, -phi], x)


def _intervals(x, y, covariance, segments, model_error=None):
    b, *_ = np.linalg.lstsq(x, y, rcond=None)
    return estimate_uncertainty(NAMES, b, x, x @ b - y, lambda z: np.asarray(z, dtype=float), np.ones(3),
                                Rules.for_fit(), covariance=covariance, segments=segments, model_error=model_error)


def _coverage(phi, covariance, draws=400, segments=3, m=300):
    rng = np.random.default_rng(5)
    x = _design(segments, m)
    held = np.zeros(3)
    for _ in range(draws):
        y = x @ TRUE_B + np.concatenate([_ar1(m, phi, rng) for _ in range(segments)])
        u = _intervals(x, y, covariance, [m] * segments)
        held += [u.ci95[n][0] <= b <= u.ci95[n][1] for n, b in zip(NAMES, TRUE_B)]
    return held / draws


def test_hac_coverage_is_nominal_under_ar1_noise():
    """AR(1) noise with lag-1 correlation 0.9 (10 ms at 1 kHz): HAC intervals hold the truth about 95 % of
    the time (400 draws: binomial SD 1.1 %); the iid intervals, about a third of the time."""
    hac = _coverage(0.9, "hac")
    iid = _coverage(0.9, "iid")
    assert np.all((hac > 0.91) & (hac < 0.98)), hac
    assert np.all(iid < 0.6), iid


def test_hac_matches_iid_on_white_noise_and_is_wider_on_correlated():
    x = _design()
    rng = np.random.default_rng(2)
    white = x @ TRUE_B + 0.1 * rng.standard_normal(x.shape[0])
    red = x @ TRUE_B + np.concatenate([_ar1(300, 0.9, rng) for _ in range(3)])
    for y, lo_ratio, hi_ratio in ((white, 0.8, 1.25), (red, 2.5, 10.0)):
        hac = _intervals(x, y, "hac", [300] * 3)
        iid = _intervals(x, y, "iid", [300] * 3)
        assert (hac.method, iid.method) == ("hac", "iid")
        for n in NAMES:
            assert lo_ratio < hac.std_errors[n] / iid.std_errors[n] < hi_ratio, (n, hac.std_errors, iid.std_errors)
            assert hac.estimates[n] == iid.estimates[n]


def test_segments_keep_lags_inside_each_series():
    """Lags never cross a segment boundary: two independent series give the sum of their own middles."""
    x = _design(2)
    rng = np.random.default_rng(3)
    y = x @ TRUE_B + np.concatenate([_ar1(300, 0.8, rng) for _ in range(2)])
    one = _intervals(x, y, "hac", None)
    two = _intervals(x, y, "hac", [300, 300])
    assert one.std_errors != two.std_errors
    with pytest.raises(InputError, match="segments"):
        _intervals(x, y, "hac", [300, 299])
    with pytest.raises(InputError, match="covariance"):
        _intervals(x, y, "newey", None)


def test_model_error_widens_toward_the_truth():
    """A model whose values are too high by e = 0.02 x column 1 (a numerical error) makes the fit's b1 too low
    by 0.02: numerical_bias says so and the interval reaches 0.02 further up, nothing else moves."""
    x = _design()
    y = x @ TRUE_B + 0.01 * np.random.default_rng(4).standard_normal(x.shape[0])
    plain = _intervals(x, y, "iid", None)
    widened = _intervals(x, y, "iid", None, model_error=0.02 * x[:, 1])
    assert widened.method == "iid+integrator" and plain.numerical_bias == dict.fromkeys(NAMES, 0.0)
    np.testing.assert_allclose([widened.numerical_bias[n] for n in NAMES], [0.0, -0.02, 0.0], atol=1e-12)
    assert widened.ci95["b1"][1] == pytest.approx(plain.ci95["b1"][1] + 0.02)
    assert widened.ci95["b1"][0] == plain.ci95["b1"][0] and widened.ci95["b0"] == plain.ci95["b0"]
    assert widened.std_errors == plain.std_errors


def test_fit_names_its_interval_method(ct09, twitch_trials, tmp_path):
    """NEURON: the default fit's intervals are HAC plus the integrator's error (named in the result, its summary
    and the report); the old ones stay available and come from the same fit."""
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], options=OPTS)
    res = fit(problem, progress=False, max_iterations=5)
    assert res.interval_method == INTERVAL_METHODS[0] == "hac+integrator"
    assert describe_method(res.interval_method) in res.summary()
    assert all(v != 0.0 for v in res.uncertainty.numerical_bias.values())
    sims = [res.simulated[t.trial_id] for t in twitch_trials]
    old = fit_uncertainty(problem, res.z, res.jacobian, sims, "iid")
    assert old.method == "iid" and old.estimates == res.estimates
    assert fit(problem, progress=False, max_iterations=5, intervals="iid").ci95 == old.ci95
    with pytest.raises(InputError, match="intervals"):
        fit(problem, progress=False, intervals="bootstrap")


def test_fit_report_names_interval_method(tmp_path):
    from neuromuscle.cli import main
    from neuromuscle.measured import example_path

    out = tmp_path / "report"
    assert main(["fit", str(example_path()), "--out", str(out), "--free", "C3", "--trials", "twitch_opt",
                 "--dt-ms", "0.1", "--max-iterations", "4", "--quiet", "--intervals", "hac"]) == 0
    doc = json.loads((out / "fit.json").read_text())
    assert doc["fit"]["interval_method"] == "hac"
    assert doc["fit"]["interval_method_text"] == describe_method("hac")
    assert describe_method("hac") in (out / "summary.md").read_text()
