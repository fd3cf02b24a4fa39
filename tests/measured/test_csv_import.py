"""neuromuscle.measured.csv_import: one CSV a trial plus a stimulus list, into the layout."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.measured import import_csv, read_measured


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

