"""Model extensions: the catalogue of canonical causes (docs/reference/diagnosis.md) as switchable components.

An extension is one mod file plus one Python file in this folder holding an ``Extension`` subclass with a
canonical ``name``: it is found here by scanning the folder, so nothing else is edited to add one.  It drives one
or more modulation ports of the baseline mechanisms (``targets``: ``{"ca.release_gain": "gain"}`` wires KimCa's
POINTER release_gain to the extension's RANGE gain) and may receive the unit's spikes.  Switched off (absent),
each port points at its mechanism's own neutral value and the unit is bit-identical to the baseline.

A ``SwitchExtension`` has no mechanism of its own: it switches on an equation of a baseline mechanism (eq 18 in
KimCa, eq 19 in KimAct) and its parameters are that mechanism's own (``kim_m1.phi1``...), declared
again with the values at which the equation does nothing (``neutral``).  Selecting one turns on exactly its
equation whatever the baseline's switches; parameters given to it replace the baseline's values, the others
keep them.  If the baseline already has the equation on (``kim_excitation(length_compensation=True)``), selecting
it changes nothing but the parameters given: the equation is applied once, never twice.
"""

from __future__ import annotations

import functools
import importlib
import pkgutil
from dataclasses import dataclass, replace
from typing import Any, ClassVar, Mapping

from ...errors import InputError
from ..component import Component, Param


@dataclass(frozen=True)
class Telling:
    """Which trials can show a cause, as conditions on a trial's description (``neuromuscle.diagnose.phases``):
    every condition given must hold.  ``text`` says it in words.

    moving: True, the length moves while stimulated; False, the trial is isometric.  min_stimuli, min/max mean
    rate (Hz), min train duration (s), min |mean length - optimum| (mm).  short_interval_ms: some interval at most
    this long among others at least twice as long (doublets, random trains).  burst_after_pause: stimuli after a
    pause that follows a burst.  lengthening_below_optimum: stimulated lengthening below the optimum.
    hold_after: +1 / -1, a stimulated hold after an active stretch / shortening."""

    text: str
    moving: bool | None = None
    min_stimuli: int = 1
    min_rate_hz: float = 0.0
    max_rate_hz: float = float("inf")
    min_train_s: float = 0.0
    min_length_offset_mm: float = 0.0
    short_interval_ms: float | None = None
    burst_after_pause: bool = False
    lengthening_below_optimum: bool = False
    hold_after: int = 0


#: Baseline parameters an extension interacts with, by kind of effect (``Extension.interacts``): its fit frees
#: them with its own and restarts them from the base set too, so a candidate is not judged against the
#: compensations the baseline made for it.
LENGTH_PARAMETERS = ("P0", "g1", "g2")
ACTIVATION_PARAMETERS = ("C1", "C2", "C3", "alpha", "Umax", "tau2")
MOVEMENT_PARAMETERS = ("KSE", "a0", "b0", "c0", "d0")


class Extension(Component):
    """A component that modulates the baseline through its ports.  ``name`` is the canonical cause name; the
    class also holds the cause's facts the diagnosis reads: what the data show (``shows``), the trials that can
    show it (``telling``), the explanatory variable its residual follows (``variable``, a name of
    ``neuromuscle.diagnose.residuals.VARIABLES``), whether it acts through the movement itself (``moves``) or is
    defined by the force after an active stretch (+1) or shortening (-1) (``after``), whether it is a static
    property of the muscle whose size cannot differ between trials at one length (``static``), the baseline
    parameters it interacts with (``interacts``) and its section of the extensions page (``docs``)."""

    name: ClassVar[str]
    targets: ClassVar[Mapping[str, str]] = {}
    shows: ClassVar[str] = ""
    telling: ClassVar[Telling] = Telling("any stimulated trial")
    variable: ClassVar[str] = "length"
    moves: ClassVar[bool] = False
    after: ClassVar[int] = 0
    static: ClassVar[bool] = False
    interacts: ClassVar[tuple[str, ...]] = ACTIVATION_PARAMETERS
    docs: ClassVar[str] = "reference/extensions.md"

    @classmethod
    def needs_movement(cls) -> bool:
        """Whether the extension acts only where the length moves (through the movement, ``moves``, or after it,
        ``after``): at a length held exactly constant the force is the model's without it, bit for bit."""
        return cls.moves or cls.after != 0

    def attach(self, components: Mapping[str, Component], params: Mapping[str, float] | None) -> None:
        """Called by the unit once every component is built (a mechanism extension needs nothing here)."""


class SwitchExtension(Extension):
    """An equation of a baseline mechanism switched on, with that mechanism's parameters (no mod file).

    ``slot``/``owner``: the baseline component (e.g. "ca", KimCalcium); ``switch``: its boolean attribute
    (re-applied by its ``configure``); ``parameters``: the owner's own parameters with neutral values
    (``borrow``), so their qualified names are the owner's (a fit of the extension varies ``kim_m1.phi1``)."""

    suffix = ""
    slot: ClassVar[str]
    owner: ClassVar[type[Component]]
    switch: ClassVar[str]

    @classmethod
    def borrow(cls, owner: type[Component], neutral: Mapping[str, float | None]) -> tuple[Param, ...]:
        """``owner``'s parameters named in ``neutral``, with those neutral values (same unit, bounds, source)."""
        return tuple(replace(owner.param(name), neutral=value) for name, value in neutral.items())

    def instantiate(self, seg: Any, params: Mapping[str, float] | None) -> Any:
        """Nothing to build: the equation lives in the owner's mechanism."""
        self.obj = None
        return None

    def attach(self, components: Mapping[str, Component], params: Mapping[str, float] | None) -> None:
        """Switch the owner's equation on and set the parameters given to this extension on its mechanism."""
        comp = components.get(self.slot)
        if not (isinstance(comp, self.owner) or self.owner in getattr(comp, "modules", ())):
            found = type(comp).__name__ if comp is not None else "nothing"
            raise InputError(f"extension {self.name!r} switches an equation of {self.owner.__name__} (slot "
                             f"{self.slot!r}); this unit has {found} there: use the Kim excitation")
        setattr(comp, self.switch, True)
        comp.configure(params)
        for name, value in self.overrides.items():
            setattr(comp.obj, name, value)

    def switches(self) -> dict[str, Any]:
        return {"switches": f"{self.slot}.{self.switch}", "parameters": dict(self.overrides)}


def registry() -> dict[str, type[Extension]]:
    """Every extension in this folder by canonical name (imported on first call, not at package import; the
    folder is scanned once per process, since every simulation asks)."""
    return dict(_registry())


@functools.lru_cache(maxsize=1)
def _registry() -> dict[str, type[Extension]]:
    found: dict[str, type[Extension]] = {}
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, Extension) and obj is not Extension and \
                    getattr(obj, "name", None):
                found[obj.name] = obj
    return found


def mechanism_extensions() -> list[type[Extension]]:
    """The registered extensions that are mechanisms of their own (a POINT_PROCESS in mod/)."""
    return [e for e in registry().values() if e.suffix]


def make_extensions(spec: Mapping[str, Mapping[str, float]] | None) -> dict[str, Extension]:
    """Instantiate extensions from ``{"staircase": {"k": 0.2, "tau": 500.0}, ...}`` (parameter overrides per
    extension)."""
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
