"""neuromuscle.measured.hdf5: reading and writing the layout (round trip, extras, never touching the input)."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from measured_samples import make_data, sha256, write_raw

from neuromuscle.errors import InputError
from neuromuscle.measured import check_file, find_problems, read_measured, write_measured


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

