"""Diagnosed datasets shared by the diagnosis tests (each diagnosis runs once per session, also under
pytest-xdist: test_diagnose_verdicts.py and test_diagnose_report.py share the null's on whichever runner they land)."""

from __future__ import annotations

import fcntl
import json
import os
import shutil
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from diagnose_datasets import make_data
from neuromuscle.diagnose import run_diagnosis
from neuromuscle.measured import MeasuredData, write_measured


def session_folder(tmp_path_factory, name: str, make: Callable[[Path], None]) -> Path:
    """A folder that ``make`` fills once per test session: under pytest-xdist in the session's temporary root, which
    every runner sees, by the first runner to ask while the others wait on a lock.  A failed ``make`` leaves no
    mark, and the next runner to ask clears what it left and tries again (a half-written report would otherwise
    make the retry meet "refusing to overwrite" instead of the first failure's cause)."""
    if os.environ.get("PYTEST_XDIST_WORKER") is None:
        folder = tmp_path_factory.mktemp(name)
        make(folder)
        return folder
    folder = tmp_path_factory.getbasetemp().parent / name  # basetemp is <session root>/popen-gwN
    with open(f"{folder}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / ".made").exists():
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            make(folder)
            (folder / ".made").touch()
    return folder


def _diagnosed(tmp_path_factory, name: str, data: Callable[[], MeasuredData]) -> tuple[Path, Path, dict]:
    """``data`` written to ``<name>.h5`` and diagnosed (2 workers) once per session: (file, report folder, the
    content of its diagnosis.json)."""
    def make(folder: Path) -> None:
        run_diagnosis(write_measured(folder / f"{name}.h5", data()), folder / "report", workers=2)

    folder = session_folder(tmp_path_factory, name, make)
    return folder / f"{name}.h5", folder / "report", json.loads((folder / "report" / "diagnosis.json").read_text())


def _null_data():
    data = make_data(2)
    data.trials["long50_short"].force = data.trials["long50_short"].force * 0.94
    return data


@pytest.fixture(scope="session")
def null_files(tmp_path_factory):
    """A preparation without hidden effect, except one calibration long train whose force is 6 % low (a
    calibration misfit, ~4 % NRMSE against a ~1.4 % noise floor), and its diagnosis."""
    return _diagnosed(tmp_path_factory, "null", _null_data)


@pytest.fixture(scope="session")
def fatigue_files(tmp_path_factory):
    """A preparation with the hidden fatigue-like effect (count-based release weights, strength 0.7: ~5 % NRMSE on
    long trains), and its diagnosis."""
    return _diagnosed(tmp_path_factory, "fatigue", lambda: make_data(3, fatigue=0.7))


@pytest.fixture()
def small_file(tmp_path):
    """A writer of variants of a small preparation (no diagnosis)."""
    def write(change=None, name="data.h5"):
        data = make_data(4)
        if change is not None:
            change(data)
        return write_measured(tmp_path / name, data)
    return write


def ar1(rng, n, sd, rho):
    e = rng.normal(0.0, sd * np.sqrt(1 - rho ** 2), n)
    x = np.empty(n)
    x[0] = rng.normal(0.0, sd)
    for i in range(1, n):
        x[i] = rho * x[i - 1] + e[i]
    return x


def evidence(failed=(), chi2_gain: float = 90.0):
    """Evidence of a candidate with a held-out gain ``chi2_gain`` that failed the rules ``failed`` (bookkeeping
    tests of the selection and the backward check)."""
    from neuromuscle.diagnose.evidence import Evidence

    ev = Evidence(n_parameters=2, gain=100.0, chi2_gain=chi2_gain, bic_penalty=10.0, bootstrap_p05=1.0, excess=200.0,
                  nrmse_before=5.0, nrmse_after=4.0, structured_before=["a"], identified=["x.k"],
                  calibration_chi2_gain=50.0, calibration_penalty=10.0)
    ev.failed = {r: "failed" for r in failed}
    return ev
