"""One refuse-to-overwrite rule for output files and report folders, and atomic writes.

The rule: an output file that exists, or a report folder that already holds one of the report's files, is kept
unless the caller says overwrite; the refusal names the path and how to overwrite, in words valid for the API and
the command line, and creates nothing.  Every writer writes ``name.part`` beside the target and moves it into
place, so a failure never leaves half a file under the target's name.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence

from ..errors import InputError


def _how(flag: str) -> str:
    return f"refusing to overwrite (overwrite=True, or {flag} on the command line)"


def refuse_existing_file(path: str | Path, overwrite: bool, flag: str = "--overwrite") -> Path:
    """Return ``path`` as a Path if it may be written: it does not exist, or it is a file and ``overwrite``.

    Raises InputError naming the path and ``flag`` otherwise (a folder is never replaced); creates nothing.
    """
    p = Path(path)
    if p.exists() and not p.is_file():
        raise InputError(f"{p}: exists and is not a regular file; refusing to replace it")
    if p.exists() and not overwrite:
        raise InputError(f"{p}: exists; {_how(flag)}")
    return p


def check_out_dir(path: str | Path, overwrite: bool, report_files: Sequence[str],
                  flag: str = "--overwrite") -> Path:
    """Return ``path`` as a Path if a report may be written into it: it is absent, or a folder holding none of
    ``report_files`` (names relative to it), or ``overwrite``.  Raises InputError naming the folder, the files it
    holds and ``flag`` otherwise; creates nothing (call it before long work, then :func:`prepare_out_dir`)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"{p}: exists and is not a directory")
    existing = [name for name in report_files if (p / name).exists()]
    if existing and not overwrite:
        raise InputError(f"{p}: already holds {', '.join(existing)}; {_how(flag)}")
    return p


def prepare_out_dir(path: str | Path, overwrite: bool, report_files: Sequence[str],
                    flag: str = "--overwrite") -> Path:
    """:func:`check_out_dir`, then create the folder (and its parents); returns it."""
    p = check_out_dir(path, overwrite, report_files, flag)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{p}: cannot create the folder ({exc.strerror})") from None
    return p


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield ``path`` + ``.part`` to write; on leaving without error it replaces ``path``, on error it is removed.

    The caller has already decided (with :func:`refuse_existing_file` or :func:`check_out_dir`) that ``path`` may
    be written.  A writer that picks its format from the file name must be told the format explicitly.
    """
    target = Path(path)
    part = target.with_name(target.name + ".part")
    try:
        yield part
        part.replace(target)
    finally:
        part.unlink(missing_ok=True)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; returns the path."""
    with atomic_path(path) as part:
        part.write_text(text, encoding="utf-8")
    return Path(path)
