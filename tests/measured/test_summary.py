"""neuromuscle.measured.summary: the text summary of a file."""

from __future__ import annotations

from pathlib import Path

from measured_samples import make_data

from neuromuscle.measured import check_file, read_measured, summarize, write_measured


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

