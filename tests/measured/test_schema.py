"""neuromuscle.measured.schema: the Trial and MeasuredData objects."""

from __future__ import annotations

import numpy as np
import pytest
from measured_samples import make_data

from neuromuscle.errors import InputError


def test_trial_helpers() -> None:
    data = make_data()
    twitch, ramp = data.trials["tw2"], data.trials["tw1"]
    assert twitch.duration_s == pytest.approx(0.5)
    np.testing.assert_array_equal(twitch.length_at([0.0, 0.25]), [-3.0, -3.0])
    assert twitch.length_at().shape == twitch.time_s.shape
    mid = 0.5 * (ramp.time_s[0] + ramp.time_s[-1])
    assert ramp.length_at([mid])[0] == pytest.approx(0.25, abs=1e-3)
    with pytest.raises(InputError, match="tw2"):
        twitch.length_at([1.0])

