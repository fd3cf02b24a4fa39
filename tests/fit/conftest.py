"""Trials shared by the fit tests."""

import pytest
from fit_synthetic import synthetic_trial


@pytest.fixture(scope="session")
def twitch_trials(ct09):
    return [synthetic_trial(ct09, "twitch", [0.02]),
            synthetic_trial(ct09, "train20", [0.02, 0.07, 0.12, 0.17], seed=1)]
