"""Model extensions: the catalogue of canonical causes (shared/spec/diagnosis.md) as switchable components.

An extension is one mod file plus one Python file in this folder holding an ``Extension`` subclass with a
canonical ``name``: it is found here by scanning the folder, so nothing else is edited to add one.  It drives one
or more modulation ports of the baseline mechanisms (``targets``: ``{"ca.release_gain": "gain"}`` wires KimCa's
POINTER release_gain to the extension's RANGE gain) and may receive the unit's spikes.  Switched off (absent),
each port points at its mechanism's own neutral value and the unit is bit-identical to the baseline.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import ClassVar, Mapping

from ...errors import InputError
from ..component import Component


class Extension(Component):
    """A component that modulates the baseline through its ports.  ``name`` is the canonical cause name."""

    name: ClassVar[str]
    targets: ClassVar[Mapping[str, str]] = {}


def registry() -> dict[str, type[Extension]]:
    """Every extension in this folder by canonical name (imported on first call, not at package import)."""
    found: dict[str, type[Extension]] = {}
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, Extension) and obj is not Extension and \
                    getattr(obj, "name", None):
                found[obj.name] = obj
    return found


def make_extensions(spec: Mapping[str, Mapping[str, float]] | None) -> dict[str, Extension]:
    """Instantiate extensions from ``{"staircase": {"gain": 0.1}, ...}`` (parameter overrides per extension)."""
    if not spec:
        return {}
    known = registry()
    out: dict[str, Extension] = {}
    for name, overrides in spec.items():
        if name not in known:
            raise InputError(f"unknown extension {name!r}; known: {', '.join(sorted(known)) or 'none'}")
        if overrides is not None and not isinstance(overrides, Mapping):
            raise InputError(f"extension {name!r}: parameters must be a mapping name -> value, got {overrides!r}")
        out[name] = known[name](**dict(overrides or {}))
    return out
