"""The version is written once: the package, its installed metadata and the changelog's latest entry agree."""

import re
from importlib import metadata
from pathlib import Path

import neuromuscle
from neuromuscle.sim.provenance import versions

CHANGELOG = Path(__file__).resolve().parents[1] / "CHANGELOG.md"


def test_package_metadata_and_provenance_carry_the_version():
    assert re.fullmatch(r"\d+\.\d+\.\d+", neuromuscle.__version__)
    assert metadata.version("neuromuscle") == neuromuscle.__version__, "reinstall (pip install -e .) after a bump"
    assert versions()["neuromuscle"] == neuromuscle.__version__


def test_the_changelog_describes_this_version_first():
    headings = re.findall(r"^## (\d+\.\d+\.\d+)\b", CHANGELOG.read_text(), re.M)
    assert headings and headings[0] == neuromuscle.__version__, headings
    assert len(set(headings)) == len(headings), headings
