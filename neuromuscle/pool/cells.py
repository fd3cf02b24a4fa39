"""What a pool needs of a motoneuron, and two kinds of cell that provide it: the built-in reduced cell
(``Motoneuron``) and a reconstructed cell read from an SWC morphology with the channels you name.

    cells = reconstructed_cells("my_cell.swc", {"all": {"pas": {"g": 1e-4, "e": -70}},
                                                "soma": {"mn_soma": {"gnaf": 0.6, "gkdr": 0.15}},
                                                "dend": {"mn_pic": {"gbar": 3e-5}}})
    with Pool(definition, cells=cells) as pool: ...

A cell (``MotoneuronCell``) has a ``soma`` section (the input site: common currents and Poisson synapses sit at
``soma(0.5)``), its ``sections``, ``spike_source()`` (the soma's voltage: its threshold crossings are the unit's
spikes), ``axon_delay_ms`` (to its muscle unit), ``v_rest_mV`` (where a lone cell's runs start: excitability),
``play_synaptic_conductance`` (the common synaptic drive over the whole membrane), ``recordables()`` /
``ref(name)`` / ``section_of(name)`` (what ``Pool.record`` records as "mn.<name>") and ``destroy()``.  A pool
builds one cell a unit through a factory, ``(UnitSpec, name) -> cell``: ``reduced_cells`` (the default),
``reconstructed_cells`` (an SWC morphology), or ``built_cells`` for a cell you build yourself, a hoc template
instance or a Python object with a soma section, wrapped by ``wrap_cell``:

    h.load_file("my_motoneuron.hoc")
    cells = built_cells(lambda spec, name: h.MyMotoneuron(spec.motoneuron.size))

Units: um, ms, mV, S/cm2, ohm cm, uF/cm2.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Mapping, Protocol

from ..errors import InputError
from ..validate import finite_number, positive_number
from .definition import UnitSpec
from .motoneuron import Motoneuron, membrane_area_um2, play_synaptic_conductance


class MotoneuronCell(Protocol):
    """The members a pool uses of a motoneuron (module docstring)."""

    name: str
    soma: Any

    @property
    def sections(self) -> list[Any]: ...

    @property
    def axon_delay_ms(self) -> float: ...

    @property
    def v_rest_mV(self) -> float: ...

    def spike_source(self) -> Any: ...

    def play_synaptic_conductance(self, times_ms: Any, conductance_uS: Any, events: bool = True) -> list[Any]: ...

    def recordables(self) -> dict[str, str]: ...

    def ref(self, variable: str) -> Any: ...

    def section_of(self, variable: str) -> Any: ...

    def destroy(self) -> None: ...


#: Builds unit ``spec``'s motoneuron, named ``name``, in NEURON.
CellFactory = Callable[[UnitSpec, str], MotoneuronCell]


def reduced_cells(channels: str = "fused", pic_substeps: int = 1) -> CellFactory:
    """The built-in reduced cells, sized by each unit's motoneuron parameters (``Motoneuron``; ``pic_substeps``:
    its PIC gate's step in membrane steps)."""
    return lambda spec, name: Motoneuron(spec.motoneuron, name=name, channels=channels, pic_substeps=pic_substeps)


#: The SWC section groups a mechanism may be inserted into ("all": every section).
SECTION_GROUPS = ("all", "soma", "dend", "apic", "axon")
#: What a cell of sections records (``Pool.record``'s "mn.<name>"): the soma's and the first dendrite's middle
#: membrane potential.
CELL_RECORDABLES = {"v": "mV", "v_dend": "mV"}


class _Morphology:
    """What Import3d instantiates into (its lists soma, dend, apic, axon, all); sections named after ``name``."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return self.name


def mechanism_parameters(mechanism: str) -> list[str] | None:
    """The PARAMETERs of the compiled density mechanism ``mechanism`` (e.g. "g", "e" of pas), or None if no
    density mechanism has that name."""
    from neuron import h

    kind = h.MechanismType(0)
    kind.select(mechanism)
    if kind.selected() <= 0:
        return None
    standard = h.MechanismStandard(mechanism, 1)
    name = h.ref("")
    out = []
    for i in range(int(standard.count())):
        standard.name(name, i)
        out.append(name[0].removesuffix(f"_{mechanism}"))
    return out


def check_mechanisms(mechanisms: Mapping[str, Mapping[str, Mapping[str, float]]], where: str) -> None:
    """Every section group known (SECTION_GROUPS), every mechanism a compiled density mechanism, every parameter
    one of its PARAMETERs with a finite value; InputError naming ``where``, the group, mechanism and parameter."""
    from ..model.mechanisms import load_mechanisms

    load_mechanisms()
    for group, mechs in mechanisms.items():
        if group not in SECTION_GROUPS:
            raise InputError(f"{where}: mechanisms for {group!r}: section groups are {', '.join(SECTION_GROUPS)}")
        for mech, values in mechs.items():
            known = mechanism_parameters(mech)
            if known is None:
                raise InputError(f"{where}: {group}: no density mechanism {mech!r} is compiled")
            for k, v in values.items():
                if k not in known:
                    raise InputError(f"{where}: {group}: {mech} has no parameter {k!r}; parameters: "
                                     f"{', '.join(known)}")
                finite_number(f"{where}: {group}.{mech}.{k}", v)


class SectionCell:
    """A motoneuron made of NEURON sections: its ``soma`` (input site and spike source), ``dends`` (the first
    records "v_dend"), every section (``sections``: the synaptic drive spreads over their membrane), its axon
    delay (ms), its resting potential ``v_rest_mV`` (mV) and the object holding the sections (``owner``, kept
    alive with the cell)."""

    def __init__(self, soma: Any, dends: list[Any], sections: list[Any], axon_delay_ms: float, name: str,
                 owner: Any = None, v_rest_mV: float = -70.0) -> None:
        self.name = name
        self.soma, self.dends, self.sections, self.owner = soma, dends, sections, owner
        self._delay = positive_number(f"{name}: axon_delay_ms", axon_delay_ms)
        self.v_rest_mV = finite_number(f"{name}: v_rest_mV", v_rest_mV)

    @property
    def axon_delay_ms(self) -> float:
        """Conduction delay (ms) from the soma to the muscle unit."""
        return self._delay

    def spike_source(self) -> Any:
        """The soma's membrane potential reference (a NetCon source; give ``section=self.soma``)."""
        return self.soma(0.5)._ref_v

    def membrane_area_um2(self) -> float:
        """Total membrane area (um2)."""
        return membrane_area_um2(self.sections)

    def play_synaptic_conductance(self, times_ms: Any, conductance_uS: Any, events: bool = True) -> list[Any]:
        """The common synaptic drive over the whole membrane (``motoneuron.play_synaptic_conductance``)."""
        return play_synaptic_conductance(self.sections, times_ms, conductance_uS, events)

    def recordables(self) -> dict[str, str]:
        """The recordable variables (CELL_RECORDABLES; "v_dend" only with dendrites) and their units."""
        return {k: u for k, u in CELL_RECORDABLES.items() if k != "v_dend" or self.dends}

    def section_of(self, variable: str) -> Any:
        """The section holding ``variable``: the soma, or the first dendrite for "v_dend"."""
        if variable not in self.recordables():
            raise InputError(f"{self.name}: no variable {variable!r}; recordable: {', '.join(self.recordables())}")
        return self.dends[0] if variable == "v_dend" else self.soma

    def ref(self, variable: str) -> Any:
        """NEURON reference to ``variable``."""
        return self.section_of(variable)(0.5)._ref_v

    def destroy(self) -> None:
        """Let go of the sections (NEURON removes them with the last reference; idempotent)."""
        for attr in ("sections", "soma", "dends", "owner"):
            self.__dict__.pop(attr, None)


class ReconstructedMotoneuron(SectionCell):
    """A motoneuron whose morphology is read from an SWC file by NEURON's Import3d, with ``mechanisms``
    {section group: {mechanism: {parameter: value}}} inserted (groups: SECTION_GROUPS; a group's values apply
    after "all"'s).  Segments at most ``max_segment_um`` (um) long (an odd count a section); membrane ``cm``
    (uF/cm2) and axial ``ra`` (ohm cm) everywhere; the axon to the muscle takes ``axon_delay_ms`` (ms)."""

    def __init__(self, swc: str | Path, mechanisms: Mapping[str, Mapping[str, Mapping[str, float]]], *,
                 axon_delay_ms: float, name: str = "mn", cm: float = 1.0, ra: float = 70.0,
                 max_segment_um: float = 100.0, v_rest_mV: float = -70.0) -> None:
        path = Path(swc)
        if not path.is_file():
            raise InputError(f"{path}: no such SWC morphology file")
        check_mechanisms(mechanisms, str(path))
        positive_number(f"{name}: axon_delay_ms", axon_delay_ms)
        seg_um = positive_number(f"{name}: max_segment_um", max_segment_um)
        cm, ra = positive_number(f"{name}: cm", cm), positive_number(f"{name}: ra", ra)
        from neuron import h

        h.load_file("stdlib.hoc")
        h.load_file("import3d.hoc")
        reader = h.Import3d_SWC_read()
        reader.quiet = 1
        reader.input(str(path))
        morphology = _Morphology(name)
        h.Import3d_GUI(reader, False).instantiate(morphology)
        groups = {g: list(getattr(morphology, g, None) or []) for g in SECTION_GROUPS}
        if not groups["soma"]:
            raise InputError(f"{path}: the morphology has no soma (SWC type 1)")
        super().__init__(groups["soma"][0], groups["dend"] + groups["apic"], groups["all"], axon_delay_ms, name,
                         owner=morphology, v_rest_mV=v_rest_mV)
        for sec in self.sections:
            n = max(1, math.ceil(sec.L / seg_um))
            sec.nseg = n + 1 - n % 2   # odd: a node at the middle
            sec.cm, sec.Ra = cm, ra
        for group in SECTION_GROUPS:
            for mech, values in mechanisms.get(group, {}).items():
                for sec in groups[group]:
                    sec.insert(mech)
                    for seg in sec:
                        for k, v in values.items():
                            setattr(getattr(seg, mech), k, float(v))


def _first_section(value: Any) -> Any:
    """A section, or the first of a list or hoc section array of them."""
    from neuron import nrn

    if isinstance(value, nrn.Section):
        return value
    try:
        return value[0]
    except (TypeError, IndexError, KeyError, RuntimeError):
        return None


def wrap_cell(cell: Any, *, axon_delay_ms: float, name: str, soma: str = "soma", dend: str = "dend",
              v_rest_mV: float = -70.0) -> SectionCell:
    """A cell you built (an instance of a hoc template or of a Python class) as a pool's motoneuron: its soma
    is attribute ``soma`` (a section, or the first of a list or array), its dendrites attribute ``dend`` (may
    be absent), its sections ``cell.all`` (a SectionList or list) or else every section NEURON says belongs to
    it (``sec.cell()``).  InputError naming the cell when it has no such soma."""
    from neuron import h

    first = _first_section(getattr(cell, soma, None))
    if first is None:
        raise InputError(f"{name}: the cell {cell!r} has no section {soma!r} (give soma= the attribute of its soma)")
    dends = getattr(cell, dend, None)
    dends = [] if dends is None else [dends] if _first_section(dends) is dends else list(dends)
    every = getattr(cell, "all", None)
    sections = list(every) if every is not None else [sec for sec in h.allsec() if sec.cell() == cell]
    if not any(sec == first for sec in sections):
        sections = [first, *dends]
    return SectionCell(first, dends, sections, axon_delay_ms, name, owner=cell, v_rest_mV=v_rest_mV)


def built_cells(build: Callable[[UnitSpec, str], Any], **options: Any) -> CellFactory:
    """A factory of cells you build: ``build(spec, name)`` returns a hoc template instance or Python object
    (e.g. ``lambda spec, name: h.MyMotoneuron()``), wrapped by ``wrap_cell`` (``options``: soma=, dend=,
    v_rest_mV=) with the unit's axon delay."""
    return lambda spec, name: wrap_cell(build(spec, name), axon_delay_ms=spec.motoneuron.axon_delay_ms, name=name,
                                        **options)


def reconstructed_cells(swc: str | Path, mechanisms: Mapping[str, Mapping[str, Mapping[str, float]]],
                        **options: Any) -> CellFactory:
    """Every unit a ReconstructedMotoneuron of the same morphology and mechanisms, with its own axon delay
    (the unit's motoneuron parameters); ``options``: cm, ra, max_segment_um.  Checks the file and the
    mechanisms now."""
    if not Path(swc).is_file():
        raise InputError(f"{swc}: no such SWC morphology file")
    check_mechanisms(mechanisms, str(swc))
    return lambda spec, name: ReconstructedMotoneuron(swc, mechanisms, axon_delay_ms=spec.motoneuron.axon_delay_ms,
                                                      name=name, **options)
