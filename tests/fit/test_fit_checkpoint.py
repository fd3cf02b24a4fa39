"""Checkpoint and resume (neuromuscle.fit.checkpoint)."""

import json

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
