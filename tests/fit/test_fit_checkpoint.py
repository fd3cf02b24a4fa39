"""Checkpoint and resume (neuromuscle.fit.checkpoint)."""

import json
import math

import pytest
from fit_synthetic import OPTS, far_start

from neuromuscle.errors import InputError
from neuromuscle.fit import FitProblem, fit, read_checkpoint


def test_checkpoint_written_and_resume_continues(ct09, twitch_trials, tmp_path, capsys):
    path = tmp_path / "fit.json"
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    first = fit(problem, progress=True, checkpoint=path, max_iterations=2)
    assert "iter   2" in capsys.readouterr().err
    doc = json.loads(path.read_text())
    assert doc["free"] == ["C3", "C1"] and len(doc["history"]) == 2
    assert doc["best"] == first.estimates and doc["best_cost"] == pytest.approx(first.cost)
    assert read_checkpoint(path, problem)["n_simulations"] == first.n_simulations
    second = fit(problem, progress=False, checkpoint=path, resume=True)
    assert second.history[:2] == json.loads(json.dumps(first.history))
    assert second.n_iterations > 2 and second.n_simulations > first.n_simulations
    assert second.cost < first.cost
    assert abs(second.estimates["C3"] / ct09["C3"] - 1) < 0.01
    assert json.loads(path.read_text())["finished"] is True
    with pytest.raises(InputError, match="fits"):
        fit(FitProblem(twitch_trials, ct09, ["C3"], options=OPTS), checkpoint=path, resume=True)


def test_fit_stopped_for_a_continuation_makes_no_jacobian_at_its_end(ct09, twitch_trials):
    """final_jacobian=False: a fit stopped at max_iterations skips the Jacobian its intervals alone would need
    (one run of every trial per free parameter) and says its uncertainty was not made; the estimate is the same."""
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    kw = {"progress": False, "fd": "forward", "intervals": "hac"}
    full = fit(problem, max_iterations=1, **kw)
    lean = fit(problem, max_iterations=1, final_jacobian=False, **kw)
    assert "max_iterations" in lean.message
    assert lean.estimates == full.estimates and lean.cost == full.cost
    assert full.n_simulations - lean.n_simulations == 3 * len(twitch_trials)  # the point and one step per parameter
    assert lean.jacobian is None and full.jacobian is not None
    assert lean.interval_method == "none" and not any(lean.identifiable.values())
    assert all(lo == -math.inf and hi == math.inf for lo, hi in lean.ci95.values())
    converged = fit(problem, final_jacobian=False, **kw)  # not stopped: intervals as always
    assert "max_iterations" not in converged.message and converged.jacobian is not None
    assert converged.interval_method == full.interval_method
