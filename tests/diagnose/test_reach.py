"""What a model reaches on the held-out trials within its calibration confidence region (``diagnose.reach``): the
bounded move itself, and the held-out forces of a model whose force-length width is off where the calibration
trials do not tell it."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2

from diagnose_datasets import make_data, preparation
from neuromuscle.diagnose.models import FittedModel, simulate_all
from neuromuscle.diagnose.reach import MAX_MOVE, constrained_move, heldout_reach
from neuromuscle.diagnose.residuals import Noise
from neuromuscle.diagnose.selection import Context, reached


def _metric(jc: np.ndarray, q: float) -> np.ndarray:
    return jc.T @ jc + (q / MAX_MOVE ** 2) * np.eye(jc.shape[1])


def test_an_affordable_move_is_the_least_squares_one():
    rng = np.random.default_rng(0)
    jc, jh = rng.normal(size=(40, 3)), rng.normal(size=(30, 3))
    d_true = np.array([0.01, -0.02, 0.015])
    d = constrained_move(jc, jh, jh @ d_true, q=10.0)
    assert np.allclose(d, d_true, atol=1e-9)


def test_a_move_the_calibration_cannot_afford_stops_on_the_bound():
    rng = np.random.default_rng(1)
    jc, jh = 50.0 * rng.normal(size=(40, 3)), rng.normal(size=(30, 3))
    r = jh @ np.array([0.3, -0.2, 0.25])
    q = 7.8
    d = constrained_move(jc, jh, r, q)
    assert float(d @ _metric(jc, q) @ d) == pytest.approx(q, rel=1e-6)
    assert float((r - jh @ d) @ (r - jh @ d)) < float(r @ r)
    # no point of the bound does better (random points on it)
    w, v = np.linalg.eigh(_metric(jc, q))
    for u in rng.normal(size=(200, 3)):
        p = (v / np.sqrt(w)) @ (np.sqrt(q) * u / np.linalg.norm(u))
        assert float((r - jh @ p) @ (r - jh @ p)) >= float((r - jh @ d) @ (r - jh @ d)) - 1e-9


def test_a_direction_the_calibration_pins_is_not_moved_along():
    jc = np.diag([1e4, 1e-3])
    jh = np.eye(2)
    d = constrained_move(jc, jh, np.array([1.0, 0.2]), q=5.0)
    assert abs(d[0]) < 2.5e-4 and d[1] == pytest.approx(0.2, rel=1e-2)   # 1.0 and 0.2 unbounded


def _model(g2_factor: float):
    """The preparation's own parameters but g2 (the force-length curve's width), calibrated on the trials at the
    optimum (which g2 does not change) and judged on those away from it."""
    data = make_data(3)
    params = preparation(3)
    params = params.with_values({"g2": params["g2"] * g2_factor})
    trials = list(data.trials.values())
    model = FittedModel((), params, ("g2", "C1"), None, simulate_all(params, trials))
    noise = {t.trial_id: Noise(0.015 * float(np.ptp(t.force)), 0.6, t.n_samples * 0.25) for t in trials}
    cal = [t for t in trials if t.trial_id.endswith("_opt")]
    held = [t for t in trials if not t.trial_id.endswith("_opt")]
    return data, model, noise, cal, held


def _chi2(forces, trials, noise) -> float:
    return sum(float(((forces[t.trial_id] - t.force) ** 2).sum()) * noise[t.trial_id].chi2_weight for t in trials)


def test_a_width_the_calibration_leaves_open_is_reached_on_the_heldout_trials():
    data, model, noise, cal, held = _model(0.8)
    reach = heldout_reach(model, cal, held, noise)
    assert set(reach) == {t.trial_id for t in held}
    assert all(np.all(np.isfinite(f)) for f in reach.values())
    before, after = _chi2(model.simulated, held, noise), _chi2(reach, held, noise)
    assert after < 0.5 * before


def test_a_model_at_the_truth_reaches_little_further():
    data, model, noise, cal, held = _model(1.0)
    reach = heldout_reach(model, cal, held, noise)
    before, after = _chi2(model.simulated, held, noise), _chi2(reach, held, noise)
    assert after <= before
    assert before - after < chi2.ppf(0.95, 2)


def test_the_reference_is_the_model_itself_without_the_option():
    data, model, noise, cal, held = _model(0.8)
    ctx = Context(data, {}, [t.trial_id for t in cal], [t.trial_id for t in held], noise, model.parameters,
                  ("g2", "C1"))
    assert reached(ctx, model) is model
    ctx.reach = True
    moved = reached(ctx, model)
    assert moved is not model and reached(ctx, model) is moved      # kept per model and noise
    assert all(np.array_equal(moved.simulated[t.trial_id], model.simulated[t.trial_id]) for t in cal)
    assert _chi2(moved.simulated, held, noise) < _chi2(model.simulated, held, noise)


def test_a_heldout_trial_without_a_stimulus_keeps_the_models_force():
    from dataclasses import replace

    data, model, noise, cal, held = _model(0.8)
    passive = replace(held[0], trial_id="passive", stimulus_times_s=np.zeros(0))
    noise["passive"] = noise[held[0].trial_id]
    model.simulated["passive"] = model.simulated[held[0].trial_id] * 0.0
    reach = heldout_reach(model, cal, [passive] + held, noise)
    assert np.array_equal(reach["passive"], model.simulated["passive"])
    assert _chi2(reach, held, noise) < 0.5 * _chi2(model.simulated, held, noise)
