"""A reduced motoneuron in NEURON: soma + one dendrite, its parameters scaled by cell size across S, FR and FF.

    mn = Motoneuron(motoneuron_parameters(0.0))      # the smallest S cell; 1.0 is the largest FF cell
    mn.soma, mn.dend                                 # NEURON sections; mn.spike_source() for NetCons
    mn.axon_delay_ms                                 # axon conduction delay to the muscle (ms)
    mn.destroy()

Channels (mod/mn_*.mod, kinetics and sources in each header): soma mn_naf, mn_kdr, mn_can (N-type Ca),
mn_cadyn (submembrane Ca), mn_kca (the AHP), leak (pas); dendrite mn_cal (L-type Ca PIC) and leak.  By default
(``channels="fused"``) the soma's five and its leak run as one mechanism, mn_soma, and the PIC with the
dendrite's leak as mn_pic, each also carrying its compartment's share of the common synaptic drive: the same
equations with tabulated rates under the fixed step (exact under CVODE), a third faster in a pool;
``channels="fused_fixed"`` runs them as mn_soma_fixed and mn_pic_fixed, cheaper again per step, under the fixed
step only (the Simulator refuses them under CVODE);
``channels="separate"`` builds the reference (tests/pool/test_motoneuron_channels.py compares them).  The structure
is that of Booth, Rinzel & Kiehn 1997 (two compartments, PIC in the dendrite); the geometry is an equivalent
cylinder dendrite.

Size scaling (``motoneuron_parameters``): the size index x in [0, 1] places a cell between the smallest S and
the largest FF motoneuron; every size-dependent parameter is interpolated geometrically between its two ends
(``SIZE_RANGE``).  Larger cells: a larger soma and dendrite and a lower specific membrane resistance (lower input
resistance, higher rheobase: Henneman's size principle), a faster-decaying AHP calcium (shorter AHP), faster axons.
The dendrite is an equivalent cylinder of electrotonic length about 1.2 (cat lumbar motoneurons: 1-2, Fleshman,
Segev & Burke 1988), total membrane area 0.28 (S) to 0.52 mm2 (FF).  The AHP's K(Ca) conductance has a half-
activation of 2 uM, so successive spikes sum their AHPs over the primary range instead of saturating it at the
first spike.  Measured at ``neuromodulation=0`` (no PIC, as in the anaesthetised cat) the cells fall within the
published cat ranges (tests/pool/test_motoneuron_physiology.py):
  input resistance  S ~2.6, FF ~0.7 MOhm      (Zengel, Reid, Sypert & Munson 1985: S 1.6 +- 0.5, FF 0.6 +- 0.2)
  rheobase          S ~5, FF ~18 nA           (Zengel et al. 1985: S 5 +- 2, FR 12, FF 21 nA)
  AHP duration      S ~160, FF ~70 ms         (Zengel et al. 1985; Gustafsson & Pinter 1984)
  f-I slope         1-2 Hz/nA, steady discharge (Kernell 1965; Powers & Binder 2001: primary range 1-4 Hz/nA)
  conduction        80 (S) to 110 m/s (FF)    (Burke 1981; Zengel et al. 1985)
The exact figures are printed by ``python -m neuromuscle.pool.excitability``.

Neuromodulation (``neuromodulation``, 0 upward): the dendritic L-type PIC's conductance is ``neuromodulation``
times its full density ``g_cal_S_per_cm2``, as monoamines (serotonin, noradrenaline from the brainstem) set the
PIC's strength in vivo (Heckman, Lee & Brownstone 2003; Heckman & Enoka 2012).  0: no PIC (anaesthetised cat);
1: the decerebrate cat's strong state, S cells bistable (a brief excitation starts firing that outlasts it: Lee &
Heckman 1998); ``HUMAN_NEUROMODULATION``: moderate, giving the recruitment-derecruitment hysteresis of human
motor units (Delta F of a few Hz by the paired-unit method: Gorassini, Yang, Eken & Bennett 2002).  The PIC
activates from about -65 mV (half-activation -57 mV, slope 4 mV), just below the spike threshold, as in the
decerebrate cat (Lee & Heckman 1998: onset a few mV below recruitment).

Late adaptation (``g_ks_S_per_cm2``, off by default): a slow potassium current in the soma (mod/mn_ks.mod) that
each spike activates a little and that decays with ``ks_tau_ms``, so that a steady discharge slows over seconds,
the faster cells more (Kernell & Monster 1982).

Minimum rate (``g_km_S_per_cm2``, off by default): an M-like potassium current in the soma (mod/mn_km.mod,
half-activated at ``km_vhalf_mV``, time constant ``km_tau_ms``) that makes the onset of repetitive firing abrupt,
so that a cell fires at or above a minimum steady rate near the inverse of its AHP duration or not at all (Kernell
1965), where without it a cell with its PIC on fires ever more slowly as its drive approaches threshold.

Where the PIC sits (``pic_start_x``, 0 by default: the whole dendrite): the L-type channels of cat motoneurons lie
in the dendrites away from the soma, in hot spots farther out in larger cells (Elbasiouny, Bennett & Mushahwar
2005: 300-850 um from the soma; Grande, Bui & Rose 2007); ``pic_start_x`` leaves the dendrite's proximal part (that
fraction of its length) without PIC and puts the same total conductance on the rest.

Units: um, ohm cm2, S/cm2, ms, mV, m/s, mm, mM.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from ..errors import InputError
from ..validate import finite_number, positive_number

#: The channel implementations: "fused" (mn_soma + mn_pic: one mechanism per compartment, tabulated rates under
#: the fixed step; the default), "fused_fixed" (mn_soma_fixed + mn_pic_fixed: the same at a lower cost per step,
#: the fixed step only) or "separate" (mn_naf, mn_kdr, mn_can, mn_cadyn, mn_kca + mn_cal: the reference, one
#: mechanism per channel, NEURON's cnexp).
CHANNELS = ("fused", "fused_fixed", "separate")

#: The soma's and the dendrite's mechanism of each fused channel set.
FUSED_CHANNELS = {"fused": ("mn_soma", "mn_pic"), "fused_fixed": ("mn_soma_fixed", "mn_pic_fixed")}

#: Reversal potential (mV) of the excitatory synaptic drive (glutamatergic, AMPA-like: mixed cations).
SYNAPTIC_REVERSAL_MV = 0.0

#: What a pool records of a motoneuron (``Pool.record``'s "mn.<name>") and its unit: the soma's and the
#: dendrite's middle membrane potential, the PIC's current density at the dendrite's middle (inward < 0) and the
#: soma's submembrane calcium.
RECORDABLES = {"v": "mV", "v_dend": "mV", "i_pic": "mA/cm2", "cai": "mM"}

#: Motor-unit types in size order (slow, fast fatigue-resistant, fast fatigable).
TYPES = ("S", "FR", "FF")

#: Size-dependent parameters: (value at x = 0, the smallest S cell; value at x = 1, the largest FF cell).
SIZE_RANGE: dict[str, tuple[float, float]] = {
    "soma_diam_um": (55.0, 80.0),
    "dend_length_um": (3500.0, 4200.0),
    "dend_diam_um": (25.0, 38.0),
    "rm_soma_ohm_cm2": (600.0, 250.0),
    "rm_dend_ohm_cm2": (8000.0, 4500.0),
    "ca_decay_ms": (45.0, 12.0),
    "conduction_m_per_s": (80.0, 110.0),
    "g_cal_S_per_cm2": (6.0e-5, 6.0e-5),
}

#: Neuromodulation of human voluntary contractions: the PIC strength (fraction of full) that gives human motor
#: units their recruitment-derecruitment hysteresis (see the module docstring).
HUMAN_NEUROMODULATION = 0.6
#: Each cell's own synaptic noise (uS at a drive of 1 uS; ``PoolDefinition.synaptic_noise_uS``) with which the
#: human profile's cells, at steady drives of 0.6-1.0 uS, vary their interspike intervals as the decomposed human
#: units do (CV 0.12-0.33, median near the recorded 0.165).  No profile sets it: with it the same cells are
#: recruited by the fluctuations at low rates (docs/guide/pools.md, "Synaptic noise").
IRREGULAR_NOISE_US = 0.05


@dataclass(frozen=True)
class MotoneuronProfile:
    """A named setting of a pool's reduced cells: the neuromodulation, fields replaced in every cell
    (``overrides``), factors on size-dependent parameters (``scales``) and each cell's own synaptic noise
    (``synaptic_noise_uS``, uS), as ``PoolDefinition`` takes them (``pool_options``)."""

    name: str
    neuromodulation: float
    overrides: tuple[tuple[str, float], ...] = ()
    scales: tuple[tuple[str, float], ...] = ()
    about: str = ""
    synaptic_noise_uS: float = 0.0

    def pool_options(self) -> dict[str, Any]:
        """``PoolDefinition`` keyword arguments: neuromodulation, motoneuron_overrides, motoneuron_scales,
        synaptic_noise_uS."""
        return {"neuromodulation": self.neuromodulation, "motoneuron_overrides": dict(self.overrides),
                "motoneuron_scales": dict(self.scales), "synaptic_noise_uS": self.synaptic_noise_uS}


#: The pools' motoneuron profiles.  "default": the cells as scaled to cat data (module docstring) with the PIC at
#: ``HUMAN_NEUROMODULATION``.  "human": the setting whose pools, following recorded human forces, fire like the
#: decomposed human units (docs/validation/pools_vs_recorded.md): an M-like current for a minimum steady rate near
#: the inverse of the AHP (Kernell 1965), a slow K current for late adaptation (Kernell & Monster 1982), AHPs 1.3
#: times as long (human estimates 145-255 ms, Kudina & Alexeeva 1992) and the PIC at 0.7 of the decerebrate cat's
#: (the four chosen together on the recordings, so the rates there are a fit; the thresholds and the rates at
#: other levels are the test).
PROFILES: dict[str, MotoneuronProfile] = {
    "default": MotoneuronProfile("default", HUMAN_NEUROMODULATION,
                                 about="cells scaled to cat data, PIC at the neuromodulation of human contractions"),
    "human": MotoneuronProfile("human", 0.7, (("g_km_S_per_cm2", 0.002), ("g_ks_S_per_cm2", 0.03)),
                               (("ca_decay_ms", 1.3),),
                               about="minimum rate, late adaptation and AHPs of human motor units"),
}


def describe_profiles() -> str:
    """One line naming every profile and what it is (``MotoneuronProfile.about``), for help texts."""
    return "; ".join(f"{p.name}: {p.about}" for p in PROFILES.values())


def motoneuron_profile(name: str) -> MotoneuronProfile:
    """The profile called ``name`` (``PROFILES``); InputError naming the known ones otherwise."""
    if name not in PROFILES:
        raise InputError(f"motoneuron profile {name!r}: known profiles are {', '.join(PROFILES)}")
    return PROFILES[name]


@dataclass(frozen=True)
class MotoneuronParameters:
    """One motoneuron's parameters (units in the names; conductances in S/cm2).  ``size`` is the index in [0, 1]
    they were made from (None if set by hand) and ``unit_type`` one of TYPES.  ``g_cal_S_per_cm2`` is the PIC's full
    density; the cell gets ``neuromodulation`` times it (``g_pic_S_per_cm2``)."""

    soma_diam_um: float
    dend_length_um: float
    dend_diam_um: float
    rm_soma_ohm_cm2: float
    rm_dend_ohm_cm2: float
    ca_decay_ms: float
    conduction_m_per_s: float
    g_cal_S_per_cm2: float
    unit_type: str = "S"
    size: float | None = None
    axon_length_mm: float = 600.0
    ra_ohm_cm: float = 70.0
    cm_uF_per_cm2: float = 1.0
    e_leak_mV: float = -70.0
    ena_mV: float = 50.0
    ek_mV: float = -80.0
    g_naf_S_per_cm2: float = 0.6
    g_kdr_S_per_cm2: float = 0.15
    g_can_S_per_cm2: float = 0.01
    g_kca_S_per_cm2: float = 0.012
    kca_kd_mM: float = 0.002
    ca_depth_um: float = 1.0
    cal_vhalf_mV: float = -57.0
    cal_slope_mV: float = 4.0
    neuromodulation: float = HUMAN_NEUROMODULATION
    g_ks_S_per_cm2: float = 0.0
    ks_tau_ms: float = 10000.0
    g_km_S_per_cm2: float = 0.0
    km_vhalf_mV: float = -55.0
    km_slope_mV: float = 4.0
    km_tau_ms: float = 100.0
    pic_start_x: float = 0.0
    dend_nseg: int = 3

    def __post_init__(self) -> None:
        where = f"motoneuron ({self.unit_type})"
        if self.unit_type not in TYPES:
            raise InputError(f"{where}: unit_type must be one of {', '.join(TYPES)}, got {self.unit_type!r}")
        for f in fields(self):
            if f.name in ("unit_type", "size", "dend_nseg"):
                continue
            v = finite_number(f"{where}: {f.name}", getattr(self, f.name))
            negative_ok = f.name.endswith("_mV") and "slope" not in f.name     # a gate's slope must be > 0
            zero_ok = f.name.startswith("g_") or f.name == "neuromodulation"
            if f.name == "pic_start_x":
                if not 0.0 <= v < 1.0:
                    raise InputError(f"{where}: pic_start_x must lie in [0, 1), got {v!r}")
                continue
            if not negative_ok and (v < 0 or (v == 0 and not zero_ok)):
                raise InputError(f"{where}: {f.name} must be {'>= 0' if zero_ok else '> 0'}, got {v!r}")
        if not isinstance(self.dend_nseg, int) or isinstance(self.dend_nseg, bool) or self.dend_nseg < 1:
            raise InputError(f"{where}: dend_nseg must be an integer >= 1, got {self.dend_nseg!r}")

    @property
    def axon_delay_ms(self) -> float:
        """Conduction delay (ms) from the soma to the muscle: axon_length_mm / conduction_m_per_s."""
        return self.axon_length_mm / self.conduction_m_per_s

    @property
    def g_pic_S_per_cm2(self) -> float:
        """The dendritic PIC's density in the cell (S/cm2): neuromodulation x g_cal_S_per_cm2."""
        return self.neuromodulation * self.g_cal_S_per_cm2

    def pic_densities(self) -> list[float]:
        """The PIC's density (S/cm2) in each of the dendrite's ``dend_nseg`` segments: ``g_pic_S_per_cm2`` spread
        over the part of the dendrite beyond ``pic_start_x`` (its normalised distance from the soma), each segment
        weighted by the share of its length there, so that the cell's total PIC conductance does not depend on
        where it starts."""
        n, x0 = self.dend_nseg, self.pic_start_x
        share = [min(max((i + 1) / n - x0, 0.0), 1.0 / n) * n for i in range(n)]
        return [self.g_pic_S_per_cm2 * w / (1.0 - x0) for w in share]

    def to_dict(self) -> dict[str, Any]:
        """The parameters as a JSON-ready dict."""
        return asdict(self)


def unit_type_of(size: float, fractions: tuple[float, float, float] = (0.25, 0.25, 0.5)) -> str:
    """The type (S, FR, FF) of the cell at size index ``size`` in a pool whose S, FR, FF fractions (summing to 1)
    are ``fractions``, the smallest cells being S."""
    s, fr, ff = fractions
    if min(fractions) < 0 or abs(s + fr + ff - 1.0) > 1e-9:
        raise InputError(f"type fractions (S, FR, FF) must be >= 0 and sum to 1, got {fractions}")
    if size < s or (fr == 0 and ff == 0):
        return "S"
    return "FR" if size < s + fr or ff == 0 else "FF"


def motoneuron_parameters(size: float, unit_type: str | None = None, *, scales: Mapping[str, float] | None = None,
                          **overrides: Any) -> MotoneuronParameters:
    """Parameters of the cell at size index ``size`` in [0, 1] (0: smallest S, 1: largest FF), interpolated
    geometrically over SIZE_RANGE; ``scales`` multiply size-dependent ones (e.g. ``{"ca_decay_ms": 2}``, a pool
    whose AHPs last twice as long); ``unit_type`` defaults to ``unit_type_of(size)``; ``overrides`` replace any
    field (e.g. ``neuromodulation=0`` removes the PIC, ``axon_length_mm=900`` for a human leg)."""
    x = finite_number("motoneuron size index", size)
    if not 0.0 <= x <= 1.0:
        raise InputError(f"motoneuron size index must lie in [0, 1], got {x}")
    values = {k: lo * math.exp(x * math.log(hi / lo)) for k, (lo, hi) in SIZE_RANGE.items()}
    for k, factor in (scales or {}).items():
        if k not in SIZE_RANGE:
            raise InputError(f"motoneuron scale {k!r}: only size-dependent parameters scale ({', '.join(SIZE_RANGE)})")
        values[k] *= positive_number(f"motoneuron scale {k}", factor)
    p = MotoneuronParameters(**values, unit_type=unit_type or unit_type_of(x), size=x)
    unknown = set(overrides) - {f.name for f in fields(MotoneuronParameters)}
    if unknown:
        raise InputError(f"unknown motoneuron parameter(s) {sorted(unknown)}")
    return replace(p, **overrides) if overrides else p


def parse_settings(items: Iterable[str]) -> dict[str, float]:
    """Motoneuron parameters from command-line settings "NAME=VALUE" (e.g. ``cal_vhalf_mV=-52``): a dict for
    ``motoneuron_parameters(**...)`` or ``PoolDefinition(motoneuron_overrides=...)``; InputError naming the setting
    when it has no "=", an unknown name or a value that is not a number.  The neuromodulation has its own option in
    each command (a setting would silently replace it) and is refused here."""
    known = {f.name for f in fields(MotoneuronParameters)} - {"unit_type", "size", "dend_nseg", "neuromodulation"}
    out: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep:
            raise InputError(f"motoneuron setting {item!r}: expected NAME=VALUE")
        if name == "neuromodulation":
            raise InputError(f"motoneuron setting {item!r}: give the neuromodulation by its own option")
        if name not in known:
            raise InputError(f"motoneuron setting {item!r}: no parameter {name!r}; known: {', '.join(sorted(known))}")
        try:
            out[name] = float(value)
        except ValueError:
            raise InputError(f"motoneuron setting {item!r}: the value is not a number") from None
    return out


#: The fused mechanisms that carry their compartment's synaptic conductance (``gsyn``, and a pool's common drive
#: from their shared GLOBAL ``gcommon``, uS).
COMMON_SYNAPTIC_MECHANISMS = tuple(name for pair in FUSED_CHANNELS.values() for name in pair)


def membrane_area_um2(sections: Iterable[Any]) -> float:
    """Total membrane area (um2) of ``sections``."""
    from neuron import h

    return float(sum(h.area(seg.x, sec=seg.sec) for sec in sections for seg in sec))


def held_steps(times_ms: Any, values: np.ndarray) -> tuple[Any, np.ndarray]:
    """The knots (a hoc Vector of times, ms, and the values) of a continuous Vector.play that holds each of
    ``values`` from its time in ``times_ms`` to the next: two knots at every step (CoreNEURON plays no events into
    mechanism instances)."""
    from neuron import h

    t = np.asarray(times_ms, float)
    v = np.asarray(values, float)
    return h.Vector(np.repeat(t, 2)[1:]), (np.repeat(v, 2)[:-1] if v.size == t.size else v)


def play_synaptic_conductance(sections: Sequence[Any], times_ms: Any, conductance_uS: Any,
                              events: bool = True, fused: Iterable[str] | None = None) -> list[Any]:
    """Excitatory synaptic conductance on a whole cell, reversal SYNAPTIC_REVERSAL_MV: ``conductance_uS`` (uS,
    the cell's total, numbers) from each of ``times_ms`` (a hoc Vector, ms) to the next, spread uniformly over
    the membrane of ``sections`` (mod/mn_syn.mod, which NEURON and CoreNEURON both run; one Vector.play a
    segment, its values set as events at those times, not interpolated every step).  events=False: a continuous
    play of the same steps (each value held to the next time: CoreNEURON plays no events into a density
    mechanism).  ``fused``: names of mechanisms that carry their compartment's synaptic conductance as ``gsyn``
    (mn_soma, mn_pic: mod/mn_ohmic.inc); a segment holding one of them gets the drive there instead of an mn_syn.
    Returns the Vectors to keep alive (``times_ms`` among them)."""
    from neuron import h

    density = 100.0 / membrane_area_um2(sections)   # S/cm2 per uS of the cell's total: 1e-6 S / (A um2 * 1e-8)
    values = np.asarray(conductance_uS, float) * density
    kept = [times_ms]   # a play whose time Vector is freed stops: the caller need not keep it
    if not events:
        times_ms, values = held_steps(times_ms, values)
        kept.append(times_ms)
    carriers = tuple(fused or ())
    for sec in sections:
        own = next((name for name in carriers if sec.has_membrane(name)), None)
        if own is None:
            sec.insert("mn_syn")
        for seg in sec:
            mech = getattr(seg, own or "mn_syn")
            if own is None:
                mech.e, mech.g = SYNAPTIC_REVERSAL_MV, 0.0
                ref = mech._ref_g
            else:
                mech.esyn, mech.gsyn = SYNAPTIC_REVERSAL_MV, 0.0
                ref = mech._ref_gsyn
            g = h.Vector(values)
            g.play(ref, times_ms, 0 if events else 1)
            kept.append(g)
    return kept


def clear_synaptic_conductance(sections: Iterable[Any]) -> None:
    """Take the common synaptic drive off ``sections`` (after its plays are removed): mn_syn is removed and the
    fused mechanisms' own ``gsyn`` set to 0."""
    for sec in sections:
        if sec.has_membrane("mn_syn"):
            sec.uninsert("mn_syn")
        for name in COMMON_SYNAPTIC_MECHANISMS:
            if sec.has_membrane(name):
                for seg in sec:
                    getattr(seg, name).gsyn = 0.0


class Motoneuron:
    """The cell in NEURON (soma + dendrite); ``destroy()`` or ``with`` removes it.  ``pic_substeps`` k (fused
    channels, fixed step): the PIC's gate, whose time constant is 60 ms, advances every k membrane steps by one
    step of k dt (its current is computed every step); 1 is the exact update of every step."""

    def __init__(self, params: MotoneuronParameters, name: str = "mn", channels: str = "fused",
                 pic_substeps: int = 1) -> None:
        from ..model.mechanisms import load_mechanisms

        if not isinstance(params, MotoneuronParameters):
            raise InputError(f"{name}: params must be MotoneuronParameters, got {type(params).__name__}")
        if channels not in CHANNELS:
            raise InputError(f"{name}: channels must be one of {', '.join(CHANNELS)}, got {channels!r}")
        if isinstance(pic_substeps, bool) or not isinstance(pic_substeps, int) or pic_substeps < 1:
            raise InputError(f"{name}: pic_substeps must be an integer >= 1, got {pic_substeps!r}")
        if pic_substeps > 1 and channels not in FUSED_CHANNELS:
            raise InputError(f"{name}: pic_substeps = {pic_substeps} needs the fused channels")
        load_mechanisms()
        from neuron import h

        self.params = params
        self.name = name
        p = params
        self.soma = h.Section(name=f"{name}_soma")
        self.dend = h.Section(name=f"{name}_dend")
        self.dend.connect(self.soma(1.0))
        self.soma.L = self.soma.diam = p.soma_diam_um
        self.dend.L, self.dend.diam, self.dend.nseg = p.dend_length_um, p.dend_diam_um, p.dend_nseg
        for sec in self.sections:
            sec.Ra, sec.cm = p.ra_ohm_cm, p.cm_uF_per_cm2
        self.channels = channels
        if channels in FUSED_CHANNELS:
            # the leak and the synaptic drive ride in the fused mechanisms (mn_ohmic.inc): no pas, no mn_syn
            soma_mech, pic_mech = self.fused_mechanisms
            self.soma.insert(soma_mech)
            m = getattr(self.soma(0.5), soma_mech)
            m.gnaf, m.gkdr, m.gcan, m.gkca = (p.g_naf_S_per_cm2, p.g_kdr_S_per_cm2, p.g_can_S_per_cm2,
                                              p.g_kca_S_per_cm2)
            m.ena, m.ek, m.depth, m.taur, m.kd = p.ena_mV, p.ek_mV, p.ca_depth_um, p.ca_decay_ms, p.kca_kd_mM
            m.gleak, m.eleak = 1.0 / p.rm_soma_ohm_cm2, p.e_leak_mV
            self.dend.insert(pic_mech)
            for s, g in zip(self.dend, p.pic_densities()):
                pic = getattr(s, pic_mech)
                pic.gbar, pic.vhalf, pic.slope = g, p.cal_vhalf_mV, p.cal_slope_mV
                pic.gleak, pic.eleak = 1.0 / p.rm_dend_ohm_cm2, p.e_leak_mV
                pic.substeps = pic_substeps
            self._insert_slow_potassium()
            return
        for sec, rm in ((self.soma, p.rm_soma_ohm_cm2), (self.dend, p.rm_dend_ohm_cm2)):
            sec.insert("pas")
            for seg in sec:
                seg.pas.g, seg.pas.e = 1.0 / rm, p.e_leak_mV
        for mech in ("mn_naf", "mn_kdr", "mn_can", "mn_cadyn", "mn_kca"):
            self.soma.insert(mech)
        seg = self.soma(0.5)
        seg.mn_naf.gbar, seg.mn_kdr.gbar = p.g_naf_S_per_cm2, p.g_kdr_S_per_cm2
        seg.mn_can.gbar, seg.mn_kca.gbar, seg.mn_kca.kd = p.g_can_S_per_cm2, p.g_kca_S_per_cm2, p.kca_kd_mM
        seg.mn_cadyn.depth, seg.mn_cadyn.taur = p.ca_depth_um, p.ca_decay_ms
        self.soma.ena, self.soma.ek = p.ena_mV, p.ek_mV
        self.dend.insert("mn_cal")
        for s, g in zip(self.dend, p.pic_densities()):
            s.mn_cal.gbar, s.mn_cal.vhalf, s.mn_cal.slope = g, p.cal_vhalf_mV, p.cal_slope_mV
        self._insert_slow_potassium()

    def _insert_slow_potassium(self) -> None:
        """The soma's slow potassium currents, each only when its conductance is > 0: mn_ks (late adaptation,
        g_ks_S_per_cm2) and mn_km (the M-like current that sets a minimum steady rate, g_km_S_per_cm2)."""
        p = self.params
        if p.g_ks_S_per_cm2 > 0:
            self.soma.insert("mn_ks")
            m = self.soma(0.5).mn_ks
            m.gbar, m.mtau, m.ek = p.g_ks_S_per_cm2, p.ks_tau_ms, p.ek_mV
        if p.g_km_S_per_cm2 > 0:
            self.soma.insert("mn_km")
            m = self.soma(0.5).mn_km
            m.gbar, m.mtau, m.ek = p.g_km_S_per_cm2, p.km_tau_ms, p.ek_mV
            m.vhalf, m.slope = p.km_vhalf_mV, p.km_slope_mV

    @property
    def fused_mechanisms(self) -> tuple[str, str]:
        """The soma's and the dendrite's mechanism of the fused channels (("", "") with the separate ones)."""
        return FUSED_CHANNELS.get(self.channels, ("", ""))

    @property
    def axon_delay_ms(self) -> float:
        """Conduction delay (ms) from the soma to the muscle unit."""
        return self.params.axon_delay_ms

    @property
    def sections(self) -> list[Any]:
        """The cell's sections: soma and dendrite."""
        return [self.soma, self.dend]

    @property
    def v_rest_mV(self) -> float:
        """The potential (mV) runs of the cell start from: the leak reversal."""
        return self.params.e_leak_mV

    def membrane_area_um2(self) -> float:
        """Total membrane area of soma and dendrite (um2)."""
        return membrane_area_um2(self.sections)

    def play_synaptic_conductance(self, times_ms: Any, conductance_uS: Any, events: bool = True) -> list[Any]:
        """The common synaptic drive on soma and dendrite (``play_synaptic_conductance``; with the fused
        channels into mn_soma's and mn_pic's own ``gsyn``); returns the Vectors to keep alive."""
        fused = self.fused_mechanisms if self.channels in FUSED_CHANNELS else None
        return play_synaptic_conductance(self.sections, times_ms, conductance_uS, events, fused)

    def share_common_synaptic(self, on: bool) -> None:
        """Let the fused mechanisms' shared ``gcommon`` (uS, one play for a whole pool: ``Pool.drive_synaptic``)
        drive this cell (``on``), spread uniformly over its membrane as ``play_synaptic_conductance`` spreads it,
        or not.  Only the fused channels carry it."""
        if self.channels not in FUSED_CHANNELS:
            raise InputError(f"{self.name}: only the fused channels share a common synaptic drive")
        density = 100.0 / self.membrane_area_um2() if on else 0.0   # S/cm2 per uS of the cell's total
        soma_mech, pic_mech = self.fused_mechanisms
        soma = getattr(self.soma(0.5), soma_mech)
        soma.fcommon, soma.esyn = density, SYNAPTIC_REVERSAL_MV
        for seg in self.dend:
            pic = getattr(seg, pic_mech)
            pic.fcommon, pic.esyn = density, SYNAPTIC_REVERSAL_MV

    def recordables(self) -> dict[str, str]:
        """The recordable variables (RECORDABLES) with their units."""
        return dict(RECORDABLES)

    def section_of(self, variable: str) -> Any:
        """The section holding ``variable`` (one of RECORDABLES)."""
        return self.dend if variable in ("v_dend", "i_pic") else self.soma

    def ref(self, variable: str) -> Any:
        """NEURON reference to ``variable`` (one of RECORDABLES); InputError naming the recordable ones."""
        if variable not in RECORDABLES:
            raise InputError(f"{self.name}: no variable {variable!r}; recordable: {', '.join(RECORDABLES)}")
        seg = self.section_of(variable)(0.5)
        if variable in ("v", "v_dend"):
            return seg._ref_v
        soma_mech, pic_mech = self.fused_mechanisms
        if variable == "i_pic":   # mn_cal is the dendrite's only calcium current
            return getattr(seg, pic_mech)._ref_ipic if pic_mech else seg._ref_ica
        return getattr(seg, soma_mech)._ref_cai if soma_mech else seg._ref_cai

    def spike_source(self) -> Any:
        """The soma's membrane potential reference (a NetCon source; give ``section=self.soma``)."""
        return self.soma(0.5)._ref_v

    def input_resistance_MOhm(self) -> float:
        """Input resistance at the soma (MOhm): NEURON's Impedance at 0 Hz after ``finitialize`` at the leak
        reversal, each mechanism contributing its conductance at rest (di/dv).  This equals the steady response to
        a small current step (tests/pool/test_motoneuron_physiology.py); NEURON 9.0's extended impedance
        (``compute(0, 1)``) gives less than half of it for these cells, even with every channel removed."""
        from neuron import h

        h.finitialize(self.params.e_leak_mV)
        imp = h.Impedance()
        imp.loc(0.5, sec=self.soma)
        imp.compute(0, 0)
        return float(imp.input(0.5, sec=self.soma))

    def destroy(self) -> None:
        """Remove the sections from NEURON (idempotent)."""
        for attr in ("dend", "soma"):
            if hasattr(self, attr):
                delattr(self, attr)

    def __enter__(self) -> Motoneuron:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy()
