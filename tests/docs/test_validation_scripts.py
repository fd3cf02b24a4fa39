"""The scripts behind the validation pages (docs/validation/accuracy.md, published.md) run as the pages say and
print tables that parse.

compare_published.py needs the authors' published code, which CI does not have: it runs only when
NEUROMUSCLE_PUBLISHED names a folder holding it (e.g. a checkout of ModelDB 266732).
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "docs" / "validation"


def _run(*args: str) -> str:
    done = subprocess.run([sys.executable, *args], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-3000:]
    return done.stdout


def markdown_tables(text: str) -> list[list[list[str]]]:
    """Every pipe table in text as rows of cells (header first, separator dropped); fails on a ragged table."""
    tables, current = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            current.append([c.strip() for c in line.strip().strip("|").split("|")])
        elif current:
            assert re.fullmatch(r"(---\|?)+", "|".join(current[1])), f"no separator under {current[0]}"
            assert all(len(r) == len(current[0]) for r in current), f"ragged table {current[0]}"
            tables.append([current[0]] + current[2:])
            current = []
    return tables


def numbers(cell: str) -> list[float]:
    """The numbers of a cell such as "3.5698 N / 81.39 / 41.19 ms" or "+0.019 %"."""
    return [float(x) for x in re.findall(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?", cell)]


def test_accuracy_script_quick_prints_the_table():
    out = _run(str(SCRIPTS / "accuracy.py"), "--quick")
    main, dts = markdown_tables(out)
    assert main[0] == ["condition (CT09 unless named)", "SciPy Radau", "NEURON fixed", "NEURON CVODE", "spec"]
    twitch, train = main[1], main[2]
    assert twitch[0] == "twitch -8 mm" and train[0] == "20 Hz plateau (P0)"
    scipy = numbers(twitch[1])
    for cell in twitch[2:4]:  # the accuracy contract: within 0.5 % of SciPy
        assert all(abs(v / s - 1) < 0.005 for v, s in zip(numbers(cell), scipy, strict=True))
    assert all(abs(numbers(c)[0] / numbers(train[1])[0] - 1) < 0.005 for c in train[2:4])
    assert [numbers(r[0])[0] for r in dts[1:]] == [0.05, 0.025]
    assert numbers(dts[2][1])[0] < numbers(dts[1][1])[0] < 0.5  # error in %, shrinking with dt
    assert numbers(re.search(r"Largest deviation from SciPy: ([\d.]+) %", out).group(1))[0] < 0.5


@pytest.mark.skipif(not os.environ.get("NEUROMUSCLE_PUBLISHED"),
                    reason="NEUROMUSCLE_PUBLISHED does not name a folder with the authors' published code "
                           "(ModelDB 266732); CI has neither the code nor the network to fetch it")
def test_compare_published_briefly():
    folder = Path(os.environ["NEUROMUSCLE_PUBLISHED"])
    assert folder.is_dir(), f"NEUROMUSCLE_PUBLISHED={folder} is not a folder"
    out = _run(str(SCRIPTS / "compare_published.py"), str(folder), "--units", "2", "--duration-ms", "1500",
               "--no-reference")
    speed, gaps, agreement, spread = markdown_tables(out)
    assert [r[0] for r in speed[1:]] == [r[0] for r in gaps[1:]] == ["twitch", "10 Hz", "40 Hz"]
    assert all(numbers(c)[0] > 0 for r in speed[1:] for c in r[1:])
    rows = {r[0]: r for r in agreement[1:]}
    for name in ("twitch peak (N)", "10 Hz plateau, mean 1300-1500 ms (N)", "40 Hz plateau, mean 1300-1500 ms (N)"):
        assert abs(numbers(rows[name][4])[0]) < 0.5, rows[name]  # package vs published, %
    for row in spread[1:]:  # the package's identically driven units are identical
        low, high = numbers(row[1].replace(" - ", " "))
        assert low == high, row


@pytest.mark.slow
def test_identification_variants_script_quick_prints_the_table():
    """Every variant's row, a distance in [0, 1] for each file, and the one spread for subject S1 on both files."""
    out = _run(str(SCRIPTS / "identification_variants.py"), "--quick")
    (table,) = markdown_tables(out)
    assert table[0] == ["variant", "S1_30_36L", "S1_50_64L"]
    names = [r[0] for r in table[1:]]
    assert "ranked, a 1.75" in names and "sampled, a 1.75" in names and len(names) == 14
    assert sum(n.startswith("one spread for S1") for n in names) == 3
    for row in table[1:]:
        assert all(0.0 <= numbers(c)[0] <= 1.0 for c in row[1:])

