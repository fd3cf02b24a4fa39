"""Provenance of a simulation: what is needed to replay it (parameters, versions, mechanism hash, seeds)."""

from __future__ import annotations

import datetime as _dt
import functools
import platform
import sys
from importlib import metadata
from typing import Any

from .._version import __version__


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


@functools.lru_cache(maxsize=1)
def _versions() -> tuple[tuple[str, str], ...]:
    return (("python", sys.version.split()[0]), ("platform", platform.platform()),
            ("neuromuscle", __version__), *((d, _version(d)) for d in ("neuron", "numpy", "scipy", "h5py")))


def versions() -> dict[str, str]:
    """Versions of Python, neuromuscle and the numerical stack (read once per process: the packages' metadata
    took ~10 ms a call, more than a short simulation, and the imported modules cannot change)."""
    return dict(_versions())


def provenance(**extra: Any) -> dict[str, Any]:
    """A provenance record: versions, mechanism hash, UTC time, plus the caller's fields (protocol, seeds...)."""
    from ..model.mechanisms import COMPILE_FLAGS, loaded_mechanism_hash

    return {"versions": versions(), "mechanism_sha256": loaded_mechanism_hash(), "mechanism_flags": COMPILE_FLAGS,
            "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"), **extra}
