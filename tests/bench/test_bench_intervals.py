"""The coverage study's pieces (neuromuscle.bench.intervals): the transducer noise it adds and its data sets."""

import numpy as np
import pytest

from neuromuscle.bench.intervals import ar1_noise, noise_free_trials
from neuromuscle.errors import InputError
from neuromuscle.parameters import ParameterSet


def test_ar1_noise_has_the_stated_sd_and_correlation_time():
    x = ar1_noise(200_000, 0.02, 10.0, 1.0, np.random.default_rng(0))
    assert np.std(x) == pytest.approx(0.02, rel=0.03)
    assert np.corrcoef(x[1:], x[:-1])[0, 1] == pytest.approx(np.exp(-0.1), abs=0.005)
    white = ar1_noise(200_000, 0.02, 0.0, 1.0, np.random.default_rng(0))
    assert abs(np.corrcoef(white[1:], white[:-1])[0, 1]) < 0.01


def test_example_data_needs_the_example_base(ct09):
    with pytest.raises(InputError, match="example"):
        noise_free_trials(ParameterSet("other", ct09.values), {"C3": 55.0}, "example")
    with pytest.raises(InputError, match="data must be one of"):
        noise_free_trials(ct09, {"C3": 55.0}, "recorded")
