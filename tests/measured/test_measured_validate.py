"""neuromuscle.measured.validate: every rule of the layout, refused naming the file, the trial and the field."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from measured_samples import replace_dataset, set_value, write_raw

from neuromuscle.errors import InputError
from neuromuscle.measured import check_file, read_measured


VIOLATIONS = [
    ("missing schema", lambda h5: h5.attrs.__delitem__("schema"), ["schema"]),
    ("wrong schema", lambda h5: h5.attrs.__setitem__("schema", "neuromuscle.measured/0"), ["schema"]),
    ("NaN in force", set_value("force", 10, np.nan), ["trial 'tw1'", "field 'force'", "non-finite", "index 10"]),
    ("inf in time", set_value("time", 3, np.inf), ["trial 'tw1'", "field 'time'", "non-finite"]),
    ("non-increasing time", set_value("time", 50, 0.2), ["trial 'tw1'", "field 'time'", "strictly increasing"]),
    ("length size mismatch", replace_dataset("length", np.zeros(99)), ["trial 'tw1'", "field 'length'", "99"]),
    ("stimulus outside range", replace_dataset("stimulus_times", np.array([0.1, 5.0])),
     ["trial 'tw1'", "field 'stimulus_times'", "outside"]),
    ("decreasing stimuli", replace_dataset("stimulus_times", np.array([0.5, 0.1])),
     ["trial 'tw1'", "field 'stimulus_times'", "non-decreasing"]),
    ("unknown force unit", lambda h5: h5["trials/tw1"].attrs.__setitem__("force_unit", "kg"),
     ["trial 'tw1'", "force_unit", "'kg'"]),
    ("unknown length unit", lambda h5: h5["trials/tw1"].attrs.__setitem__("length_unit", "cm"),
     ["trial 'tw1'", "length_unit"]),
    ("missing protocol", lambda h5: h5["trials/tw1"].attrs.__delitem__("protocol"), ["trial 'tw1'", "protocol"]),
    ("missing /trials", lambda h5: h5.__delitem__("trials"), ["'/trials'", "missing"]),
    ("empty /trials", lambda h5: [h5["trials"].__delitem__(k) for k in list(h5["trials"])], ["'/trials'"]),
    ("missing time", lambda h5: h5["trials/tw1"].__delitem__("time"), ["trial 'tw1'", "field 'time'", "missing"]),
    ("missing stimulus_times", lambda h5: h5["trials/tw1"].__delitem__("stimulus_times"),
     ["trial 'tw1'", "field 'stimulus_times'"]),
    ("integer time", replace_dataset("time", np.arange(100)), ["trial 'tw1'", "field 'time'", "dtype"]),
    ("no length at all", lambda h5: h5["trials/tw1"].__delitem__("length"), ["trial 'tw1'", "length"]),
    ("length twice, different", lambda h5: h5["trials/tw1"].attrs.__setitem__("length", 1.0),
     ["trial 'tw1'", "length", "both"]),
    ("non-finite length attribute", lambda h5: h5["trials/iso"].attrs.__setitem__("length", np.nan),
     ["trial 'iso'", "attribute 'length'"]),
    ("NaN spike time", lambda h5: h5.create_dataset("motor_units/mu1/spike_times", data=[0.1, np.nan]),
     ["motor unit 'mu1'", "spike_times"]),
]



@pytest.mark.parametrize("mutate, expected", [v[1:] for v in VIOLATIONS], ids=[v[0] for v in VIOLATIONS])
def test_violation_is_refused_naming_file_trial_field(tmp_path: Path, mutate, expected: list[str]) -> None:
    path = write_raw(tmp_path / "data.h5", mutate)
    with pytest.raises(InputError) as info:
        read_measured(path)
    message = str(info.value)
    assert str(path) in message
    for part in expected:
        assert part in message
    with pytest.raises(InputError):
        check_file(path)


def test_length_given_twice_but_equal_is_accepted(tmp_path: Path) -> None:
    path = write_raw(tmp_path / "d.h5", lambda h5: h5["trials/tw1"].attrs.__setitem__("length", 0.0))
    trial = read_measured(path).trials["tw1"]
    assert trial.length_const == 0.0 and trial.length is not None


def test_all_problems_are_listed_in_one_message(tmp_path: Path) -> None:
    def two_faults(h5: h5py.File) -> None:
        h5["trials/tw1/force"][3] = np.nan
        h5["trials/iso"].attrs["force_unit"] = "lbf"
    with pytest.raises(InputError) as info:
        read_measured(write_raw(tmp_path / "d.h5", two_faults))
    message = str(info.value)
    assert "2 problems" in message and "field 'force'" in message and "trial 'iso'" in message

