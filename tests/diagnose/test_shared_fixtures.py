"""The shared-diagnosis helper of conftest.py under pytest-xdist: a failed make is retried from a clean folder."""

import shutil
import uuid

import pytest

from conftest import session_folder


def test_a_failed_make_is_retried_from_a_clean_folder(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("PYTEST_XDIST_WORKER", "gw0")  # the xdist route: a folder in the session's temporary root
    name = f"shared-{uuid.uuid4().hex[:8]}"

    def fails(folder):
        (folder / "report").mkdir()
        (folder / "report" / "half.json").write_text("{")
        raise RuntimeError("make failed part-way")

    root = tmp_path_factory.getbasetemp().parent  # where the xdist route puts the folder and its lock
    try:
        with pytest.raises(RuntimeError, match="part-way"):
            session_folder(tmp_path_factory, name, fails)
        seen = []

        def works(folder):
            seen.append(sorted(p.name for p in folder.iterdir()))
            (folder / "report").mkdir()

        folder = session_folder(tmp_path_factory, name, works)
        assert seen == [[]]  # the failed make's half-written report is gone before the retry
        assert (folder / ".made").exists() and (folder / "report").is_dir()
        assert session_folder(tmp_path_factory, name, fails) == folder  # made once: not made again
    finally:  # the session root outlives this test: leave nothing there
        shutil.rmtree(root / name, ignore_errors=True)
        (root / f"{name}.lock").unlink(missing_ok=True)
