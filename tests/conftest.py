"""Shared fixtures: the shipped parameter sets, the real-data folder (tests using it fail if it is absent) and the
example scripts of networks/ loaded as modules."""

import importlib.util
import sys
from pathlib import Path

import pytest

from neuromuscle import load_parameters

REAL_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data"
NETWORKS = Path(__file__).resolve().parents[1] / "networks"


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


@pytest.fixture(scope="session")
def network_script():
    """A loader: network_script("stretch_reflex") is networks/stretch_reflex.py as a module."""
    def load(name: str):
        spec = importlib.util.spec_from_file_location(f"network_{name}", NETWORKS / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = mod
        spec.loader.exec_module(mod)
        return mod
    return load


def _heavy_cost(item: pytest.Item) -> float:
    mark = item.get_closest_marker("heavy")
    return float(mark.kwargs.get("cost_s", 0.0)) if mark is not None else -1.0


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Heavy files first, largest first (the ``heavy`` marker); the rest keep their order.  With ``--dist
    loadfile --no-loadscope-reorder`` the workers take files in this order."""
    items.sort(key=lambda item: -_heavy_cost(item))
