"""neuromuscle.analysis.metrics: eq 17 (NRMSE)."""

import numpy as np
import pytest

from neuromuscle.analysis.metrics import nrmse_percent
from neuromuscle.errors import InputError


def test_nrmse_percent():
    measured = np.array([0.0, 1.0, 2.0, 3.0])
    assert nrmse_percent(measured, measured) == 0.0
    assert nrmse_percent(measured, measured + 0.5) == pytest.approx(100.0 * 0.5 / 3.0)
    assert nrmse_percent([1.0, 3.0], [2.0, 2.0]) == pytest.approx(50.0)


@pytest.mark.parametrize("measured, simulated, culprit", [
    ([0.0, 1.0, 2.0], [0.0, 1.0], "simulated"),
    ([0.0, np.nan, 2.0], [0.0, 1.0, 2.0], "measured"),
    ([0.0, 1.0, 2.0], [0.0, np.inf, 2.0], "simulated"),
    ([2.0, 2.0, 2.0], [0.0, 1.0, 2.0], "zero range"),
    ([], [], "measured"),
])
def test_nrmse_bad_inputs(measured, simulated, culprit):
    with pytest.raises(InputError, match=culprit):
        nrmse_percent(measured, simulated)

