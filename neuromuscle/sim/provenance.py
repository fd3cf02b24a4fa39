"""Provenance of a simulation: what is needed to replay it (parameters, versions, mechanism hash, seeds)."""

from __future__ import annotations

import datetime as _dt
import platform
import sys
from importlib import metadata
from typing import Any


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def versions() -> dict[str, str]:
    """Versions of Python, neuromuscle and the numerical stack."""
    return {"python": sys.version.split()[0], "platform": platform.platform(),
            **{d: _version(d) for d in ("neuromuscle", "neuron", "numpy", "scipy", "h5py")}}


def provenance(**extra: Any) -> dict[str, Any]:
    """A provenance record: versions, mechanism hash, UTC time, plus the caller's fields (protocol, seeds...)."""
    from ..model.mechanisms import COMPILE_FLAGS, mechanism_hash

    return {"versions": versions(), "mechanism_sha256": mechanism_hash(), "mechanism_flags": COMPILE_FLAGS,
            "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"), **extra}
