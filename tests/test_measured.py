"""Tests of neuromuscle.measured: the measured-data HDF5 layout, its validator, CSV import and real-data loaders."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Callable

import h5py
import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.measured import (SCHEMA, MeasuredData, Trial, check_file, find_problems, import_csv,
                                  load_herzog_leonard_2002, load_scott_brown_loeb_1996, read_measured,
                                  summarize, write_measured)

REAL_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data"
HERZOG = REAL_DATA / "cat_soleus_herzog_leonard_2002"
DIGITIZED = REAL_DATA / "cat_digitized_literature"


# ------------------------------------------------------------------------------------------------ helpers


def make_data() -> MeasuredData:
    """Two trials (ids deliberately not in alphabetical order), one motor unit, extras."""
    t = np.linspace(0.0, 0.5, 501)
    twitch = Trial(trial_id="tw2", protocol="twitch", time_s=t, force=np.exp(-t / 0.05) * t,
                   force_unit="N", length_unit="mm", length_const=-3.0,
                   stimulus_times_s=np.array([0.01]), attrs={"temperature_C": 37.0, "note": "first"})
    t2 = np.cumsum(np.full(200, 1e-3)) + 0.1 * np.sin(np.arange(200)) * 1e-4  # non-uniform sampling
    ramp = Trial(trial_id="tw1", protocol="movement", time_s=t2, force=np.sin(t2 * 10.0), force_unit="N*m",
                 length_unit="rad", length=np.linspace(0.1, 0.4, 200),
                 stimulus_times_s=np.linspace(t2[10], t2[150], 8), attrs={"labels": ["a", "b"]})
    return MeasuredData(trials={"tw2": twitch, "tw1": ramp},
                        attrs={"species": "cat", "muscle": "soleus", "preparation": "in situ",
                               "source": "synthetic", "licence": "CC0", "n_cats": 1},
                        motor_units={"mu1": np.array([0.01, 0.02, 0.02, 0.3])},
                        extra_datasets={"/extra/emg": np.arange(5.0)},
                        extra_attrs={"/extra": {"kind": "emg"}})


def write_raw(path: Path, mutate: Callable[[h5py.File], None] | None = None) -> Path:
    """A valid file built directly with h5py (independent of write_measured), then ``mutate``d."""
    t = np.arange(100) * 0.01
    with h5py.File(path, "w") as h5:
        h5.attrs["schema"] = SCHEMA
        h5.attrs["species"] = "cat"
        trial = h5.create_group("trials/tw1")
        trial.attrs.update(protocol="twitch", force_unit="N", length_unit="mm")
        trial.create_dataset("time", data=t)
        trial.create_dataset("force", data=np.sin(t))
        trial.create_dataset("length", data=np.zeros_like(t))
        trial.create_dataset("stimulus_times", data=np.array([0.1, 0.5]))
        iso = h5.create_group("trials/iso")
        iso.attrs.update(protocol="train", force_unit="N", length_unit="mm", length=2.5)
        iso.create_dataset("time", data=t)
        iso.create_dataset("force", data=np.cos(t))
        iso.create_dataset("stimulus_times", data=np.zeros(0))
        if mutate is not None:
            mutate(h5)
    return path


def set_value(name: str, index: int, value: float) -> Callable[[h5py.File], None]:
    """Mutation: dataset trials/tw1/<name>[index] = value."""
    def mutate(h5: h5py.File) -> None:
        h5[f"trials/tw1/{name}"][index] = value
    return mutate


def replace_dataset(name: str, values: np.ndarray) -> Callable[[h5py.File], None]:
    """Mutation: replace dataset trials/tw1/<name>."""
    def mutate(h5: h5py.File) -> None:
        del h5[f"trials/tw1/{name}"]
        h5[f"trials/tw1/{name}"] = values
    return mutate


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


# ------------------------------------------------------------------------------------------ round trip


def test_round_trip_write_read_equal(tmp_path: Path) -> None:
    data = make_data()
    path = write_measured(tmp_path / "data.h5", data)
    back = read_measured(path)
    assert back == data
    assert list(back.trials) == ["tw2", "tw1"]  # file order, not alphabetical
    assert back.path == path
    assert back.trials["tw1"].time_s.dtype == np.float64
    assert back.trials["tw2"].length is None and back.trials["tw2"].length_const == -3.0
    np.testing.assert_array_equal(back.motor_units["mu1"], data.motor_units["mu1"])


def test_extra_groups_and_attributes_are_kept(tmp_path: Path) -> None:
    def add_extras(h5: h5py.File) -> None:
        h5.attrs["lab"] = "somewhere"
        h5["trials/tw1"].attrs["temperature_C"] = 36.5
        h5["trials/tw1/emg"] = np.ones(3)
        h5["trials/tw1/time"].attrs["unit"] = "s"
        h5.create_group("calibration").attrs["gain"] = 2.0
    data = read_measured(write_raw(tmp_path / "x.h5", add_extras))
    assert data.attrs["lab"] == "somewhere"
    assert data.trials["tw1"].attrs["temperature_C"] == 36.5
    assert data.extra_attrs["/calibration"] == {"gain": 2.0}
    assert data.extra_attrs["/trials/tw1/time"] == {"unit": "s"}
    np.testing.assert_array_equal(data.extra_datasets["/trials/tw1/emg"], np.ones(3))
    again = read_measured(write_measured(tmp_path / "y.h5", data))
    assert again == data


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


# ------------------------------------------------------------------------------------------- violations


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


def test_missing_and_non_hdf5_files_are_refused(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="not found"):
        read_measured(tmp_path / "absent.h5")
    text = tmp_path / "text.h5"
    text.write_text("time,force\n0,1\n")
    with pytest.raises(InputError, match="not an HDF5 file") as info:
        read_measured(text)
    assert str(text) in str(info.value)


def test_read_leaves_input_file_unchanged(tmp_path: Path) -> None:
    path = write_raw(tmp_path / "data.h5")
    before, mtime = sha256(path), path.stat().st_mtime_ns
    read_measured(path)
    check_file(path)
    assert sha256(path) == before and path.stat().st_mtime_ns == mtime


# ---------------------------------------------------------------------------------------------- writing


def test_write_refuses_to_overwrite(tmp_path: Path) -> None:
    path = write_measured(tmp_path / "d.h5", make_data())
    before = sha256(path)
    with pytest.raises(InputError, match="exists"):
        write_measured(path, make_data())
    assert sha256(path) == before
    write_measured(path, make_data(), overwrite=True)
    assert read_measured(path) == make_data()


def test_write_never_replaces_the_file_it_read(tmp_path: Path) -> None:
    path = write_raw(tmp_path / "input.h5")
    data = read_measured(path)
    before = sha256(path)
    with pytest.raises(InputError, match="input file"):
        write_measured(path, data, overwrite=True)
    assert sha256(path) == before


def test_write_validates_with_the_same_rules(tmp_path: Path) -> None:
    data = make_data()
    data.trials["tw1"].force[5] = np.nan
    out = tmp_path / "bad.h5"
    with pytest.raises(InputError, match="trial 'tw1': field 'force' has 1 non-finite"):
        write_measured(out, data)
    assert not out.exists() and not list(tmp_path.iterdir())
    assert any("field 'force'" in p for p in find_problems(data))


# ----------------------------------------------------------------------------------------------- CSV import


def write_trial_csv(path: Path, rows: list[str], header: str = "time,force,length") -> Path:
    path.write_text("\n".join([header] + rows) + "\n")
    return path


def test_csv_import_round_trip(tmp_path: Path) -> None:
    t_ms = np.arange(0.0, 50.0, 0.5)
    force = np.round(np.sin(t_ms / 10.0), 6)
    length = np.round(0.01 * t_ms, 6)
    a = write_trial_csv(tmp_path / "ramp.csv", [f"{t},{f},{x}" for t, f, x in zip(t_ms, force, length)])
    b = write_trial_csv(tmp_path / "iso.csv", [f"{t},{f}" for t, f in zip(t_ms, force)], header="time,force")
    stim = tmp_path / "ramp_stim.txt"
    stim.write_text("# stimulus times in ms\n5\n15.5\n\n25\n")
    out = tmp_path / "imported.h5"
    made = import_csv([a, b], [stim, None], out, protocol=["movement", "isometric"], force_unit="N",
                      length_unit="mm", time_unit="ms", length_const=1.5, attrs={"species": "rat"})
    back = read_measured(out)
    assert back == made
    assert list(back.trials) == ["ramp", "iso"]
    ramp, iso = back.trials["ramp"], back.trials["iso"]
    np.testing.assert_allclose(ramp.time_s, t_ms / 1000.0)
    np.testing.assert_allclose(ramp.force, force)
    np.testing.assert_allclose(ramp.length, length)
    np.testing.assert_allclose(ramp.stimulus_times_s, [0.005, 0.0155, 0.025])
    assert iso.length is None and iso.length_const == 1.5 and iso.stimulus_times_s.size == 0
    assert back.attrs["species"] == "rat"


def test_csv_custom_column_names(tmp_path: Path) -> None:
    a = write_trial_csv(tmp_path / "t.csv", ["0,1,2", "0.1,1,2"], header="Time (s),F (N),L (mm)")
    data = import_csv([a], [None], tmp_path / "o.h5", protocol="step", force_unit="N", length_unit="mm",
                      time_column="Time (s)", force_column="F (N)", length_column="L (mm)")
    np.testing.assert_array_equal(data.trials["t"].length, [2.0, 2.0])


def test_csv_bad_cell_names_file_line_and_column(tmp_path: Path) -> None:
    bad = write_trial_csv(tmp_path / "bad.csv", ["0,1,0", "0.1,2,0", "0.2,abc,0"])
    out = tmp_path / "o.h5"
    with pytest.raises(InputError) as info:
        import_csv([bad], [None], out, protocol="twitch", force_unit="N", length_unit="mm")
    message = str(info.value)
    assert str(bad) in message and "line 4" in message and "'force'" in message and "abc" in message
    assert not out.exists()


def test_csv_bad_stimulus_line_and_rule_violation(tmp_path: Path) -> None:
    good = write_trial_csv(tmp_path / "g.csv", ["0,1,0", "0.1,2,0", "0.2,3,0"])
    stim = tmp_path / "s.txt"
    stim.write_text("0.05\nsoon\n")
    with pytest.raises(InputError, match=r"s\.txt: line 2"):
        import_csv([good], [stim], tmp_path / "o.h5", protocol="twitch", force_unit="N", length_unit="mm")
    stim.write_text("0.5\n")  # outside [0, 0.2] s
    with pytest.raises(InputError) as info:
        import_csv([good], [stim], tmp_path / "o.h5", protocol="twitch", force_unit="N", length_unit="mm")
    assert "g.csv" in str(info.value) and "stimulus_times" in str(info.value)
    with pytest.raises(InputError, match="force_unit"):
        import_csv([good], [None], tmp_path / "o.h5", protocol="twitch", force_unit="kgf", length_unit="mm")


# --------------------------------------------------------------------------------------- summary / check


def test_check_file_lists_trials(tmp_path: Path) -> None:
    path = write_measured(tmp_path / "d.h5", make_data())
    text = check_file(path)
    lines = text.splitlines()
    assert len(lines) == 3 and "2 trial(s)" in lines[0] and "cat" in lines[0]
    assert lines[1].strip().startswith("tw2: twitch, 501 samples") and "1000 Hz" in lines[1]
    assert "length const -3 mm" in lines[1]
    assert lines[2].strip().startswith("tw1: movement") and "non-uniform" in lines[2]
    assert "8 stimuli" in lines[2] and "Hz)" in lines[2] and "rad" in lines[2] and "N*m" in lines[2]
    assert summarize(read_measured(path)) == text


# ------------------------------------------------------------------------------------------ real data


needs_herzog = pytest.mark.skipif(not HERZOG.is_dir(), reason=f"real data folder absent: {HERZOG}")
needs_digitized = pytest.mark.skipif(not DIGITIZED.is_dir(), reason=f"real data folder absent: {DIGITIZED}")


@needs_herzog
def test_herzog_leonard_loader_yields_finite_trials(tmp_path: Path) -> None:
    data = load_herzog_leonard_2002(HERZOG)
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


@needs_digitized
def test_scott_brown_loeb_loader() -> None:
    pts = load_scott_brown_loeb_1996(DIGITIZED)
    assert pts.active_length_L0.shape == pts.active_force_F0.shape == pts.active_specimen.shape == (65,)
    assert pts.passive_length_L0.shape == pts.passive_force_F0.shape == (45,)
    assert pts.velocity_L0_per_s.shape == pts.velocity_force_F0.shape == (86,)
    assert set(pts.active_specimen) == {"S8", "S9", "S10", "S11", "S12"}
    for arr in (pts.active_length_L0, pts.active_force_F0, pts.passive_length_L0, pts.velocity_L0_per_s):
        assert np.all(np.isfinite(arr))
    assert 0.9 < pts.active_force_F0.max() < 1.1
    assert pts.velocity_L0_per_s.min() < 0 < pts.velocity_L0_per_s.max()  # shortening and lengthening
