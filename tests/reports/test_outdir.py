"""One refuse-to-overwrite rule: refusal keeps what exists and creates nothing; overwrite works; messages name
the path and how to overwrite from the API and the command line; writes are atomic."""

from pathlib import Path

import pytest

from neuromuscle.errors import InputError
from neuromuscle.reports.outdir import (atomic_path, check_out_dir, prepare_out_dir, refuse_existing_file,
                                        write_text)


def _tree(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() if p.is_file() else b"<dir>" for p in sorted(root.rglob("*"))}


def test_existing_file_is_refused_untouched_and_nothing_created(tmp_path):
    target = tmp_path / "result.h5"
    target.write_bytes(b"old")
    before = _tree(tmp_path)
    with pytest.raises(InputError) as exc:
        refuse_existing_file(target, overwrite=False)
    msg = str(exc.value)
    assert str(target) in msg and "refusing to overwrite" in msg
    assert "overwrite=True" in msg and "--overwrite" in msg
    assert _tree(tmp_path) == before


def test_file_flag_is_named_and_overwrite_allows(tmp_path):
    target = tmp_path / "a.json"
    target.write_text("{}")
    with pytest.raises(InputError, match="--replace"):
        refuse_existing_file(target, overwrite=False, flag="--replace")
    assert refuse_existing_file(target, overwrite=True) == target
    assert refuse_existing_file(tmp_path / "absent.json", overwrite=False) == tmp_path / "absent.json"
    assert _tree(tmp_path) == {"a.json": b"{}"}


def test_a_folder_is_never_replaced_by_a_file(tmp_path):
    with pytest.raises(InputError, match="not a regular file"):
        refuse_existing_file(tmp_path, overwrite=True)


def test_report_folder_holding_a_report_is_refused_untouched(tmp_path):
    out = tmp_path / "report"
    out.mkdir()
    (out / "report.json").write_text("{}")
    (out / "notes.txt").write_text("mine")
    before = _tree(tmp_path)
    for fn in (check_out_dir, prepare_out_dir):
        with pytest.raises(InputError) as exc:
            fn(out, False, ("report.json", "report.md"))
        msg = str(exc.value)
        assert str(out) in msg and "already holds report.json" in msg
        assert "refusing to overwrite" in msg and "overwrite=True" in msg and "--overwrite" in msg
        assert _tree(tmp_path) == before


def test_report_folder_overwrite_and_other_files(tmp_path):
    out = tmp_path / "report"
    out.mkdir()
    (out / "report.json").write_text("{}")
    assert prepare_out_dir(out, True, ("report.json",)) == out
    assert (out / "report.json").read_text() == "{}"           # the writer replaces files, not the folder
    assert prepare_out_dir(out, False, ("fit.json",)) == out    # a folder without the report's files is fine


def test_absent_folder_check_creates_nothing_prepare_creates_it(tmp_path):
    out = tmp_path / "a" / "b"
    assert check_out_dir(out, False, ("x.json",)) == out and not (tmp_path / "a").exists()
    assert prepare_out_dir(out, False, ("x.json",)) == out and out.is_dir()


def test_a_file_in_place_of_the_folder_is_refused(tmp_path):
    f = tmp_path / "out"
    f.write_text("x")
    for path in (f, f / "sub"):
        with pytest.raises(InputError, match="out"):
            prepare_out_dir(path, True, ("report.json",))
    assert _tree(tmp_path) == {"out": b"x"}


def test_atomic_write_replaces_and_a_failure_leaves_the_old_file(tmp_path):
    target = tmp_path / "summary.md"
    write_text(target, "one")
    write_text(target, "two")
    assert _tree(tmp_path) == {"summary.md": b"two"}
    with pytest.raises(RuntimeError):
        with atomic_path(target) as part:
            part.write_text("half")
            raise RuntimeError("writer failed")
    assert _tree(tmp_path) == {"summary.md": b"two"}
