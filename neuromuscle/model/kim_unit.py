"""Kim Modules 1-3 as one mechanism (mod/kim_unit.mod, KimUnit): the three-mechanism unit's numbers at lower cost.

    unit = MuscleUnit(p, excitation=kim_fused())                         # the fused unit (no contraction slot)
    unit = MuscleUnit(p, excitation=kim_fused(substeps=4))               # muscle updated every 4th membrane step
    unit = MuscleUnit(p, excitation=kim_fused(), extensions={"fatigue": {}})
    unit = MuscleUnit(p, excitation=kim_fused(fixed_step=True))          # KimUnitFixed: the fixed step only

The parameters are KimCalcium's, KimActivation's and KimForce's, read from a parameter set under their own names
(kim_m1.K1, kim_m2.C1, kim_m3.P0), so the same set drives either unit.  The fused mechanism has the three
mechanisms' modulation ports under their names, and stands for their slots ("ca", "act", "force") in what
extensions target and read ("ca.release_gain", "force.dxce"): a unit with extensions gives the three mechanisms'
numbers bit for bit.  Its own variables are recorded under its slot ("muscle.F", "muscle.CaSPT").  Units: ms, M,
mm, N.

KimUnitFixed (mod/kim_unit_fixed.mod) is KimUnit for NEURON's fixed step alone: the same numbers bit for bit at a
lower cost per step (no METHOD euler loop, which only CVODE needs); the Simulator refuses it under CVODE.
"""

from __future__ import annotations

import functools
from typing import Any, Mapping

from ..errors import InputError
from .component import Component, Param, Port, by_qualified_name
from .kim import KimActivation, KimCalcium, KimForce, MovementSwitches

_MODULES = (KimCalcium, KimActivation, KimForce)


class KimUnit(MovementSwitches, Component):
    """Modules 1-3 (eqs 1-12, 18-20) in one point process: receives spikes, outputs F (N).  ``substeps`` k >= 1:
    under the fixed step the muscle advances once every k membrane steps by a step of k dt (k = 1: the
    three-mechanism update bit for bit)."""

    suffix = "KimUnit"
    namespace = "kim_unit"
    receives_spikes = True
    output = "F"
    parameters: tuple[Param, ...] = tuple(p for m in _MODULES for p in m.parameters)
    #: the three-mechanism unit's slots this component stands for (``MuscleUnit`` resolves them to it)
    stands_for = ("ca", "act", "force")
    modules = _MODULES
    reads = (Port("xm", "mm", "length.xm"), Port("vm", "mm/s", "length.vm"),
             *(q for m in _MODULES for q in m.reads if q.source is None))
    exposes = {**{k: v for m in _MODULES for k, v in m.exposes.items()}}
    states = tuple(s for m in _MODULES for s in m.states)
    _owner = {p.name: m for m in _MODULES for p in m.parameters}

    def __init__(self, length_compensation: bool = True, movement_compensation: bool = False, substeps: int = 1,
                 **overrides: float) -> None:
        super().__init__(**overrides)
        if isinstance(substeps, bool) or not isinstance(substeps, int) or substeps < 1:
            raise InputError(f"{type(self).__name__}: substeps must be an integer >= 1, got {substeps!r}")
        self.length_compensation = bool(length_compensation)
        self.movement_depression = bool(movement_compensation)  # eq 19
        self.lengthening_divisor = bool(movement_compensation)  # eq 20
        self.substeps = substeps

    @classmethod
    def qualified(cls, name: str) -> str:
        """The parameter's name in parameter sets: its module's (``kim_m1.K1``), as for the three mechanisms."""
        return cls._owner[name].qualified(name)

    def values(self, params: Mapping[str, float] | None) -> dict[str, float]:
        """Every value from the parameter set (as the three Kim modules require) or an explicit override."""
        given = by_qualified_name(params)
        missing = [q for p, q in self.qualified_parameters() if p.name not in self.overrides and q not in given]
        if missing:
            raise InputError(f"parameter set {getattr(params, 'name', None)!r} lacks {', '.join(missing)} "
                             f"(needed by {type(self).__name__})")
        v = super().values(params)
        if not v["c0"] > -v["P0"]:
            raise InputError(f"{type(self).__name__}: c0 = {v['c0']:g} N must exceed -P0 = {-v['P0']:g} N (eq 11's "
                             "asymptote (2 + c0/P0) Fc must lie above Fc); give a larger c0")
        return v

    def switches(self) -> dict[str, Any]:
        return {"length_compensation": self.length_compensation, **self.movement_switches(),
                "substeps": self.substeps}

    def configure(self, params: Mapping[str, float] | None) -> None:
        self.obj.xopt = self.obj.g1  # eq 18's optimum is Module 3's optimal length (KimCalcium.configure)
        self.obj.lencomp = 1.0 if self.length_compensation else 0.0
        self.configure_movement()
        self.obj.substeps = float(self.substeps)
        if not self.fixed_step_only:
            _set_atolscale(self.suffix, tuple((s.name, s.atolscale) for s in self.states))

    def asymptote_steps(self) -> int:
        """Fixed (muscle) steps that ended beyond 95 % of the Mashima asymptote (the CE was yielding)."""
        return int(self.obj.nasym)

    input_warnings = KimForce.input_warnings


class KimUnitFixed(KimUnit):
    """KimUnit for NEURON's fixed step alone (and CoreNEURON): its numbers bit for bit, at a lower cost per step.
    The Simulator refuses to run it under CVODE."""

    suffix = "KimUnitFixed"
    fixed_step_only = True


@functools.cache
def _set_atolscale(suffix: str, states: tuple[tuple[str, float], ...]) -> None:
    """CVODE's atolscale of each of the mechanism's states (by name: one setting for every instance), set once per
    process; the three mechanisms' are set by the Simulator."""
    from neuron import h

    cv = h.CVode()
    for name, scale in states:
        cv.atolscale(f"{suffix}.{name}", scale)


def kim_fused(length_compensation: bool = True, movement_compensation: bool = False, substeps: int = 1,
              fixed_step: bool = False, **overrides: float) -> dict[str, Component]:
    """Modules 1-3 as the one slot {"muscle": KimUnit} (give it as ``excitation``, with no ``contraction``);
    ``fixed_step``: KimUnitFixed, the same numbers at a lower cost per step, for NEURON's fixed step only."""
    kind = KimUnitFixed if fixed_step else KimUnit
    return {"muscle": kind(length_compensation, movement_compensation, substeps, **overrides)}


COMPONENTS: tuple[type[Component], ...] = (KimUnit, KimUnitFixed)
