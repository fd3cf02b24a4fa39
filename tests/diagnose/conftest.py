"""Diagnosed datasets shared by the diagnosis tests (each diagnosis runs once per session)."""

from __future__ import annotations

import numpy as np
import pytest

from diagnose_datasets import make_data
from neuromuscle.diagnose import run_diagnosis
from neuromuscle.measured import write_measured


@pytest.fixture(scope="session")
def null_files(tmp_path_factory):
    """A preparation without hidden effect, except one calibration long train whose force is 6 % low (a
    calibration misfit, ~4 % NRMSE against a ~1.4 % noise floor), and its diagnosis."""
    root = tmp_path_factory.mktemp("null")
    data = make_data(2)
    data.trials["long50_short"].force = data.trials["long50_short"].force * 0.94
    path = write_measured(root / "null.h5", data)
    doc = run_diagnosis(path, root / "report", workers=2)
    return path, root / "report", doc


@pytest.fixture(scope="session")
def fatigue_files(tmp_path_factory):
    """A preparation with the hidden fatigue-like effect (count-based release weights, strength 0.7: ~5 % NRMSE on long trains), and its diagnosis."""
    root = tmp_path_factory.mktemp("fatigue")
    path = write_measured(root / "fatigue.h5", make_data(3, fatigue=0.7))
    doc = run_diagnosis(path, root / "report", workers=2)
    return path, root / "report", doc


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
