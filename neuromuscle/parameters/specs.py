"""The parameter registry: every parameter of every component, by qualified name, with unit and bounds.

Built from the component declarations (``neuromuscle.model``), so a new component or extension adds its
parameters here by existing.  Names are namespaced by component (``kim_m2.C1``, ``hatze_exc.theta1``); the flat
names of Table 1 of Kim et al. 2015 (``C1``, ``P0``, ...) used by the shipped CT09/CT95 files and by the fitting API are
aliases of the Kim modules' qualified names.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Iterator, Mapping

from ..errors import InputError


@dataclass(frozen=True)
class ParameterSpec:
    """One registered parameter: qualified name, unit, default, physiological range (and its source), the
    component that owns it and its seed-001 module (1-3; 0 outside the Kim modules)."""

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    doc: str
    source: str
    component: str
    module: int
    lower_inclusive: bool = True
    neutral: float | None = None

    def check(self, value: object, where: str) -> float:
        """The value as a float inside the range; InputError naming the parameter, value, range and fix."""
        from ..model.component import Param

        shown = registry().alias(self.name)  # the name the user most likely typed
        return Param(shown, self.unit, self.default, self.lower, self.upper, self.doc, self.source,
                     self.lower_inclusive).check(value, where)


class Registry(Mapping[str, ParameterSpec]):
    """Read-only mapping qualified name -> ParameterSpec that also accepts the flat Kim aliases."""

    def __init__(self, specs: Mapping[str, ParameterSpec], aliases: Mapping[str, str]) -> None:
        self._specs = dict(specs)
        self.aliases = dict(aliases)

    def resolve(self, name: str) -> str:
        """Qualified name of ``name`` (a qualified name or a flat alias); InputError if unknown."""
        if name in self._specs:
            return name
        if name in self.aliases:
            return self.aliases[name]
        raise InputError(f"unknown parameter {name!r} (known: {', '.join(self.aliases)}, or qualified names "
                         f"such as {next(iter(self._specs))})")

    def alias(self, qualified: str) -> str:
        """The flat name of a Kim parameter, else the qualified name itself."""
        short = qualified.split(".", 1)[1]
        return short if self.aliases.get(short) == qualified else qualified

    def __getitem__(self, name: str) -> ParameterSpec:
        if name in self._specs:
            return self._specs[name]
        if name in self.aliases:
            return self._specs[self.aliases[name]]
        raise KeyError(name)

    def __contains__(self, name: object) -> bool:
        return name in self._specs or name in self.aliases

    def __iter__(self) -> Iterator[str]:
        return iter(self._specs)

    def __len__(self) -> int:
        return len(self._specs)


@lru_cache(maxsize=1)
def registry() -> Registry:
    """The registry of all components' parameters (built once, on first use)."""
    from ..model import extensions, hatze, kim

    specs: dict[str, ParameterSpec] = {}
    aliases: dict[str, str] = {}
    # a switch extension (eq 18-20) declares no parameters of its own: it borrows its owner's, registered here
    for comp in (*kim.COMPONENTS, *hatze.COMPONENTS, *extensions.mechanism_extensions()):
        for p in comp.parameters:
            q = comp.qualified(p.name)
            specs[q] = ParameterSpec(q, p.unit, p.default, p.lower, p.upper, p.doc, p.source, comp.__name__,
                                     comp.module, p.lower_inclusive, p.neutral)
            if comp.module:
                if p.name in aliases:
                    raise RuntimeError(f"flat name {p.name} is declared by two Kim modules")
                aliases[p.name] = q
    return Registry(specs, aliases)


def kim_parameter_names() -> list[str]:
    """Flat names of the Kim Modules 1-3 parameters, in declaration order (the content of CT09/CT95)."""
    return list(registry().aliases)
