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
