"""neuromuscle.literature.herzog_leonard_2002: the digitized traces load as valid measured data (needs the
real-data folder: the test fails without it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from neuromuscle.literature import load_herzog_leonard_2002
from neuromuscle.measured import find_problems, read_measured, write_measured


def test_herzog_leonard_loader_yields_finite_trials(real_data: Path, tmp_path: Path) -> None:
    data = load_herzog_leonard_2002(real_data / "cat_soleus_herzog_leonard_2002")
    assert len(data.trials) == 21
    assert find_problems(data) == []
    protocols = [t.protocol for t in data.trials.values()]
    assert protocols.count("isometric") == 8 and protocols.count("stretch") == 10
    assert protocols.count("passive") == 3
    for trial in data.trials.values():
        assert trial.force_unit == "N" and trial.length_unit == "mm"
        assert np.all(np.isfinite(trial.force)) and np.all(np.isfinite(trial.length))
        assert np.allclose(np.diff(trial.time_s), 0.01)
        assert trial.stimulus_times_s.size == 0
    # README: peak forces of the 0 -> 9 mm stretches 34.6 / 36.6 / 37.4 N at 3 / 9 / 27 mm/s, passive ~7 N
    peaks = [data.trials[k].force.max() for k in ("Figure7A_F50", "Figure7B_F57", "Figure7C_F65")]
    np.testing.assert_allclose(peaks, [34.6, 36.6, 37.4], atol=0.1)
    assert 6.5 < data.trials["Figure7A_F49"].force.max() < 8.0
    for trial in data.trials.values():
        if "stretch_speed_nominal_mm_s" in trial.attrs:
            nominal = trial.attrs["stretch_speed_nominal_mm_s"]
            assert trial.attrs["ramp_speed_estimated_mm_s"] == pytest.approx(nominal, rel=0.1)
    assert data.trials["Figure5_F31"].force[0] != 0.0  # zero padding trimmed
    assert data.trials["Figure7A_F50"].attrs["keypoints_max_error_N"] < 0.05
    assert read_measured(write_measured(tmp_path / "hl.h5", data)) == data
