"""Components: one small Python class per NMODL mechanism (Jaxley's channels, BluePyOpt's mechanisms).

A component declares everything the rest of the package needs to know about its mechanism, in one place:

* ``suffix``: the POINT_PROCESS name in ``mod/``; ``namespace``: the prefix of its parameters (``kim_m2.C1``);
* ``parameters``: name, unit, default, physiological lower/upper bounds and their source, neutral value;
* ``reads``: its POINTERs (ports it reads), each wired to another component's exposed variable
  (``"act.A"``) or, when optional and unused, to one of its own neutral RANGE variables;
* ``exposes``: RANGE variables others may read and anyone may record, with units;
* ``states``: its STATEs with the CVODE atolscale that suits their magnitude.

``instantiate(seg, values)`` builds the point process into NEURON and ``destroy()`` drops it.  A unit is made by
wiring components' ports (``neuromuscle.sim.unit``), never by if/elif over model names, so a new model
extension is one mod file plus one component file.
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass, field
from typing import Any, ClassVar, Mapping

from ..errors import InputError


@dataclass(frozen=True)
class Param:
    """One parameter of a component: unit, default, admissible (physiological) range and where it comes from."""

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    doc: str = ""
    source: str = ""
    lower_inclusive: bool = True
    neutral: float | None = None  # the value at which an extension does nothing (None: not an extension knob)

    def check(self, value: object, where: str) -> float:
        """``value`` as a float inside [lower, upper]; InputError naming the parameter, value, range and fix."""
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise InputError(f"{where}: parameter {self.name!r} must be a number, got {value!r}")
        v = float(value)
        if not math.isfinite(v):
            raise InputError(f"{where}: parameter {self.name!r} is not finite ({v})")
        low_bad = v < self.lower or (v == self.lower and not self.lower_inclusive)
        if low_bad or v > self.upper:
            lo = "(" if not self.lower_inclusive else "["
            raise InputError(f"{where}: parameter {self.name!r} = {v:g} {self.unit} is outside its physiological "
                             f"range {lo}{self.lower:g}, {self.upper:g}] {self.unit} ({self.source or self.doc}); "
                             "give a value inside it")
        return v


@dataclass(frozen=True)
class State:
    """A STATE of the mechanism and the CVODE absolute-tolerance scale (in its unit) that suits it."""

    name: str
    unit: str
    atolscale: float


@dataclass(frozen=True)
class Port:
    """A POINTER of the mechanism.  ``source`` is the default ``"slot.variable"`` it reads; ``neutral`` names the
    component's own RANGE variable it points at when nothing else is wired (a modulation port left unused).
    ``optional``: read ``source`` when the unit has it, else ``neutral`` (information another component may or may
    not give, e.g. KimAct's eq 20 switch within a fixed step; never counts as a modulation); ``enables`` names the
    mechanism's RANGE switch set to 1 when an optional port reads its source (the mechanism reads it only then)."""

    name: str
    unit: str
    source: str | None = None
    neutral: str | None = None
    optional: bool = False
    enables: str | None = None


class Component:
    """Base class: subclasses set the class attributes and, if needed, override ``configure``."""

    suffix: ClassVar[str]
    namespace: ClassVar[str]
    doc: ClassVar[str] = ""
    module: ClassVar[int] = 0  # module (1-3) of Kim et al. 2015 for the Kim mechanisms, 0 otherwise
    parameters: ClassVar[tuple[Param, ...]] = ()
    reads: ClassVar[tuple[Port, ...]] = ()
    exposes: ClassVar[Mapping[str, str]] = {}
    states: ClassVar[tuple[State, ...]] = ()
    receives_spikes: ClassVar[bool] = False
    output: ClassVar[str | None] = None  # for a contraction model: the exposed variable that is "the force"
    #: True for a mechanism that only NEURON's fixed step advances (the Simulator refuses it under CVODE)
    fixed_step_only: ClassVar[bool] = False

    def __init__(self, **overrides: float) -> None:
        known = {p.name for p in self.parameters}
        unknown = sorted(set(overrides) - known)
        if unknown:
            raise InputError(f"{type(self).__name__}: unknown parameter(s) {unknown}; known: {sorted(known)}")
        self.overrides = {k: self.param(k).check(v, type(self).__name__) for k, v in overrides.items()}
        self.obj: Any = None

    # -- declarations --------------------------------------------------------------------------------------
    @classmethod
    def param(cls, name: str) -> Param:
        """The declaration of parameter ``name`` (InputError if unknown)."""
        for p in cls.parameters:
            if p.name == name:
                return p
        raise InputError(f"{cls.__name__}: no parameter {name!r}")

    @classmethod
    def qualified(cls, name: str) -> str:
        """``namespace.name``: how the parameter is named in parameter sets and fits."""
        return f"{cls.namespace}.{name}"

    @classmethod
    def recordables(cls) -> dict[str, str]:
        """Variables that can be recorded, with units: the exposed RANGE variables and the states."""
        return dict(cls._referable()[0])

    @classmethod
    @functools.cache
    def _referable(cls) -> tuple[dict[str, str], frozenset[str]]:
        """(the recordables, every variable ``ref`` accepts), made once per class: units are built by the
        thousand in a fit, and the declarations are class constants."""
        rec = {**dict(cls.exposes), **{s.name: s.unit for s in cls.states}}
        return rec, frozenset(rec) | {p.neutral for p in cls.reads if p.neutral}

    # -- lifecycle -----------------------------------------------------------------------------------------
    def values(self, params: Mapping[str, float] | None) -> dict[str, float]:
        """Parameter values for this instance: explicit overrides, else the parameter set's value (by qualified
        name), else the declared default."""
        given = by_qualified_name(params)
        out = {}
        for p, q in self.qualified_parameters():
            if p.name in self.overrides:
                out[p.name] = self.overrides[p.name]
            elif q in given:
                out[p.name] = float(given[q])
            else:
                out[p.name] = p.default
        return out

    @classmethod
    @functools.cache
    def qualified_parameters(cls) -> tuple[tuple[Param, str], ...]:
        """Each declared parameter with its qualified name, made once per class."""
        return tuple((p, cls.qualified(p.name)) for p in cls.parameters)

    def instantiate(self, seg: Any, params: Mapping[str, float] | None) -> Any:
        """Create the point process at ``seg`` and set its parameters; returns the hoc object."""
        from neuron import h

        self.obj = getattr(h, self.suffix)(seg)
        for name, value in self.values(params).items():
            setattr(self.obj, name, value)
        self.configure(params)
        return self.obj

    def configure(self, params: Mapping[str, float] | None) -> None:
        """Set switches and derived values after the parameters (subclasses override)."""

    def ref(self, variable: str) -> Any:
        """NEURON reference to an exposed variable or state (for POINTERs, Vector.record)."""
        if variable not in self._referable()[1]:
            raise InputError(f"{type(self).__name__} exposes no {variable!r}; recordable: "
                             f"{', '.join(self.recordables())}")
        return getattr(self.obj, f"_ref_{variable}")

    def switches(self) -> dict[str, Any]:
        """Settings other than parameters that change the model (for provenance)."""
        return {}

    def input_warnings(self, trace: Any, params: Mapping[str, float] | None) -> list[str]:
        """Warnings about the run's inputs (e.g. a length where the model can make no force), before it runs."""
        return []

    def run_warnings(self) -> list[str]:
        """Things the user should know after a run (read from the mechanism's counters)."""
        return []

    def destroy(self) -> None:
        """Drop the point process (NEURON frees it when no reference is left)."""
        self.obj = None


def by_qualified_name(params: Mapping[str, float] | None) -> Mapping[str, float]:
    """``params`` as a mapping looked up by qualified name (``kim_m2.C1``): a ParameterSet's own ``values`` dict
    (its keys are the qualified names, so each lookup is one dict access: units are built by the thousand in a
    fit), any other mapping as it is, None as empty."""
    if params is None:
        return {}
    own = getattr(params, "values", None)
    return own if isinstance(own, dict) else params


@dataclass
class Slots:
    """The components of one unit by slot name ("length", "ca", "act", "force", an extension's name)."""

    items: dict[str, Component] = field(default_factory=dict)

    def __getitem__(self, slot: str) -> Component:
        try:
            return self.items[slot]
        except KeyError:
            raise InputError(f"no component in slot {slot!r}; the unit has {', '.join(self.items)}") from None

    def __contains__(self, slot: object) -> bool:
        return slot in self.items
