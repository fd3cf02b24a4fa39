"""Product text speaks of the product: the tracked files say what the code does and why, not how it was developed.

Every tracked text file (package code and data, NMODL, networks, docs, README, tests, configuration) is scanned for
development history and workplace text: development stops and issue numbers, "this machine", the papers' file names
or internal numbers instead of author and year, paths outside the repository.  History belongs in commit messages
and CHANGELOG.md, which is not scanned.  The papers are cited by author and year (Kim, Sandercock & Heckman 2015;
van Zandwijk, Bobbert, Harlaar & Hof 1998); the published recordings are read from ``../shared/real_data``, beside
the checkout, which is not a workplace path.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOT_SCANNED = {"CHANGELOG.md", "tests/test_product_text.py"}
BINARY_SUFFIXES = (".png", ".h5", ".npz", ".mat", ".pdf")

#: What product text must not say, by kind.  A random seed is a seed ("the draw's seed"); the paper is not.
PATTERNS: dict[str, re.Pattern[str]] = {name: re.compile(p) for name, p in {
    "a development stop": r"\b[Ss]tops? \d+\b(?!\s*(?:ms|s|mm|Hz|%|N|x)\b)",
    "an issue number": r"\b[Ii]ssue[- ]?#?\d+",
    "a session number": r"\b[Ss]ession \d+",
    "the build machine": r"\b(?:this|the build|our) (?:[\w-]+ )?machine\b",
    "a time of day": r"\b(?:this|that) (?:morning|afternoon|evening)\b|\byesterday\b",
    "a paper by its file name or number": r"\bseed \d{3}\b|\b\d{3}_[0-9a-f]{16}\b|\bseeds/",
    "a paper called 'the seed'": r"(?<!of )(?<!from )\b[Tt]he seed(?:'s)?\b(?!\s*(?:of|for|=|value|stream|\())"
                                 r"|\bseed's\b|\bseed \d\.\d",
    "a workplace path": r"/work/|/tmp/nm|\bshared/(?:spec|seeds|design)\b|\bspec/\w+\.md\b",
    "a colleague": r"\bcolleague",
}.items()}


def tracked_files() -> list[str]:
    """The repository's tracked files (git), else every file under the package, mod, docs, networks and tests."""
    try:
        out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
        return out.split()
    except (OSError, subprocess.CalledProcessError):
        tops = ("neuromuscle", "mod", "docs", "networks", "tests")
        return [str(p.relative_to(ROOT)) for t in tops for p in (ROOT / t).rglob("*") if p.is_file()] + \
            [p.name for p in ROOT.iterdir() if p.is_file()]


def scanned_files() -> list[str]:
    return [f for f in tracked_files() if f not in NOT_SCANNED and not f.endswith(BINARY_SUFFIXES)
            and (ROOT / f).is_file()]


def findings(files: list[str]) -> list[tuple[str, int, str, str]]:
    """(file, line number, what, line) for every line that matches a pattern."""
    out = []
    for f in files:
        try:
            text = (ROOT / f).read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for n, line in enumerate(text.splitlines(), 1):
            for what, pattern in PATTERNS.items():
                if pattern.search(line):
                    out.append((f, n, what, line.strip()))
    return out


def test_product_text_has_no_development_history_or_workplace_text():
    hits = findings(scanned_files())
    listed = "\n".join(f"{f}:{n}: {what}: {line[:140]}" for f, n, what, line in hits)
    assert not hits, f"{len(hits)} lines speak of development or the workplace, not of the product:\n{listed}"


def test_the_patterns_catch_what_they_are_for():
    caught = ["until stop 39 the rule", "as issue 9 asks", "on this machine", "seed 001's eq 19", "the seed's order",
              "/work/shared/spec/measured_data.md", "seeds/000_637b96e18aae2ab4.txt", "this 2-core machine"]
    kept = ["stop 5 ms after the train", "the draw's seed", "drawn from the seed", "the seed of the noise",
            "../shared/real_data", "Kim, Sandercock & Heckman 2015", "stops at its iteration cap"]
    assert all(any(p.search(t) for p in PATTERNS.values()) for t in caught), caught
    assert not [t for t in kept if any(p.search(t) for p in PATTERNS.values())]


DOC_PATH = re.compile(r"(?<![\w/.])docs/[\w./-]+\.(?:md|py|png)\b")


def test_the_docs_the_product_points_to_exist():
    """Every ``docs/...`` path named outside the docs (code, NMODL, README, tests) is a file of the repository."""
    missing = set()
    for f in scanned_files():
        if f.startswith("docs/") or f.endswith(".md") and f != "README.md":
            continue
        for line in (ROOT / f).read_text(encoding="utf-8", errors="replace").splitlines():
            missing |= {(f, m.group(0)) for m in DOC_PATH.finditer(line) if not (ROOT / m.group(0)).is_file()}
    assert not missing, f"pointers to documentation pages that do not exist: {sorted(missing)}"
