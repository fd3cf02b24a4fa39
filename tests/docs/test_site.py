"""The documentation site builds with warnings as errors, and its reference pages cover what they claim to.

``mkdocs build --strict`` fails on a broken link or anchor, a page missing from the navigation, an API page whose
module is gone, or a docstring mkdocstrings cannot read.  The command-line page is generated from the parsers
(docs/hooks/cli_page.py): every command and subcommand must appear in the built page.  The mechanisms page must
name every mechanism of mod/.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from neuromuscle.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)], cwd=ROOT,
                          env=env, capture_output=True, text=True)
    assert done.returncode == 0, f"mkdocs build --strict failed:\n{done.stderr[-6000:]}"
    return out


def commands(parser: argparse.ArgumentParser, prefix: str = "neuromuscle") -> list[str]:
    """Every command and subcommand of ``parser``, as typed ("neuromuscle bench unit")."""
    out = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out += [f"{prefix} {name}", *commands(sub, f"{prefix} {name}")]
    return out


def test_the_site_builds_strict(site):
    assert (site / "index.html").is_file()
    assert (site / "reference" / "api" / "sim" / "index.html").is_file()


def test_the_cli_page_lists_every_command(site):
    page = (site / "reference" / "cli" / "index.html").read_text()
    names = commands(build_parser())
    assert {"neuromuscle simulate", "neuromuscle bench unit", "neuromuscle data check"} <= set(names)
    missing = [c for c in names if f"<code>{c}</code>" not in page]
    assert not missing, missing


def test_the_mechanisms_page_names_every_mechanism():
    declared = re.compile(r"^\s*(?:POINT_PROCESS|SUFFIX|ARTIFICIAL_CELL)\s+(\w+)", re.M)
    names = {m.group(1) for f in (ROOT / "mod").glob("*.mod") for m in declared.finditer(f.read_text())}
    page = (ROOT / "docs" / "reference" / "mechanisms.md").read_text()
    assert len(names) > 20
    missing = sorted(n for n in names if f"`{n}`" not in page)
    assert not missing, f"mechanisms missing from docs/reference/mechanisms.md: {missing}"
