"""One muscle unit inside NEURON: Modules 1-3 (seed 001) wired together, driven by spikes and a length input.

Reads like the experiment::

    params = load_parameters("CT09")
    result = simulate(params, spikes_ms=twitch(500.0), length=-8.0, duration_ms=700.0)
    result.force_N.max()

``MuscleUnit`` is the building block for pools: it instantiates its mechanisms into NEURON, accepts spikes from
any NetCon source (``connect_from``) or from recorded times (``add_spike_times``), and is torn down with
``destroy()`` (or ``with MuscleUnit(...) as unit:``) so no hoc state leaks between simulations.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import numpy as np

from .errors import InputError, NumericalError
from .length import LengthTrace
from .mechanisms import load_mechanisms
from .parameters import ParameterSet

#: Largest fixed step (ms) accepted.  The linearly implicit scheme stays stable beyond it, but the release
#: kernel (tau1 = 3 ms) and spike timing are resolved only below it: larger steps are refused, not tolerated.
MAX_DT_MS = 0.2

_M1 = ("K1", "K2", "K3", "K4", "K5i", "K6i", "K", "Rmax", "Umax", "tau1", "tau2", "CS0", "B0", "T0", "CaSR0",
       "phi1", "phi2", "phi3", "phi4")
_M2 = ("C1", "C2", "C3", "C4", "C5", "T0", "alpha", "alpha1", "alpha2", "alpha3", "beta", "gamma",
       "phi1", "phi2", "phi3", "phi4")
_M3 = ("P0", "KSE", "g1", "g2", "a0", "b0", "c0", "d0")

#: Calcium states of Module 1 (M) recorded by default.
CA_STATES = ("CaSR", "CaSRCS", "CaSP", "CaSPB", "CaSPT")


def check_spike_times(spikes_ms: Iterable[float], name: str = "spike times") -> np.ndarray:
    """Validate spike times (ms): finite, non-negative, sorted. Returns them as float64."""
    s = np.asarray(list(spikes_ms) if not isinstance(spikes_ms, np.ndarray) else spikes_ms, dtype=float)
    if s.ndim != 1:
        raise InputError(f"{name}: expected a 1-D sequence of times in ms, got shape {s.shape}")
    if not np.all(np.isfinite(s)):
        raise InputError(f"{name}: non-finite value at index {int(np.flatnonzero(~np.isfinite(s))[0])}")
    if np.any(s < 0):
        raise InputError(f"{name}: negative time {s[s < 0][0]} ms at index {int(np.flatnonzero(s < 0)[0])}")
    if np.any(np.diff(s) < 0):
        raise InputError(f"{name}: not sorted (index {int(np.flatnonzero(np.diff(s) < 0)[0]) + 1})")
    return s


class MuscleUnit:
    """A motor unit's muscle fibres: KimCa -> KimAct -> KimForce point processes sharing a MuscleLength.

    Parameters
    ----------
    params: a complete ParameterSet (units of ``parameters.SPECS``: ms, M, mm, N).
    length_compensation: eq 18 (K5 scaled by phi(Xm)).
    movement_compensation: eqs 19-20 on the movement clock of the length input (``LengthTrace.onset_ms``).
    length_source: a MuscleLength point process to share (a pool's muscle); a private one is made if None.
    section: NEURON section that hosts the point processes; a private one-segment section if None.
    excitation: "kim" (Modules 1-2: KimCa -> KimAct) or "hatze" (HatzeExc, seed 000 eqs 6-9, with
        ``hatze_theta`` an ``neuromuscle.hatze.parameters.ExcitationTheta``, Table 2 if None).  Spikes go to
        ``self.receiver``.
    contraction: "kim" (Module 3, KimForce: force F in N, length from the MuscleLength in mm) or "hatze"
        (HatzeMTC of subject ``hatze_subject``, Table 1: moment M in N m, MTC angle offset
        ``force.phi_mtc_offset`` in rad).  Either excitation's A drives either contraction through the same
        POINTER; ``output_ref`` points at the output.  ``simulate`` uses contraction "kim".
    """

    def __init__(self, params: ParameterSet, *, length_compensation: bool = True,
                 movement_compensation: bool = False, length_source: Any = None, section: Any = None,
                 name: str = "unit", excitation: str = "kim", hatze_theta: Any = None,
                 contraction: str = "kim", hatze_subject: str = "3") -> None:
        if not isinstance(params, ParameterSet):
            raise InputError(f"{name}: params must be a ParameterSet (see load_parameters), got {type(params)}")
        load_mechanisms()
        from neuron import h

        self.params = params
        self.name = name
        self._sec = section if section is not None else h.Section(name=f"{name}_muscle")
        seg = self._sec(0.5)
        self.length = length_source if length_source is not None else h.MuscleLength(seg)
        if excitation == "kim":
            self._build_kim(seg, length_compensation, movement_compensation)
        elif excitation == "hatze":
            self._build_hatze(seg, hatze_theta)
        else:
            raise InputError(f"{name}: excitation must be 'kim' or 'hatze', got {excitation!r}")
        self.excitation = excitation
        if contraction == "kim":
            self.force = h.KimForce(seg)
            for n in _M3:
                setattr(self.force, n, params[n])
            self.force._ref_xm = self.length._ref_xm
            self.output = "F"  # N
        elif contraction == "hatze":
            self._build_hatze_mtc(seg, hatze_subject)
            self.output = "M"  # N m
        else:
            raise InputError(f"{name}: contraction must be 'kim' or 'hatze', got {contraction!r}")
        self.contraction = contraction
        self.force._ref_act = self.act._ref_A
        self._netcons: list[Any] = []
        self._spike_times: list[np.ndarray] = []

    def _build_kim(self, seg: Any, lencomp: bool, movcomp: bool) -> None:
        from neuron import h

        self.ca = h.KimCa(seg)
        self.act = h.KimAct(seg)
        for n in _M1:
            setattr(self.ca, n, self.params[n])
        for n in _M2:
            setattr(self.act, n, self.params[n])
        self.ca.xopt = self.act.xopt = self.params["g1"]
        self.ca.lencomp = 1.0 if lencomp else 0.0
        self.act.movcomp = 1.0 if movcomp else 0.0
        self.ca._ref_atil = self.act._ref_atil
        self.ca._ref_xm = self.length._ref_xm
        self.act._ref_caspt = self.ca._ref_CaSPT
        self.act._ref_xm = self.length._ref_xm
        self.act._ref_vm = self.length._ref_vm
        self.receiver = self.ca

    def _build_hatze(self, seg: Any, theta: Any) -> None:
        from neuron import h

        from .hatze.parameters import load_theta

        theta = load_theta() if theta is None else theta
        self.act = h.HatzeExc(seg)  # exposes A = q (eq 9) like KimAct
        for n in ("theta1", "theta2", "theta3", "theta4", "theta5"):
            setattr(self.act, n, float(getattr(theta, n)))
        self.receiver = self.act

    def _build_hatze_mtc(self, seg: Any, subject: str) -> None:
        from neuron import h

        from .hatze.parameters import load_subject

        sub = load_subject(subject)
        self.force = h.HatzeMTC(seg)  # angular MTC: moment M (N m); input phi_mtc_offset (rad), isometric 0
        for attr, value in (("k_see", sub.k_see), ("phi_ce_opt", sub.phi_ce_opt), ("Mmax", sub.m_max),
                            ("a_rel", sub.a_rel), ("b_rel", sub.b_rel), ("w", sub.w), ("k_pee", sub.k_pee),
                            ("phi_pee0_rel", sub.phi_pee0_rel)):
            setattr(self.force, attr, float(value))

    @property
    def output_ref(self) -> Any:
        """Reference to the contraction model's output: KimForce.F (N) or HatzeMTC.M (N m)."""
        return getattr(self.force, f"_ref_{self.output}")

    # -- spikes -------------------------------------------------------------------------------------------
    def connect_from(self, source: Any, *, threshold_mV: float = -10.0, delay_ms: float = 1.0,
                     section: Any = None) -> Any:
        """Deliver spikes from any NetCon source: a voltage reference (``sec(0.5)._ref_v``, give ``section``),
        an artificial cell (NetStim, VecStim), or None for events sent by hand. Returns the NetCon."""
        from neuron import h

        if section is not None:
            with_sec = h.NetCon(source, self.receiver, sec=section)
        else:
            with_sec = h.NetCon(source, self.receiver)
        with_sec.threshold = threshold_mV
        with_sec.delay = delay_ms
        with_sec.weight[0] = 1.0
        self._netcons.append(with_sec)
        return with_sec

    def add_spike_times(self, spikes_ms: Iterable[float]) -> None:
        """Deliver recorded spike times (ms) as events at initialisation (no per-step cost)."""
        self._spike_times.append(check_spike_times(spikes_ms))

    def _queue_spikes(self) -> None:
        if not self._spike_times:
            return
        nc = self._event_netcon
        for s in self._spike_times:
            for t in s:
                nc.event(float(t))

    def prepare(self) -> None:
        """Create what initialisation needs (called by ``simulate``/pools before ``finitialize``)."""
        from neuron import h

        if self._spike_times and not hasattr(self, "_event_netcon"):
            self._event_netcon = h.NetCon(None, self.receiver)
            self._event_netcon.weight[0] = 1.0
            self._fih = h.FInitializeHandler(1, self._queue_spikes)

    def destroy(self) -> None:
        """Remove every NEURON object this unit made (idempotent)."""
        for attr in ("_fih", "_event_netcon", "receiver", "force", "act", "ca", "length", "_sec"):
            if hasattr(self, attr):
                delattr(self, attr)
        self._netcons.clear()

    def __enter__(self) -> "MuscleUnit":
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy()


@dataclass
class SimulationResult:
    """Time course of one simulated unit. Units: t ms, force N, length mm, Ca states M, A and Atil 1."""

    t_ms: np.ndarray
    force_N: np.ndarray
    A: np.ndarray
    atil: np.ndarray
    ca_M: dict[str, np.ndarray]
    length_mm: np.ndarray
    params: ParameterSet
    settings: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    provenance: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str, overwrite: bool = False) -> None:
        """Write to HDF5 with provenance (see ``neuromuscle.results``)."""
        from .results import save_result

        save_result(self, path, overwrite=overwrite)


def _length_trace(length: LengthTrace | float, duration_ms: float) -> LengthTrace:
    if isinstance(length, LengthTrace):
        trace = length
    elif isinstance(length, (int, float)) and not isinstance(length, bool):
        trace = LengthTrace.isometric(float(length), duration_ms)
    else:
        raise InputError(f"length must be a LengthTrace or a constant length in mm, got {type(length)}")
    if not trace.covers(duration_ms):
        raise InputError(f"length trace {trace.name!r} spans {trace.t_ms[0]}..{trace.t_ms[-1]} ms, shorter "
                         f"than the run 0..{duration_ms} ms")
    return trace


def _check_run(duration_ms: float, dt_ms: float, record_dt_ms: float, method: str) -> None:
    if not np.isfinite(duration_ms) or duration_ms <= 0:
        raise InputError(f"duration_ms must be finite and > 0, got {duration_ms}")
    if method not in ("fixed", "cvode"):
        raise InputError(f"method must be 'fixed' or 'cvode', got {method!r}")
    if not np.isfinite(dt_ms) or dt_ms <= 0:
        raise InputError(f"dt_ms must be finite and > 0, got {dt_ms}")
    if method == "fixed" and dt_ms > MAX_DT_MS:
        raise InputError(f"dt_ms = {dt_ms} ms is too large for the fixed-step scheme (maximum {MAX_DT_MS} ms: "
                         "the 3 ms release kernel must be resolved)")
    if not np.isfinite(record_dt_ms) or record_dt_ms <= 0:
        raise InputError(f"record_dt_ms must be finite and > 0, got {record_dt_ms}")


class _NeuronRun:
    """Set NEURON's global integrator state for one run and restore it afterwards."""

    def __init__(self, method: str, dt_ms: float, atol: float, rtol: float) -> None:
        self.method, self.dt_ms, self.atol, self.rtol = method, dt_ms, atol, rtol

    def __enter__(self) -> Any:
        from neuron import h

        h.load_file("stdrun.hoc")
        self.cv = h.CVode()
        self.saved = (h.dt, h.steps_per_ms, self.cv.active(), self.cv.atol(), self.cv.rtol(), h.secondorder)
        h.secondorder = 0
        if self.method == "cvode":
            self.cv.active(1)
            self.cv.atol(self.atol)
            self.cv.rtol(self.rtol)
            _atol_scales()
        else:
            self.cv.active(0)
            h.dt = self.dt_ms
            h.steps_per_ms = 1.0 / self.dt_ms
        return h

    def __exit__(self, *exc: object) -> None:
        from neuron import h

        dt, spm, active, atol, rtol, so = self.saved
        self.cv.active(active)
        self.cv.atol(atol)
        self.cv.rtol(rtol)
        h.dt, h.steps_per_ms, h.secondorder = dt, spm, so


def _atol_scales() -> None:
    """Per-state absolute tolerances for CVODE: concentrations ~1e-4 M, lengths ~1 mm, Hatze's beta ~1e-9 s^2
    and gamma ~1e-15 s^4."""
    from neuron import h

    c = h.CVode()
    for st, scale in (("CaSR", 1e-9), ("CaSRCS", 1e-8), ("CaSP", 1e-11), ("CaSPB", 1e-10),
                      ("CaSPT", 1e-11), ("S2", 1e-6), ("S12", 1e-6)):
        c.atolscale(f"KimCa.{st}", scale)
    c.atolscale("KimAct.atil", 1e-5)
    c.atolscale("KimForce.xce", 1e-6)
    for st, scale in (("b", 1e-12), ("vb", 1e-9), ("g", 1e-18), ("vg", 1e-15)):
        c.atolscale(f"HatzeExc.{st}", scale)
    c.atolscale("HatzeMTC.phi_ce", 1e-3)


def simulate(params: ParameterSet, spikes_ms: Iterable[float], length: LengthTrace | float,
             duration_ms: float, *, dt_ms: float = 0.025, method: str = "fixed", record_dt_ms: float = 0.1,
             length_compensation: bool = True, movement_compensation: bool = False,
             atol: float = 1e-3, rtol: float = 1e-6, provenance_extra: dict | None = None,
             excitation: str = "kim", hatze_theta: Any = None) -> SimulationResult:
    """Simulate one unit from 0 to duration_ms (ms).

    spikes_ms: stimulus times (ms, sorted, finite, >= 0).  length: a LengthTrace or a constant length (mm).
    method: "fixed" (linearly implicit step dt_ms) or "cvode" (variable step, atol/rtol; spikes as events).
    Records every record_dt_ms (ms).  The length is played continuously into the unit's MuscleLength.
    excitation: "kim" (Modules 1-2) or "hatze" (seed 000 eqs 6-9, ``hatze_theta``) in front of Module 3.
    """
    _check_run(duration_ms, dt_ms, record_dt_ms, method)
    spikes = check_spike_times(spikes_ms)
    trace = _length_trace(length, duration_ms)
    if excitation == "hatze" and spikes.size > 1 and np.min(np.diff(spikes)) < 1.0:
        raise InputError("spike times: Hatze pulses last 1 ms and may not overlap; an interval is "
                         f"{np.min(np.diff(spikes)):.3f} ms")
    unit = MuscleUnit(params, length_compensation=length_compensation,
                      movement_compensation=movement_compensation, excitation=excitation,
                      hatze_theta=hatze_theta)
    extra = dict(provenance_extra or {})
    extra["excitation"] = excitation
    if excitation == "hatze":
        extra["hatze_theta_SI"] = {n: float(getattr(unit.act, n)) for n in
                                   ("theta1", "theta2", "theta3", "theta4", "theta5")}
    try:
        return _run(unit, spikes, trace, duration_ms, dt_ms, method, record_dt_ms, atol, rtol,
                    extra, length_compensation, movement_compensation)
    finally:
        unit.destroy()


def _run(unit: MuscleUnit, spikes: np.ndarray, trace: LengthTrace, duration_ms: float, dt_ms: float,
         method: str, record_dt_ms: float, atol: float, rtol: float, extra: dict,
         lencomp: bool, movcomp: bool) -> SimulationResult:
    from neuron import h

    from .provenance import provenance

    unit.add_spike_times(spikes)
    unit.prepare()
    kim = unit.excitation == "kim"
    if trace.onset_ms is not None and kim:
        unit.act.onset = trace.onset_ms
    tvec = h.Vector(trace.t_ms)
    xvec = h.Vector(trace.xm_mm)
    vvec = h.Vector(trace.velocity_mm_s)
    unit.length.xm = float(trace.xm_mm[0])
    unit.length.vm = float(trace.velocity_mm_s[0])
    if not trace.is_isometric:
        xvec.play(unit.length._ref_xm, tvec, 1)
        vvec.play(unit.length._ref_vm, tvec, 1)
    # time itself is not recorded (a record of t belongs to no thread): samples are at k * record_dt_ms
    states = CA_STATES if kim else ()
    recs = {"F": h.Vector(), "A": h.Vector(), "atil": h.Vector(), "xm": h.Vector(),
            **{s: h.Vector() for s in states}}
    recs["F"].record(unit.force._ref_F, record_dt_ms)
    recs["A"].record(unit.act._ref_A, record_dt_ms)
    # Hatze's model has no Atil: its gamma (s^4) is recorded in that slot
    recs["atil"].record(unit.act._ref_atil if kim else unit.act._ref_g, record_dt_ms)
    recs["xm"].record(unit.length._ref_xm, record_dt_ms)
    for s in states:
        recs[s].record(getattr(unit.ca, f"_ref_{s}"), record_dt_ms)
    with _NeuronRun(method, dt_ms, atol, rtol) as hh:
        hh.finitialize()
        if method == "cvode" and trace.onset_ms is not None and movcomp:
            hh.CVode().event(trace.onset_ms)
        if method == "cvode":
            hh.continuerun(duration_ms)
        else:  # psolve steps in C: no per-step hoc interpreter loop
            pc = hh.ParallelContext()
            pc.set_maxstep(10.0)
            pc.psolve(duration_ms)
    out = {k: np.array(v) for k, v in recs.items()}
    xvec.play_remove()
    vvec.play_remove()
    n = min(len(v) for v in out.values())
    out = {k: v[:n] for k, v in out.items()}
    out["t"] = np.arange(n) * record_dt_ms
    bad = [k for k, v in out.items() if not np.all(np.isfinite(v))]
    if bad:
        i = int(np.flatnonzero(~np.isfinite(out[bad[0]]))[0])
        raise NumericalError(f"{unit.name}: non-finite {bad[0]} at t = {out['t'][i]:.3f} ms ({method}, dt "
                             f"{dt_ms} ms): the integration failed")
    warnings = []
    nasym = int(unit.force.nasym)
    if nasym:
        warnings.append(f"the force exceeded the Mashima asymptote during {nasym} steps: the CE yielded at "
                        "the continued (tangent, vmax-capped) velocity")
    settings = {"duration_ms": duration_ms, "dt_ms": dt_ms if method == "fixed" else None, "method": method,
                "record_dt_ms": record_dt_ms, "atol": atol if method == "cvode" else None,
                "rtol": rtol if method == "cvode" else None, "length_compensation": lencomp,
                "movement_compensation": movcomp, "movement_onset_ms": trace.onset_ms,
                "n_spikes": int(spikes.size), "excitation": unit.excitation}
    return SimulationResult(
        t_ms=out["t"], force_N=out["F"], A=out["A"], atil=out["atil"],
        ca_M={s: out[s] for s in states}, length_mm=out["xm"], params=unit.params, settings=settings,
        warnings=warnings,
        provenance=provenance(settings=settings, parameter_set=unit.params.name, spikes_ms=spikes.tolist(),
                              **extra))
