"""One muscle unit inside NEURON: components wired port to port, driven by spikes and a length input.

    unit = MuscleUnit(load_parameters("CT09"))                        # Kim Modules 1-3 (the default)
    unit = MuscleUnit(p, excitation=kim_excitation(movement_compensation=True))
    unit = MuscleUnit(p, excitation="hatze", contraction="kim")       # Hatze's q drives Module 3
    unit = MuscleUnit(p, extensions={"fatigue": {}})                  # any catalogue extension, by name
    unit = MuscleUnit(p, excitation=kim_fused())                      # Modules 1-3 in one mechanism (faster)

A component that both receives spikes and has an output (KimUnit, ``kim_fused``) is a whole muscle model: it is given as
``excitation`` with no ``contraction``; the slots it ``stands_for`` ("ca", "act", "force") name it in what extensions
target and read, so an extension written for the three mechanisms drives it (its variables are recorded under its
own slot, "muscle.F").  Each slot holds one component ("length", "ca", "act", "force", and one per
extension).  Every POINTER of every component is wired at construction: to the variable its port names ("act.A"), to an
extension that targets it, or, for an unused modulation port, to the mechanism's own neutral value.  ``connect_from``
takes spikes from any NetCon source, ``add_spike_times`` from a recording; ``destroy()`` (or ``with``) removes
everything from NEURON.
"""

from __future__ import annotations

import copy
from typing import Any, Iterable, Mapping

import numpy as np

from ..errors import InputError
from ..model.combine import PortCombine
from ..model.component import Component, by_qualified_name
from ..model.extensions import Extension, make_extensions
from ..model.hatze import hatze_contraction, hatze_excitation
from ..model.kim import kim_contraction, kim_excitation
from ..model.length import MuscleLength
from ..model.mechanisms import load_mechanisms
from ..parameters import ParameterSet
from ..validate import check_spike_times

#: Models selectable by name (the CLI's --excitation/--contraction); anything else is passed as components.
EXCITATIONS = {"kim": kim_excitation, "hatze": hatze_excitation}
CONTRACTIONS = {"kim": kim_contraction, "hatze": hatze_contraction}

Model = Mapping[str, Component] | str | None

#: How a unit starts: its resting steady state at the initial length, or the published initial state of Kim et al. 2015.
INITIAL_STATES = {"rest": 1.0, "published": 0.0}


def _slots(model: Model, table: Mapping[str, Any], what: str) -> dict[str, Component]:
    if model is None:
        model = "kim"
    if isinstance(model, str):
        if model not in table:
            raise InputError(f"{what} must be one of {', '.join(table)} or a mapping slot -> component, "
                             f"got {model!r}")
        return table[model]()
    if isinstance(model, Mapping) and all(isinstance(c, Component) for c in model.values()):
        return {slot: copy.copy(c) for slot, c in model.items()}
    raise InputError(f"{what} must be a model name ({', '.join(table)}) or a mapping slot -> Component, "
                     f"got {model!r}")


class MuscleUnit:
    """A motor unit's muscle fibres in NEURON.

    params: a ParameterSet (values looked up by qualified name, e.g. kim_m2.C1; the flat names of the shipped
    CT09/CT95 files are aliases).  excitation/contraction: a model name ("kim", "hatze") or a mapping slot ->
    Component.  extensions: {canonical name: {parameter: value}} (see ``neuromuscle.model.extensions``).
    length_source: a MuscleLength hoc object to share (one per rank in a pool); a private one if None.
    section: the NEURON section hosting the point processes; a private one-segment section if None.
    initial_state: "rest" (default: every mechanism starts at its resting steady state at the initial length,
    so nothing creeps before the first spike) or "published" (the initial state of Kim et al. 2015: all SR calcium free,
    Atil = 0, no force; it settles within ~100 ms: the spec's "unsettled twitch" reference).
    """

    def __init__(self, params: Mapping[str, float], *, excitation: Model = None, contraction: Model = None,
                 extensions: Mapping[str, Mapping[str, float]] | None = None, length_source: Any = None,
                 section: Any = None, name: str = "unit", initial_state: str = "rest") -> None:
        if not isinstance(params, ParameterSet):
            raise InputError(f"{name}: params must be a ParameterSet (see load_parameters), got {type(params)}")
        load_mechanisms()
        from neuron import h

        self.params = params
        self.name = name
        exc = _slots(excitation, EXCITATIONS, "excitation")
        whole = [s for s, c in exc.items() if c.output]  # a whole muscle model (KimUnit): no contraction slot
        if whole and contraction is not None:
            raise InputError(f"{name}: the excitation {whole[0]!r} ({type(exc[whole[0]]).__name__}) holds the "
                             f"contraction already; give no contraction (got {contraction!r})")
        con = {} if whole else _slots(contraction, CONTRACTIONS, "contraction")
        exts: dict[str, Extension] = make_extensions(extensions)
        #: slot names that resolve to another slot (the fused KimUnit stands for "ca", "act" and "force")
        self._aliases = {a: slot for slot, c in exc.items() for a in getattr(c, "stands_for", ())}
        clash = (set(exc) & set(con)) | ((set(exc) | set(con) | set(self._aliases)) & (set(exts) | {"length"}))
        if clash:
            raise InputError(f"{name}: slot(s) {sorted(clash)} used twice")
        outputs = [s for s, c in (*exc.items(), *con.items()) if c.output]
        if len(outputs) != 1:
            raise InputError(f"{name}: the contraction model must have exactly one component with an output, "
                             f"got {outputs}")
        receivers = [s for s, c in exc.items() if c.receives_spikes]
        if len(receivers) != 1:
            raise InputError(f"{name}: the excitation model must have exactly one component receiving spikes, "
                             f"got {receivers}")
        self.output_slot = outputs[0]
        self.receiver_slot = receivers[0]
        self.extension_names = tuple(exts)
        self._sec = section if section is not None else h.Section(name=f"{name}_muscle")
        seg = self._sec(0.5)
        self.components: dict[str, Component] = {}
        length = MuscleLength()
        if length_source is None:
            length.instantiate(seg, None)
        else:
            length.obj = length_source.obj if isinstance(length_source, MuscleLength) else length_source
        self.components["length"] = length
        for slot, comp in (*exc.items(), *con.items(), *exts.items()):
            self._check_complete(comp)
            comp.instantiate(seg, params)
            self.components[slot] = comp
        self._wire(exts, seg)
        view = {**self.components, **{a: self.components[s] for a, s in self._aliases.items()}}
        for ext in exts.values():
            ext.attach(view, params)  # a switch extension turns its baseline equation on
        if initial_state not in INITIAL_STATES:
            raise InputError(f"{name}: initial_state must be one of {', '.join(INITIAL_STATES)}, got {initial_state!r}")
        self.initial_state = initial_state
        for comp in self.components.values():
            if comp.obj is not None and hasattr(comp.obj, "rest"):
                comp.obj.rest = INITIAL_STATES[initial_state]
        self._netcons: list[Any] = []
        self._spike_times: list[np.ndarray] = []

    # -- construction --------------------------------------------------------------------------------------
    def _check_complete(self, comp: Component) -> None:
        # the Kim modules take every value from the parameter set (no silent default); others have tables
        if comp.module:
            given = by_qualified_name(self.params)
            missing = [q for p, q in comp.qualified_parameters() if p.name not in comp.overrides and q not in given]
            if missing:
                raise InputError(f"parameter set {self.params.name!r} lacks {', '.join(missing)} "
                                 f"(needed by {type(comp).__name__})")

    def _wire(self, exts: Mapping[str, Extension], seg: Any) -> None:
        sources: dict[str, list[str]] = {}
        for slot, ext in exts.items():
            for port, var in ext.targets.items():
                sources.setdefault(self._resolved(port), []).append(f"{slot}.{var}")
        combiners: dict[str, Component] = {}
        driven = {port: self._combined(port, srcs, seg, combiners) for port, srcs in sources.items()}
        for slot, comp in self.components.items():
            modulated = False
            for port in comp.reads:
                key = f"{slot}.{port.name}"
                if port.optional:
                    src_slot, _, src_var = self._resolved(str(port.source)).partition(".")
                    has = src_slot in self.components and src_var in self.components[src_slot].recordables()
                    setattr(comp.obj, f"_ref_{port.name}", self.ref(port.source) if has else comp.ref(port.neutral))
                    if port.enables:
                        setattr(comp.obj, port.enables, 1.0 if has else 0.0)
                    continue
                # a modulation port counts as driven when an extension targets it or its component names a source
                modulated |= key in driven or (port.neutral is not None and port.source is not None)
                source = driven.pop(key, port.source)
                if source is None:
                    ref = comp.ref(port.neutral)  # an unused modulation port: the mechanism's neutral value
                elif isinstance(source, str):
                    ref = self.ref(source)
                else:
                    ref = source  # a PortCombine's output
                setattr(comp.obj, f"_ref_{port.name}", ref)
            if modulated:
                comp.obj.use_ports = 1.0  # the mechanism reads its ports only when something drives one
        if driven:
            raise InputError(f"{self.name}: extension targets {sorted(driven)} name no port of this unit")
        self.components.update(combiners)

    def _combined(self, port: str, sources: list[str], seg: Any, combiners: dict[str, Component]) -> Any:
        """What drives ``port``: its one source ("slot.variable"), or the NEURON reference to the output of a
        chain of PortCombine mechanisms (gains multiply, offsets add) over several (two extensions on one port),
        each added to ``combiners``."""
        if len(sources) == 1:
            return sources[0]
        slot, _, name = port.partition(".")
        comp = self.components.get(slot)
        unit = next((p.unit for p in comp.reads if p.name == name), "1") if comp is not None else "1"
        out = self.ref(sources[0])
        for k, src in enumerate(sources[1:], 1):
            c = PortCombine(unit)
            c.instantiate(seg, None)
            c.obj._ref_a = out
            c.obj._ref_b = self.ref(src)
            combiners[f"{slot}_{name}_combine{k}"] = c
            out = c.ref("out")
        return out

    # -- access --------------------------------------------------------------------------------------------
    def __getattr__(self, slot: str) -> Any:
        """``unit.ca``, ``unit.force``, ...: the hoc point process of a slot (hoc-style scripting)."""
        comps = self.__dict__.get("components", {})
        slot = self.__dict__.get("_aliases", {}).get(slot, slot)
        if slot in comps:
            return comps[slot].obj
        raise AttributeError(slot)

    def _resolved(self, name: str) -> str:
        """``"slot.variable"`` with the slot an alias names replaced by its own ("ca.CaSPT" -> "muscle.CaSPT" in a
        fused unit)."""
        slot, dot, var = name.partition(".")
        return f"{self.__dict__.get('_aliases', {}).get(slot, slot)}{dot}{var}"

    def __getitem__(self, slot: str) -> Component:
        try:
            return self.components[self.__dict__.get("_aliases", {}).get(slot, slot)]
        except KeyError:
            raise InputError(f"{self.name}: no slot {slot!r}; slots: {', '.join(self.components)}") from None

    def ref(self, name: str) -> Any:
        """NEURON reference to ``"slot.variable"`` (e.g. "force.F", "ca.CaSPT"); InputError if unknown."""
        slot, _, var = name.partition(".")
        if not var:
            raise InputError(f"{self.name}: a recorded name is 'slot.variable', got {name!r}")
        return self[slot].ref(var)

    def owner(self, name: str) -> Any:
        """The point process holding ``"slot.variable"`` (what NEURON's Vector.record needs besides the reference)."""
        return self[name.partition(".")[0]].obj

    def recordables(self) -> dict[str, str]:
        """Every recordable ``slot.variable`` of this unit with its unit."""
        return {f"{s}.{v}": u for s, c in self.components.items() for v, u in c.recordables().items()}

    @property
    def output(self) -> str:
        """The contraction output as ``slot.variable``: "force.F" (N) or "force.M" (N m)."""
        return f"{self.output_slot}.{self.components[self.output_slot].output}"

    @property
    def receiver(self) -> Any:
        """The point process that receives spikes (KimCa, HatzeExc)."""
        return self.components[self.receiver_slot].obj

    def spike_receivers(self) -> list[Any]:
        """Every point process that takes the unit's spikes: the excitation's, then extensions that want them."""
        return [self.receiver] + [self.components[s].obj for s in self.extension_names
                                  if self.components[s].receives_spikes]

    # -- spikes --------------------------------------------------------------------------------------------
    def connect_from(self, source: Any, *, threshold_mV: float = -10.0, delay_ms: float = 1.0,
                     section: Any = None) -> list[Any]:
        """Deliver spikes from any NetCon source: a voltage reference (``sec(0.5)._ref_v``, give ``section``),
        an artificial cell, or None for events sent by hand (threshold mV, delay ms).  Returns the NetCons."""
        from neuron import h

        made = []
        for target in self.spike_receivers():
            nc = h.NetCon(source, target, sec=section) if section is not None else h.NetCon(source, target)
            nc.threshold = threshold_mV
            nc.delay = delay_ms
            nc.weight[0] = 1.0
            made.append(nc)
        self._netcons.extend(made)
        return made

    def add_spike_times(self, spikes_ms: Iterable[float]) -> None:
        """Deliver recorded spike times (ms; finite, >= 0, strictly increasing) as events at initialisation."""
        self._spike_times.append(check_spike_times(spikes_ms, f"{self.name}: spike times"))

    def prepare(self) -> None:
        """Create what initialisation needs (called by the Simulator before ``finitialize``)."""
        from neuron import h

        if self._spike_times and not hasattr(self, "_event_netcons"):
            self._event_netcons = [h.NetCon(None, r) for r in self.spike_receivers()]
            for nc in self._event_netcons:
                nc.weight[0] = 1.0
            self._fih = h.FInitializeHandler(1, self._queue_spikes)

    def _queue_spikes(self) -> None:
        for nc in self._event_netcons:
            for s in self._spike_times:
                for t in s:
                    nc.event(float(t))

    # -- lifecycle -----------------------------------------------------------------------------------------
    def destroy(self) -> None:
        """Remove every NEURON object this unit made (idempotent)."""
        for attr in ("_fih", "_event_netcons", "_sec"):
            if hasattr(self, attr):
                delattr(self, attr)
        for comp in getattr(self, "components", {}).values():
            comp.destroy()
        self._netcons.clear()

    def __enter__(self) -> MuscleUnit:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy()
