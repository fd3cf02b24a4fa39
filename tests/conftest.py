"""Shared fixtures: the shipped parameter sets, and the real-data folder (tests using it fail if it is absent)."""

from pathlib import Path

import pytest

from neuromuscle import load_parameters

REAL_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data"


@pytest.fixture(scope="session")
def ct09():
    return load_parameters("CT09")


@pytest.fixture(scope="session")
def ct95():
    return load_parameters("CT95")


@pytest.fixture(scope="session")
def real_data() -> Path:
    if not REAL_DATA.is_dir():
        pytest.fail(f"real data folder {REAL_DATA} is absent (../shared/real_data beside the checkout; CI has it)")
    return REAL_DATA
