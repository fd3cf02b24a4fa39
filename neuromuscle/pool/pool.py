"""A motor-unit pool in NEURON: one motoneuron and one muscle unit per gid, spikes by NetCon through
ParallelContext (the motoneuron's soma is the gid's spike source; its muscle unit receives it after the axon
delay), round-robin over MPI ranks.

    pool = Pool(PoolDefinition(100, load_parameters("CT09")), length=-8.0)
    pool.drive_synaptic([0, 2000, 4000], [0, 0.3, 0])            # a common synaptic conductance (uS a cell)
    pool.record(["mn.v", "act.A"], units=[0, 99])                 # any variable of chosen units (optional)
    result = pool.run(4000.0)                                     # PoolResult: spikes, forces, recordings
    pool.destroy()

Drives: ``drive_synaptic`` (a common excitatory synaptic conductance, uS, linear between the given times: the
same total on every motoneuron, spread over its membrane; the physiological drive, its rates saturate),
``drive_current_ramp`` (a common current, nA, linear between the given times), ``drive_poisson``
(independent Poisson synaptic input per motoneuron, excitatory conductance), ``drive_discharges`` (recorded
discharge times delivered to the muscle units: no motoneurons are built).  Length: one MuscleLength per rank
shared by its units (``per_unit_length=False``) or one per unit; a float (mm) or a LengthTrace.

Motoneurons: the built-in reduced cells, or any cell a factory builds (``cells``: ``pool.cells``, e.g.
``reconstructed_cells`` for a morphology read from an SWC file with the channels you name).

Muscle sections: all of a rank's muscle units sit on one section (the default, cheapest per fixed step), or each
on its own with its own MuscleLength (``per_unit_section=True``): then NEURON's local variable time step
(``Simulator(method="cvode", local_dt=True)``) integrates every unit and every motoneuron apart, so a spike
interrupts only the unit it reaches.

Engines: ``engine="coreneuron"`` runs the fixed step in CoreNEURON (``neuromuscle.sim.simulator``); spikes, unit
forces and the pool force come back as under NEURON.  CoreNEURON records every step: the run is made in chunks
that hold at most ``STEP_RECORD_BUDGET_BYTES`` of recorded steps per rank, sampled every record_dt_ms between them.
"""

from __future__ import annotations

import weakref
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError
from ..model.kim_unit import kim_fused
from ..sim.unit import MuscleUnit
from ..protocols.lengths import LengthTrace
from ..sim import Simulator
from ..sim.recordings import Recorder, on_time_grid
from ..sim.simulator import ENGINES
from ..validate import check_spike_times, finite_number, nonnegative_number, positive_number, seed_value
from .definition import FUSED_MUSCLE_MODELS, PoolDefinition, UnitSpec
from .cells import CellFactory, MotoneuronCell, reduced_cells
from .motoneuron import (COMMON_SYNAPTIC_MECHANISMS, FUSED_CHANNELS, Motoneuron, clear_synaptic_conductance,
                         held_steps)
from .recording import PoolUnit, gather_recordings
from .result import PoolResult

#: The dendritic PIC mechanisms whose gate ``pic_substeps`` steps (mn_pic, mn_pic_fixed).
PIC_MECHANISMS = tuple(pic for _, pic in FUSED_CHANNELS.values())

#: NetCon threshold (mV) of the soma spike detector.
SPIKE_THRESHOLD_MV = -10.0

#: Memory (bytes per rank) that every-step recordings may fill before their samples are taken out (CoreNEURON).
STEP_RECORD_BUDGET_BYTES = 64 * 2**20
#: The synaptic drive is held constant over steps of this length (ms), set by events: far cheaper than an
#: interpolation every time step, and finer than anything a drive of muscle force needs.
SYNAPTIC_STEP_MS = 5.0
#: Third Random123 id of the motoneurons' synaptic noise (Poisson drives use 1).
NOISE_STREAM = 2


def _nobody() -> None:
    """No pool holds CommonClamp's shared amplitude."""
    return None


def _set_pic_substeps(cell: MotoneuronCell, k: int) -> None:
    """The definition's pic_substeps on a cell of the user's: the gate of every segment's mn_pic (or mn_pic_fixed)
    every k steps; InputError naming the cell when it has neither (nothing for the setting to act on)."""
    pics = [getattr(seg, name) for sec in cell.sections for name in PIC_MECHANISMS if sec.has_membrane(name)
            for seg in sec]
    if not pics:
        raise InputError(f"{cell.name}: pic_substeps = {k} needs mn_pic in the cell's sections; this cell has none")
    for pic in pics:
        pic.substeps = k


def parallel_context() -> Any:
    """NEURON's ParallelContext (MPI if NEURON was started with it)."""
    from neuron import h

    return h.ParallelContext()


class Pool:
    """The pool's units owned by this rank (gid % nhost == rank); see the module docstring."""

    #: The pool whose common current plays into CommonClamp's shared amplitude (one at a time per process).
    _common_owner: Callable[[], Pool | None] = _nobody
    #: The pool whose common synaptic drive plays into the fused mechanisms' shared gcommon (one at a time).
    _synaptic_owner: Callable[[], Pool | None] = _nobody

    def __init__(self, definition: PoolDefinition, *, length: LengthTrace | float = -8.0,
                 per_unit_length: bool = False, motoneurons: bool = True, per_unit_section: bool = False,
                 engine: str = "neuron", cells: CellFactory | None = None) -> None:
        from ..model.mechanisms import load_mechanisms

        load_mechanisms()
        from neuron import h

        if not isinstance(definition, PoolDefinition):
            raise InputError(f"definition must be a PoolDefinition, got {type(definition).__name__}")
        if engine not in ENGINES:
            raise InputError(f"pool {definition.name!r}: engine must be one of {', '.join(ENGINES)}, got {engine!r}")
        self.engine = engine
        pc = parallel_context()
        self.rank, self.nhost = int(pc.id()), int(pc.nhost())
        if self.nhost > definition.n_units:
            raise InputError(f"pool {definition.name!r}: {self.nhost} MPI ranks for {definition.n_units} units; "
                             "use at most one rank per unit")
        if not isinstance(length, LengthTrace):
            length = finite_number("pool length (mm)", length)
        self.definition = definition
        self.length = length
        self.per_unit_section = bool(per_unit_section)
        self.per_unit_length = bool(per_unit_length) or self.per_unit_section
        self.specs: list[UnitSpec] = [u for u in definition.units() if u.index % self.nhost == self.rank]
        if not self.per_unit_section:
            self._sec = h.Section(name=f"{definition.name}_muscle_r{self.rank}")
        self._lengths: list[Any] = []
        self.muscle: dict[int, MuscleUnit] = {}
        self.cells: dict[int, MotoneuronCell] = {}
        make_cell = cells or reduced_cells(definition.motoneuron_channels, int(definition.pic_substeps))
        self._keep: list[Any] = []
        self._drive: str | None = None
        self._synaptic: tuple[Any, np.ndarray] | None = None
        self._synaptic_kind: str | None = None
        self._synaptic_plays: list[Any] = []
        self._discharges: dict[int, np.ndarray] = {}
        self._unit_secs: list[Any] = []
        self._record: tuple[tuple[str, ...], tuple[int, ...]] | None = None
        self._noise: list[Any] = []
        shared = None if self.per_unit_length else self._new_length(h, self._sec)
        pc.gid_clear()
        for u in self.specs:
            if self.per_unit_section:
                sec = h.Section(name=f"{definition.name}_muscle{u.index}")
                self._unit_secs.append(sec)
            else:
                sec = self._sec
            src = self._new_length(h, sec) if self.per_unit_length else shared
            self.muscle[u.index] = MuscleUnit(u.muscle, section=sec, length_source=src,
                                              excitation=self._excitation(), extensions=u.extensions or None,
                                              name=f"unit{u.index}")
            pc.set_gid2node(u.index, self.rank)
            if motoneurons:
                cell = make_cell(u, f"mn{u.index}")
                if cells is not None and definition.pic_substeps > 1:
                    _set_pic_substeps(cell, int(definition.pic_substeps))
                self.cells[u.index] = cell
                if definition.synaptic_noise_uS > 0.0:
                    self._noise.append(self._new_noise(h, cell, u.index))
                det = h.NetCon(cell.spike_source(), None, sec=cell.soma)
                det.threshold = SPIKE_THRESHOLD_MV
                pc.cell(u.index, det)
                for r in self.muscle[u.index].spike_receivers():
                    nc = pc.gid_connect(u.index, r)
                    nc.delay, nc.weight[0] = cell.axon_delay_ms, 1.0
                    self._keep.append(nc)
                self._keep.append(det)
        self._spike_t, self._spike_gid = h.Vector(), h.Vector()
        if motoneurons:
            pc.spike_record(-1, self._spike_t, self._spike_gid)

    def _new_noise(self, h: Any, cell: MotoneuronCell, gid: int) -> Any:
        """The cell's own synaptic noise (MnNoise at the soma; ``PoolDefinition.synaptic_noise_uS``): its Random123
        stream is (noise_seed, gid, NOISE_STREAM), the same whatever rank or thread holds the unit."""
        d = self.definition
        noise = h.MnNoise(cell.soma(0.5))
        noise.sigma, noise.tau = 0.0, float(d.synaptic_noise_tau_ms)   # sigma follows the drive (_play_noise)
        noise.rng.set_ids(int(d.noise_seed), int(gid), NOISE_STREAM)
        return noise

    def _excitation(self) -> Any:
        """The muscle model of every unit: None (the three Kim mechanisms) or a fresh KimUnit (KimUnitFixed)."""
        model = self.definition.muscle_model
        if model in FUSED_MUSCLE_MODELS:
            return kim_fused(substeps=int(self.definition.muscle_substeps), fixed_step=model == "fused_fixed")
        return None

    def _new_length(self, h: Any, sec: Any) -> Any:
        ml = h.MuscleLength(sec(0.5))
        if isinstance(self.length, LengthTrace):
            # times on the recordings' 1e-9 ms grid (sim.recordings.sample_times_ms)
            tv = h.Vector(on_time_grid(self.length.t_ms))
            xv, vv = h.Vector(self.length.xm_mm), h.Vector(self.length.velocity_mm_s)
            xv.play(ml._ref_xm, tv, 1)
            vv.play(ml._ref_vm, tv, 1)
            self._keep.extend([tv, xv, vv])
        else:
            ml.xm = self.length
        self._lengths.append(ml)
        return ml

    # -- drives --------------------------------------------------------------------------------------------
    def _set_drive(self, kind: str) -> None:
        if self._drive is not None:
            raise InputError(f"pool {self.definition.name!r} already has the {self._drive} drive")
        if kind != "discharges" and not self.cells:
            raise InputError(f"pool {self.definition.name!r} was built without motoneurons: only recorded "
                             "discharges can drive it")
        self._drive = kind

    def drive_current_ramp(self, times_ms: Sequence[float], amps_nA: Sequence[float]) -> None:
        """Inject the same current (nA, linear between times_ms, ms) into every motoneuron's soma."""
        from neuron import h

        t = check_spike_times(times_ms, "current ramp times")
        a = np.array([finite_number(f"current ramp amplitude {i}", x) for i, x in enumerate(amps_nA)])
        if a.size != t.size or t.size < 2:
            raise InputError(f"current ramp: {t.size} times and {a.size} amplitudes (need equal, >= 2)")
        self._set_drive("current")
        self._ramp = (h.Vector(t), h.Vector(a))
        self._clamps: list[Any] = []
        self._clamp_kind: str | None = None

    def drive_synaptic(self, times_ms: Sequence[float], conductance_uS: Sequence[float]) -> None:
        """Common excitatory synaptic drive: every motoneuron receives the same total conductance (uS, linear
        between times_ms, ms; held in SYNAPTIC_STEP_MS steps), spread uniformly over its soma and dendrite,
        reversal 0 mV.  The same input on every cell recruits the small cells first (their membrane is smaller:
        Henneman's size principle), and the conductance saturates the rates as the membrane depolarises towards
        the reversal (Powers & Heckman 2017).  Wired when the pool runs (``_attach_synaptic``)."""
        from neuron import h

        t = check_spike_times(times_ms, "synaptic drive times")
        g = np.array([nonnegative_number(f"synaptic conductance {i} (uS)", x) for i, x in enumerate(conductance_uS)])
        if g.size != t.size or t.size < 2:
            raise InputError(f"synaptic drive: {t.size} times and {g.size} conductances (need equal, >= 2)")
        self._set_drive("synaptic")
        grid = np.arange(t[0], t[-1] + SYNAPTIC_STEP_MS, SYNAPTIC_STEP_MS)
        steps = np.interp(grid + 0.5 * SYNAPTIC_STEP_MS, t, g)   # each step holds the drive at its middle
        self._synaptic = (h.Vector(grid), steps)

    def _attach_synaptic(self, sim: Simulator) -> None:
        """Wire the common synaptic drive for this run: one Vector.play into the fused mechanisms' shared
        ``gcommon`` (uS), each compartment's ``fcommon`` its share (the cheap way: a play costs NEURON a look every
        step), or the cells' own ``play_synaptic_conductance``, one play a segment, where a shared value is not
        possible (CoreNEURON plays into mechanism instances only; NEURON's local time step and threads; another
        live pool's drive; cells other than the fused reduced ones).  Both give every cell the same conductance."""
        from neuron import h

        kinds = {c.fused_mechanisms if isinstance(c, Motoneuron) else ("", "") for c in self.cells.values()}
        mechanisms = kinds.pop() if len(kinds) == 1 else ("", "")
        shared = not (sim.local_dt or sim.nthread > 1 or sim.engine == "coreneuron") and all(mechanisms)
        owner = Pool._synaptic_owner()
        kind = "common" if shared and (owner is None or owner is self) else "cells"
        if kind == self._synaptic_kind:
            return
        self._release_synaptic()
        tv, steps = self._synaptic
        if kind == "common":
            for cell in self.cells.values():
                cell.share_common_synaptic(True)   # type: ignore[attr-defined]
            for mech in mechanisms:
                vec = h.Vector(steps)
                vec.play(getattr(h, f"_ref_gcommon_{mech}"), tv, 0)
                self._synaptic_plays.append(vec)
            Pool._synaptic_owner = weakref.ref(self)
        else:
            events = sim.engine != "coreneuron"
            for cell in self.cells.values():
                self._synaptic_plays.extend(cell.play_synaptic_conductance(tv, steps, events=events))
        self._play_noise(h, tv, steps, events=sim.engine != "coreneuron")
        self._synaptic_kind = kind

    def _play_noise(self, h: Any, tv: Any, steps: np.ndarray, events: bool) -> None:
        """Each cell's noise follows the common drive g(t): standard deviation synaptic_noise_uS sqrt(g / 1 uS), the
        shot noise of inputs whose number or rate makes the drive (variance in proportion to the mean), in the
        drive's own steps (events under NEURON; under CoreNEURON a continuous play of the same steps)."""
        if not self._noise:
            return
        sigma = float(self.definition.synaptic_noise_uS) * np.sqrt(steps)
        times = tv
        if not events:
            times, sigma = held_steps(tv, sigma)
            self._synaptic_plays.append(times)
        for noise in self._noise:
            vec = h.Vector(sigma)
            vec.play(noise._ref_sigma, times, 0 if events else 1)
            self._synaptic_plays.append(vec)

    def _release_synaptic(self) -> None:
        """Take the common synaptic drive off the cells (before another wiring, and at destroy)."""
        from neuron import h

        for vec in self._synaptic_plays:
            vec.play_remove()
        self._synaptic_plays.clear()
        if self._synaptic_kind == "common":
            for cell in self.cells.values():
                cell.share_common_synaptic(False)   # type: ignore[attr-defined]
            for mech in COMMON_SYNAPTIC_MECHANISMS:
                setattr(h, f"gcommon_{mech}", 0.0)
            if Pool._synaptic_owner() is self:
                Pool._synaptic_owner = _nobody
        elif self._synaptic_kind == "cells":
            for cell in self.cells.values():
                clear_synaptic_conductance(cell.sections)
        self._synaptic_kind = None

    def _attach_current(self, sim: Simulator) -> None:
        """Build the common current's clamps for this run: one CommonClamp per soma and one Vector.play into
        their shared amplitude (the cheap way), or, where a play into a shared value is not possible (NEURON's
        local time step needs every play inside a cell; threads would race for it), one IClamp and play per
        soma.  Both inject the same current."""
        from neuron import h

        # CoreNEURON plays vectors into mechanism instances only, not into a GLOBAL
        kind = "iclamp" if sim.local_dt or sim.nthread > 1 or sim.engine == "coreneuron" else "common"
        owner = Pool._common_owner()
        if kind == "common" and owner is not None and owner is not self:
            kind = "iclamp"     # another live pool's current drives CommonClamp's shared amplitude
        if kind == self._clamp_kind:
            return
        tv, av = self._ramp
        av.play_remove()
        self._clamps.clear()
        for cell in self.cells.values():
            if kind == "common":
                self._clamps.append(h.CommonClamp(cell.soma(0.5)))
            else:
                ic = h.IClamp(cell.soma(0.5))
                ic.delay, ic.dur = 0.0, 1e9
                av.play(ic._ref_amp, tv, 1)
                self._clamps.append(ic)
        if kind == "common":
            av.play(h._ref_amp_CommonClamp, tv, 1)
            Pool._common_owner = weakref.ref(self)
        elif owner is self:
            Pool._common_owner = _nobody
        self._clamp_kind = kind

    def drive_poisson(self, rate_hz: float, weight_uS: float, *, n_inputs: int = 1, tau_ms: float = 2.0,
                      start_ms: float = 0.0, seed: int = 0) -> None:
        """Independent Poisson excitation of every motoneuron: n_inputs trains of rate_hz (Hz) each on an
        excitatory synapse (reversal 0 mV, decay tau_ms, peak conductance weight_uS, uS) at the soma, from
        start_ms; the stream of unit i is seeded by (seed, i) (Random123), the same on any number of ranks."""
        from neuron import h

        positive_number("Poisson rate (Hz)", rate_hz)
        nonnegative_number("synaptic weight (uS)", weight_uS)
        positive_number("synaptic tau (ms)", tau_ms)
        nonnegative_number("Poisson start (ms)", start_ms)
        seed = seed_value(seed)
        if isinstance(n_inputs, bool) or not isinstance(n_inputs, int) or n_inputs < 1:
            raise InputError(f"n_inputs must be an integer >= 1, got {n_inputs!r}")
        self._set_drive("poisson")
        for gid, cell in self.cells.items():
            syn = h.ExpSyn(cell.soma(0.5))
            syn.tau, syn.e = tau_ms, 0.0
            stim = h.NetStim()
            stim.interval, stim.number, stim.start, stim.noise = 1000.0 / (rate_hz * n_inputs), 1e9, start_ms, 1
            stim.noiseFromRandom123(seed, gid, 1)
            nc = h.NetCon(stim, syn)
            nc.delay, nc.weight[0] = 0.1, weight_uS
            self._keep.extend([syn, stim, nc])

    def drive_discharges(self, discharges_ms: Sequence[Sequence[float]], duration_ms: float) -> None:
        """Deliver recorded discharge times (ms, one strictly increasing list per unit, within 0..duration_ms)
        straight to the muscle units (they are the motoneurons' output: no axon delay is added)."""
        positive_number("duration_ms", duration_ms)
        if len(discharges_ms) != self.definition.n_units:
            raise InputError(f"pool {self.definition.name!r}: {len(discharges_ms)} discharge trains for "
                             f"{self.definition.n_units} units")
        trains = [check_spike_times(d, f"discharges of unit {i}") for i, d in enumerate(discharges_ms)]
        for i, d in enumerate(trains):
            if d.size and d[-1] > duration_ms:
                raise InputError(f"discharges of unit {i}: {d[-1]:g} ms lies beyond the run (0..{duration_ms:g} ms)")
        self._set_drive("discharges")
        for u in self.specs:
            self._discharges[u.index] = trains[u.index]
            self.muscle[u.index].add_spike_times(trains[u.index])

    # -- running -------------------------------------------------------------------------------------------
    def record(self, names: Sequence[str], units: Sequence[int] | None = None) -> None:
        """Record the variables ``names`` of the units ``units`` (indices; None: every unit) in the next runs,
        every record_dt_ms like the forces: the muscle unit's by the single unit's names ("ca.CaSPT", "act.A",
        "force.F"), the motoneuron's as "mn.v", "mn.v_dend", "mn.i_pic", "mn.cai" (``pool.recording``).  The
        result holds them in ``recordings`` (gathered from every rank).  Call it on every rank: the names are
        checked on the ranks holding the units, and every rank raises the same InputError."""
        if self._record is not None:
            raise InputError(f"pool {self.definition.name!r} already records {list(self._record[0])}: give every "
                             "variable in one call")
        if isinstance(names, str) or not all(isinstance(n, str) for n in names) or not names:
            raise InputError(f"pool {self.definition.name!r}: recorded names must be a non-empty list of "
                             f"'slot.variable' strings, got {names!r}")
        if len(set(names)) != len(names):
            raise InputError(f"pool {self.definition.name!r}: recorded names repeat: {list(names)}")
        n = self.definition.n_units
        chosen = list(range(n)) if units is None else list(units)
        bad = [u for u in chosen if isinstance(u, bool) or not isinstance(u, (int, np.integer)) or not 0 <= u < n]
        if bad or not chosen or len(set(chosen)) != len(chosen):
            raise InputError(f"pool {self.definition.name!r}: recorded units must be distinct unit indices "
                             f"0..{n - 1}, got {list(units) if units is not None else units!r}")
        problem = None
        for gid in [u for u in chosen if u in self.muscle] or list(self.muscle)[:1]:
            known = self._probe(gid).recordables()
            unknown = [x for x in names if x not in known]
            if unknown:
                problem = (f"pool {self.definition.name!r}, unit {gid}: cannot record {unknown}; recordable: "
                           f"{', '.join(known)}")
                break
        problems = [p for p in parallel_context().py_allgather(problem) if p is not None]
        if problems:
            raise InputError(problems[0])
        self._record = (tuple(names), tuple(sorted(int(u) for u in chosen)))

    def _probe(self, gid: int) -> PoolUnit:
        """Unit ``gid`` (on this rank) as the Recorder sees it."""
        return PoolUnit(self.muscle[gid], self.cells.get(gid), f"pool {self.definition.name!r}, unit {gid}")

    # -- running -------------------------------------------------------------------------------------------
    def run(self, duration_ms: float, simulator: Simulator | None = None, record_dt_ms: float = 1.0,
            progress: Callable[[float], None] | None = None) -> PoolResult:
        """Run 0..duration_ms (ms) and gather spikes, forces and recordings from every rank (every rank gets the
        result).  Unit forces sampled every record_dt_ms (ms); the pool force is their sum (N).  ``progress``:
        called with the simulated time (ms) every tenth of the run under the fixed step (on every rank, so
        that they stop together), at the end under CVODE."""

        positive_number("duration_ms", duration_ms)
        positive_number("record_dt_ms", record_dt_ms)
        if self._drive is None:
            raise InputError(f"pool {self.definition.name!r}: no drive (drive_synaptic, drive_current_ramp, "
                             "drive_poisson or drive_discharges)")
        if self._drive == "discharges":
            last = max((d[-1] for d in self._discharges.values() if d.size), default=0.0)
            if last > duration_ms:
                raise InputError(f"discharges reach {last:g} ms, beyond the run of {duration_ms:g} ms")
        sim = simulator or Simulator(method="fixed", dt_ms=0.025, engine=self.engine)
        if self._noise and sim.method != "fixed":
            raise InputError(f"pool {self.definition.name!r}: synaptic noise (synaptic_noise_uS = "
                             f"{self.definition.synaptic_noise_uS:g} uS) needs the fixed step; the variable step "
                             "cannot integrate a noise drawn at fixed intervals")
        if self._noise and self._drive != "synaptic":
            raise InputError(f"pool {self.definition.name!r}: synaptic noise (synaptic_noise_uS = "
                             f"{self.definition.synaptic_noise_uS:g} uS) rides on the common synaptic drive "
                             f"(drive_synaptic), not on the {self._drive} drive: set synaptic_noise_uS = 0")
        if sim.engine != self.engine:
            raise InputError(f"pool {self.definition.name!r} was built for engine {self.engine!r}, the simulator "
                             f"asks for {sim.engine!r}: give Pool(..., engine={sim.engine!r}) or a simulator with "
                             f"engine={self.engine!r}")
        if sim.v_init_mV is None:
            from dataclasses import replace

            sim = replace(sim, v_init_mV=-70.0)
        if self._drive == "current":
            self._attach_current(sim)
        elif self._drive == "synaptic":
            self._attach_synaptic(sim)
        names, recorded = self._record or ((), ())
        # every step under CoreNEURON (and on several threads: see Recorder), at explicit sample times under CVODE
        stepwise = sim.method == "fixed" and (sim.nthread > 1 or sim.engine == "coreneuron")
        recorders = {}
        for gid, u in self.muscle.items():
            extra = [x for x in names if x != u.output] if gid in recorded else []
            recorders[gid] = Recorder(self._probe(gid), [u.output, *extra], record_dt_ms,
                                      every_step_dt_ms=sim.dt_ms if stepwise else None,
                                      at_times_until_ms=duration_ms if sim.method == "cvode" else None)
        pc = parallel_context()
        chunk = None
        if stepwise:
            # the fullest rank's recorded values per ms: every rank stops at the same times
            steps_per_ms = pc.allreduce(sum(len(r.names) for r in recorders.values()) / sim.dt_ms, 2)
            chunk = max(record_dt_ms, STEP_RECORD_BUDGET_BYTES / (8.0 * steps_per_ms))
        if progress is not None and sim.method == "fixed":
            chunk = min(chunk or np.inf, max(record_dt_ms, duration_ms / 10.0))

        def after_chunk() -> None:
            for r in recorders.values():
                r.take()
            if progress is not None:
                from neuron import h

                progress(float(h.t))

        wall = sim.run(duration_ms, units=list(self.muscle.values()), chunk_ms=chunk, after_chunk=after_chunk)
        if progress is not None and sim.method != "fixed":
            progress(duration_ms)
        traces = {gid: r.arrays(duration_ms)[1] for gid, r in recorders.items()}
        local_force = {gid: traces[gid][self.muscle[gid].output] for gid in recorders}
        local_recorded = {gid: ({x: traces[gid][x] for x in names},
                                {x: recorders[gid].units[x] for x in names}) for gid in recorders if gid in recorded}
        if self._drive == "discharges":
            local_spikes = {gid: self._discharges[gid] for gid in self.muscle}
        else:
            t, g = np.array(self._spike_t), np.array(self._spike_gid).astype(int)
            order = np.lexsort((t, g))   # by unit, then time: one sort, not one pass over every spike per unit
            t, g = t[order], g[order]
            bounds = np.searchsorted(g, [[gid, gid + 1] for gid in self.muscle]) if self.muscle else []
            local_spikes = {gid: t[a:b] for gid, (a, b) in zip(self.muscle, bounds)}
        gathered = pc.py_allgather((local_force, local_spikes, local_recorded, wall))
        force: dict[int, np.ndarray] = {}
        spikes: dict[int, np.ndarray] = {}
        traced: dict[int, Any] = {}
        for f, s, r, _ in gathered:
            force.update(f)
            spikes.update(s)
            traced.update(r)
        walls = [w for *_, w in gathered]
        return PoolResult.from_gathered(self.definition, force, spikes, record_dt_ms, duration_ms, sim,
                                        drive=self._drive, ranks=self.nhost, wall_s=max(walls),
                                        length=self.length, recordings=gather_recordings(names, recorded, traced))

    def destroy(self) -> None:
        """Remove every NEURON object of the pool (idempotent)."""
        pc = parallel_context()
        self._keep.clear()
        self._noise.clear()
        if self._drive == "current":
            self._ramp[1].play_remove()
            self._clamps.clear()
            self._clamp_kind = None
            if Pool._common_owner() is self:
                Pool._common_owner = _nobody
        if self._drive == "synaptic":
            self._release_synaptic()
        for u in self.muscle.values():
            u.destroy()
        for c in self.cells.values():
            c.destroy()
        self.muscle.clear()
        self.cells.clear()
        self._lengths.clear()
        self._unit_secs.clear()
        if hasattr(self, "_sec"):
            del self._sec
        pc.gid_clear()

    def __enter__(self) -> Pool:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy()
