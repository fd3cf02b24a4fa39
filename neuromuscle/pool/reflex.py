"""The stretch-reflex loop of a pool inside NEURON: muscle spindle (Ia, II) and Golgi tendon organ (Ib) afferents
read the pool's muscle length, velocity and unit forces, and their spikes reach the motoneurons by NetCon.

    pool = Pool(definition, length=ramp_and_hold)
    reflex = attach_reflex(pool, ReflexDefinition(n_ia=8, n_ib=4))   # before the drive and the run
    pool.drive_synaptic(...)
    result = pool.run(1000.0)
    afferent = reflex.spikes()                                       # {"Ia": [...], "II": [...], "Ib": [...]} (ms)

Afferents (mod/SpindleIa.mod, SpindleII.mod: the rate equations of Prochazka & Gorassini 1998 and Prochazka 1999;
TendonOrganIb.mod: the model of Lin & Crago 2002, a logarithm of the muscle's force through second-order
dynamics; each rate turned into spikes by a deterministic integrate-to-threshold): afferent k of a kind sits on
the muscle section of unit k mod N, reads that unit's MuscleLength (Ia: xm and vm; II: xm) or its force (Ib: F,
scaled to the muscle's by the pool's summed P0 over the unit's P0), and lives on the rank that owns the unit.
Each has a ParallelContext gid (after the pool's unit gids), so its spikes reach motoneurons on any rank.

Pathways: every Ia afferent excites every motoneuron monosynaptically (an excitatory synapse at the soma,
reversal 0 mV; peak conductance by motoneuron type, ``ia_weight_uS``) after ``ia_delay_ms`` (conduction and
synapse); every Ib afferent drives its own inhibitory interneuron (IbInterneuron, a leaky integrate-and-fire
cell on the afferent's rank), whose spikes inhibit every motoneuron (reversal -75 mV, ``ib_weight_uS``) after
``ib_delay_ms``: the disynaptic autogenetic inhibition.  Every group II afferent excites every motoneuron through
the Ia synapse (``ii_weight_uS``) after ``ii_delay_ms``, 2 ms beyond the Ia delay: in the cat, group II excitation
of homonymous extensor motoneurons is mostly di- or oligosynaptic, and the spinal circuit model of Moraud et al.
(2016, Neuron 89:814-828) relays it through excitatory interneurons whose total drive to a motoneuron is a third of
the Ia drive, 2 ms later; here one synapse with the longer delay stands for the relay, and the default weight is
a third of the default Ia weight.  ``ii_weight_uS=0`` leaves group II unconnected.
``cut_dorsal_roots=True`` builds the afferents (they fire and are recorded) and no connection: the loop is open.

Units: ms, uS, mV, mm, mm/s, N, /s (Hz).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..errors import InputError
from ..validate import finite_number, nonnegative_number, positive_number
from .motoneuron import TYPES
from .pool import Pool, parallel_context

#: The afferent kinds and their mechanisms.
AFFERENTS = {"Ia": "SpindleIa", "II": "SpindleII", "Ib": "TendonOrganIb"}
#: Synaptic reversal potentials (mV): glutamatergic Ia excitation, glycinergic Ib-interneuron inhibition.
E_EXCITATORY_MV = 0.0
E_INHIBITORY_MV = -75.0


def _default_ia_weights() -> dict[str, float]:
    # the same conductance on every type: the smaller cell's higher input resistance makes its EPSP larger
    return {t: 0.004 for t in TYPES}


@dataclass(frozen=True)
class ReflexDefinition:
    """The afferents and their pathways (module docstring).  Counts per kind; ``xref_mm`` (mm): the length the
    spindles' stretch is measured from; ``fusimotor`` (1, % of maximal activation): the EMG-like fusimotor term;
    weights (uS) are peak synaptic conductances of one afferent's (or interneuron's) spike, decaying with
    ``ia_tau_ms`` / ``ib_tau_ms`` (ms; group II shares the Ia synapse); delays (ms) include conduction and synapse
    (group II: the relay's too); ``ii_weight_uS=0`` leaves group II unconnected; ``interneuron_weight`` (1): an Ib
    spike's kick to its IbInterneuron (tau ``interneuron_tau_ms``; it fires at 1)."""

    n_ia: int = 8
    n_ii: int = 0
    n_ib: int = 4
    xref_mm: float = -8.0
    fusimotor: float = 0.0
    ia_weight_uS: Mapping[str, float] = field(default_factory=_default_ia_weights)
    ia_delay_ms: float = 4.0
    ia_tau_ms: float = 2.0
    ii_weight_uS: float = 0.004 / 3.0
    ii_delay_ms: float = 6.0
    ib_weight_uS: float = 0.004
    ib_delay_ms: float = 5.0
    ib_tau_ms: float = 5.0
    interneuron_weight: float = 1.1
    interneuron_tau_ms: float = 10.0
    cut_dorsal_roots: bool = False

    def __post_init__(self) -> None:
        for name in ("n_ia", "n_ii", "n_ib"):
            n = getattr(self, name)
            if isinstance(n, bool) or not isinstance(n, int) or n < 0:
                raise InputError(f"reflex: {name} must be an integer >= 0, got {n!r}")
        finite_number("reflex xref_mm (mm)", self.xref_mm)
        nonnegative_number("reflex fusimotor (% of maximal activation)", self.fusimotor)
        unknown = sorted(set(self.ia_weight_uS) - set(TYPES))
        if unknown or set(self.ia_weight_uS) != set(TYPES):
            raise InputError(f"reflex ia_weight_uS needs one weight for each motoneuron type {list(TYPES)}, got "
                             f"{dict(self.ia_weight_uS)}")
        for t, w in self.ia_weight_uS.items():
            nonnegative_number(f"reflex ia_weight_uS[{t!r}] (uS)", w)
        nonnegative_number("reflex ii_weight_uS (uS)", self.ii_weight_uS)
        nonnegative_number("reflex ib_weight_uS (uS)", self.ib_weight_uS)
        nonnegative_number("reflex interneuron_weight", self.interneuron_weight)
        for name in ("ia_delay_ms", "ii_delay_ms", "ib_delay_ms", "ia_tau_ms", "ib_tau_ms", "interneuron_tau_ms"):
            positive_number(f"reflex {name} (ms)", getattr(self, name))

    def count(self, kind: str) -> int:
        """How many afferents of ``kind`` ("Ia", "II", "Ib")."""
        return {"Ia": self.n_ia, "II": self.n_ii, "Ib": self.n_ib}[kind]


class Reflex:
    """The afferents, interneurons and NetCons attached to one pool (``attach_reflex``)."""

    def __init__(self, pool: Pool, definition: ReflexDefinition) -> None:
        from neuron import h

        if not isinstance(definition, ReflexDefinition):
            raise InputError(f"reflex: definition must be a ReflexDefinition, got {type(definition).__name__}")
        if not pool.cells and pool.definition.n_units:
            raise InputError(f"pool {pool.definition.name!r} has no motoneurons: a reflex needs them")
        if pool._drive is not None:
            raise InputError(f"pool {pool.definition.name!r}: attach the reflex before the drive")
        self.pool = pool
        self.definition = definition
        n_units = pool.definition.n_units
        pc = parallel_context()
        self.gids: dict[str, list[int]] = {}
        self.receptors: dict[int, Any] = {}
        self._keep: list[Any] = []
        self._spikes: dict[int, Any] = {}
        #: the muscle's P0 (N): every unit's, summed; a tendon organ reads its unit's force scaled to it
        self.muscle_p0_N = float(sum(u.muscle["P0"] for u in pool.definition.units()))
        next_gid = n_units
        for kind, mechanism in AFFERENTS.items():
            n = definition.count(kind)
            self.gids[kind] = list(range(next_gid, next_gid + n))
            next_gid += n
            for k, gid in enumerate(self.gids[kind]):
                unit = k % n_units
                if unit not in pool.muscle:
                    continue
                self._build_afferent(h, pc, kind, mechanism, gid, unit, k, n)
        # one interneuron per Ib afferent, on its rank, gids after the afferents
        self.interneuron_gids = list(range(next_gid, next_gid + definition.n_ib))
        for ib_gid, gid in zip(self.gids["Ib"], self.interneuron_gids):
            if ib_gid not in self.receptors:
                continue
            cell = h.IbInterneuron()
            cell.tau, cell.refrac = definition.interneuron_tau_ms, 1.0
            pc.set_gid2node(gid, pool.rank)
            pc.cell(gid, h.NetCon(cell, None))
            self._record(h, pc, gid)
            if not definition.cut_dorsal_roots:
                nc = pc.gid_connect(ib_gid, cell)
                nc.delay, nc.weight[0] = 1.0, definition.interneuron_weight
                self._keep.append(nc)
            self._keep.append(cell)
        if not definition.cut_dorsal_roots:
            self._connect_motoneurons(h, pc)
        pool._keep.append(self)   # the pool holds the loop until its destroy(), whether or not the caller does

    def _build_afferent(self, h: Any, pc: Any, kind: str, mechanism: str, gid: int, unit: int, k: int,
                        n: int) -> None:
        muscle = self.pool.muscle[unit]
        length = muscle.components["length"].obj
        seg = length.get_segment()
        receptor = getattr(h, mechanism)(seg)
        receptor.phase0 = k / n   # afferents reading the same signal fire staggered, not in lock step
        if kind == "Ib":
            out = muscle.components[muscle.output_slot]
            if out.output != "F":
                raise InputError(f"reflex: the Ib afferents read a force F (N); unit {unit}'s contraction "
                                 f"outputs {out.output!r}")
            h.setpointer(out.obj._ref_F, "F", receptor)
            receptor.fscale = self.muscle_p0_N / float(muscle.params["P0"])
        else:
            receptor.xref, receptor.fus = self.definition.xref_mm, self.definition.fusimotor
            h.setpointer(length._ref_xm, "xm", receptor)
            if kind == "Ia":
                h.setpointer(length._ref_vm, "vm", receptor)
        pc.set_gid2node(gid, self.pool.rank)
        pc.cell(gid, h.NetCon(receptor, None))
        self.receptors[gid] = receptor
        self._record(h, pc, gid)

    def _record(self, h: Any, pc: Any, gid: int) -> None:
        t, ids = h.Vector(), h.Vector()
        pc.spike_record(gid, t, ids)
        self._spikes[gid] = t
        self._keep.append(ids)

    def _connect_motoneurons(self, h: Any, pc: Any) -> None:
        d = self.definition
        for gid, cell in self.pool.cells.items():
            spec = next(u for u in self.pool.specs if u.index == gid)
            exc = h.ExpSyn(cell.soma(0.5))
            exc.tau, exc.e = d.ia_tau_ms, E_EXCITATORY_MV
            inh = h.ExpSyn(cell.soma(0.5))
            inh.tau, inh.e = d.ib_tau_ms, E_INHIBITORY_MV
            self._keep.extend([exc, inh])
            for src in self.gids["Ia"]:
                nc = pc.gid_connect(src, exc)
                nc.delay, nc.weight[0] = d.ia_delay_ms, float(d.ia_weight_uS[spec.unit_type])
                self._keep.append(nc)
            for src in self.gids["II"] if d.ii_weight_uS > 0 else ():
                nc = pc.gid_connect(src, exc)
                nc.delay, nc.weight[0] = d.ii_delay_ms, d.ii_weight_uS
                self._keep.append(nc)
            for src in self.interneuron_gids:
                nc = pc.gid_connect(src, inh)
                nc.delay, nc.weight[0] = d.ib_delay_ms, d.ib_weight_uS
                self._keep.append(nc)

    def spikes(self) -> dict[str, list[np.ndarray]]:
        """The afferents' spike times (ms) of the last run by kind, gathered from every rank (call on every rank),
        plus the Ib interneurons' as "Ib_interneurons"."""
        local = {gid: np.array(t) for gid, t in self._spikes.items()}
        merged: dict[int, np.ndarray] = {}
        for part in parallel_context().py_allgather(local):
            merged.update(part)
        out = {kind: [merged[g] for g in gids] for kind, gids in self.gids.items()}
        out["Ib_interneurons"] = [merged[g] for g in self.interneuron_gids]
        return out

    def destroy(self) -> None:
        """Remove the reflex's NEURON objects (the pool's ``destroy`` clears the gids)."""
        self._keep.clear()
        self._spikes.clear()
        self.receptors.clear()


def attach_reflex(pool: Pool, definition: ReflexDefinition | None = None) -> Reflex:
    """Build ``definition``'s afferents on ``pool`` and connect them to its motoneurons (module docstring).  Call
    on every rank, after the pool and before its drive and run; the pool keeps the loop until it is destroyed."""
    return Reflex(pool, definition or ReflexDefinition())
