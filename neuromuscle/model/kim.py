"""The three modules of Kim, Sandercock & Heckman 2015 as components (mod/kim_m*.mod).

Units: ms, M, mm, N; velocities mm/s.  Defaults are Table 1's CT09 set.  The physiological range of each
parameter ("bounds") is what a fit may explore and what a parameter file may hold: rate constants, pool sizes and
release/uptake capacities a decade either side of Table 1 (the spread between fast and slow mammalian fibres in
the sources the paper draws on, Westerblad & Allen 1994 and Baylor & Hollingworth 2003, is within it); curve
shapes within the ranges over which the paper's equations stay monotone and well posed.
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..errors import InputError
from .component import Component, Param, Port, State

_T1 = "a decade either side of Table 1 of Kim et al. 2015 (CT09/CT95)"
_SHAPE = "Kim et al. 2015 eq 8: keeps the activation curve and its time-constant bell well posed"
_EQ18 = "Kim et al. 2015 eq 18: lines through phi(Xm) between 0 and 3 over the muscle's working range"
_EQ19 = "Kim et al. 2015 eqs 19-20 (CT09/CT95 values and the authors' code)"
_M3 = "Kim et al. 2015 eqs 9-12: cat soleus and medial gastrocnemius motor units to whole muscles"


def _rate(name: str, unit: str, default: float, doc: str) -> Param:
    return Param(name, unit, default, default / 10.0, default * 10.0, doc, _T1, lower_inclusive=True)


class KimCalcium(Component):
    """Module 1 (KimCa): spikes -> Ca2+ in the SR and sarcoplasm, eqs 1-7 and 18.  Receives spikes (NetCon weight
    w: both release kernels jump by w).  Holds the parameters Module 2 shares (T0, phi1, phi2, xopt)."""

    suffix = "KimCa"
    namespace = "kim_m1"
    module = 1
    receives_spikes = True
    parameters = (
        _rate("K1", "1/(M*ms)", 3000.0, "CaSR-calsequestrin binding rate"),
        _rate("K2", "1/ms", 3.0, "calsequestrin unbinding rate"),
        _rate("K3", "1/(M*ms)", 400.0, "CaSP-buffer binding rate"),
        _rate("K4", "1/ms", 1.0, "buffer unbinding rate"),
        _rate("K5i", "1/(M*ms)", 4e5, "CaSP-troponin binding rate"),
        _rate("K6i", "1/ms", 150.0, "troponin unbinding rate at rest"),
        _rate("K", "1/M", 850.0, "pump site binding constant"),
        _rate("Rmax", "1/ms", 10.0, "maximum SR permeability"),
        _rate("Umax", "M/ms", 2000.0, "maximal pump rate"),
        Param("tau1", "ms", 3.0, 0.3, 30.0, "release rise time constant", _T1),
        Param("tau2", "ms", 25.0, 2.5, 250.0, "release decay time constant", _T1),
        _rate("CS0", "M", 0.03, "total calsequestrin"),
        _rate("B0", "M", 0.00043, "total sarcoplasmic buffer"),
        _rate("T0", "M", 7e-5, "total troponin"),
        Param("CaSR0", "M", 0.0025, 0.0, 0.025, "initial free SR calcium", _T1),
        Param("phi1", "1/mm", 0.03, -0.5, 0.5, "eq 18 slope at or below the optimum", _EQ18),
        Param("phi2", "1", 1.23, -10.0, 10.0, "eq 18 intercept at or below the optimum", _EQ18),
        Param("phi3", "1/mm", 0.01, -0.5, 0.5, "eq 18 slope above the optimum", _EQ18),
        Param("phi4", "1", 1.08, -10.0, 10.0, "eq 18 intercept above the optimum", _EQ18),
    )
    reads = (
        Port("atil", "1", "act.atil"),
        Port("xm", "mm", "length.xm"),
        Port("release_gain", "1", None, "unity"),
        Port("uptake_gain", "1", None, "unity"),
    )
    exposes = {"CaSR": "M", "CaSRCS": "M", "CaSP": "M", "CaSPB": "M", "CaSPT": "M", "R": "M/ms", "U": "M/ms",
               "phi": "1", "nspike": "1", "T0": "M", "phi1": "1/mm", "phi2": "1", "xopt": "mm"}
    states = (State("CaSR", "M", 1e-9), State("CaSRCS", "M", 1e-8), State("CaSP", "M", 1e-11),
              State("CaSPB", "M", 1e-10), State("CaSPT", "M", 1e-11), State("S2", "1", 1e-6),
              State("S12", "1", 1e-6))

    def __init__(self, length_compensation: bool = True, **overrides: float) -> None:
        super().__init__(**overrides)
        self.length_compensation = bool(length_compensation)

    def switches(self) -> dict[str, bool]:
        return {"length_compensation": self.length_compensation}

    def configure(self, params: Mapping[str, float] | None) -> None:
        # eq 18's optimum is Module 3's optimal length g1 (one fact, held by KimForce's parameter)
        self.obj.xopt = float(params["kim_m3.g1"]) if params is not None and "kim_m3.g1" in params \
            else KimForce.param("g1").default
        self.obj.lencomp = 1.0 if self.length_compensation else 0.0


class MovementSwitches:
    """Eqs 19 and 20 of Module 2 behind their own switches, for the components that hold Module 2 (KimAct and the
    fused KimUnit): ``movement_depression`` (eq 19) and ``lengthening_divisor`` (eq 20); the paper's movement
    compensation is both."""

    movement_depression: bool
    lengthening_divisor: bool
    obj: Any

    @property
    def movement_compensation(self) -> bool:
        """The paper's movement compensation: eqs 19 and 20 both on."""
        return self.movement_depression and self.lengthening_divisor

    @property
    def uses_movement_clock(self) -> bool:
        """True when eq 19 or eq 20 is on: A changes at the movement onset (a CVODE event there)."""
        return self.movement_depression or self.lengthening_divisor

    def movement_switches(self) -> dict[str, bool]:
        """The two switches and the paper's compensation, as the component's ``switches`` reports them."""
        return {"movement_compensation": self.movement_compensation, "eq19_movement_depression":
                self.movement_depression, "eq20_lengthening_divisor": self.lengthening_divisor}

    def configure_movement(self) -> None:
        """Set the mechanism's eq 19 and eq 20 flags from the switches."""
        self.obj.movdep = 1.0 if self.movement_depression else 0.0
        self.obj.lengdiv = 1.0 if self.lengthening_divisor else 0.0

    def set_movement_onset(self, onset_ms: float | None) -> None:
        """Start eq 19's movement clock at onset_ms (ms); None: the muscle never moves."""
        if onset_ms is not None:
            self.obj.onset = float(onset_ms)


class KimActivation(MovementSwitches, Component):
    """Module 2 (KimAct): troponin-bound Ca2+ -> activation A, eq 8, and the movement compensations eqs 19-20,
    each behind its own switch (``movement_depression``: eq 19; ``lengthening_divisor``: eq 20; the paper's
    movement compensation is both).  Reads T0, phi1, phi2 and xopt from KimCa."""

    suffix = "KimAct"
    namespace = "kim_m2"
    module = 2
    parameters = (
        Param("C1", "1", 0.128, -0.5, 1.0, "normalised [CaSPT] at half activation", _SHAPE),
        Param("C2", "1", 0.093, 0.005, 1.0, "slope of the activation curve", _SHAPE),
        Param("C3", "ms", 61.206, 2.0, 1000.0, "time-constant scale", _SHAPE),
        Param("C4", "1", -13.116, -100.0, 100.0, "normalised [CaSPT] of the largest time constant", _SHAPE),
        Param("C5", "1", 5.095, 0.1, 100.0, "width of the time-constant bell", _SHAPE),
        Param("alpha", "1", 2.0, 1.0, 8.0, "exponent A = Atil^alpha", _SHAPE),
        Param("alpha1", "1", 4.77, 0.0, 20.0, "eq 19 amplitude", _EQ19),
        Param("alpha2", "ms", 400.0, 0.0, 5000.0, "eq 19 midpoint after movement onset", _EQ19),
        Param("alpha3", "ms", 160.0, 1.0, 5000.0, "eq 19 width", _EQ19),
        Param("beta", "1", 0.47, 0.0, 10.0, "eq 20 length divisor", _EQ19),
        Param("gamma", "s/mm", 0.001, 0.0, 0.1, "eq 20 velocity divisor", _EQ19),
    )
    reads = (
        Port("caspt", "M", "ca.CaSPT"),
        Port("T0", "M", "ca.T0"),
        Port("phi1", "1/mm", "ca.phi1"),
        Port("phi2", "1", "ca.phi2"),
        Port("xopt", "mm", "ca.xopt"),
        Port("xm", "mm", "length.xm"),
        Port("vm", "mm/s", "length.vm"),
        Port("tauA_gain", "1", None, "unity"),
        Port("C1_shift", "1", None, "zero"),
    )
    exposes = {"A": "1", "Ainf": "1", "tauA": "ms", "alpha_t": "1", "asw": "1", "ssw": "1"}
    states = (State("atil", "1", 1e-5),)

    def __init__(self, movement_compensation: bool = False, **overrides: float) -> None:
        super().__init__(**overrides)
        self.movement_depression = bool(movement_compensation)  # eq 19
        self.lengthening_divisor = bool(movement_compensation)  # eq 20

    def switches(self) -> dict[str, bool]:
        return self.movement_switches()

    def configure(self, params: Mapping[str, float] | None) -> None:
        self.configure_movement()


class KimForce(Component):
    """Module 3 (KimForce): activation -> force, a Hill/Mashima CE in series with a linear SE, eqs 9-12.  Output
    F (N) = SE force + the force_offset port; the capacity_gain port multiplies the CE's capacity Fc (1)."""

    suffix = "KimForce"
    namespace = "kim_m3"
    module = 3
    output = "F"
    parameters = (
        Param("P0", "N", 23.0, 0.01, 500.0, "maximal isometric force at the optimum", _M3),
        Param("KSE", "1/mm", 0.4, 0.02, 10.0, "series-elastic stiffness normalised by P0", _M3),
        Param("g1", "mm", -8.0, -40.0, 10.0, "optimal length", _M3),
        Param("g2", "mm", 21.4, 2.0, 200.0, "width of the force-length Gaussian", _M3),
        Param("a0", "N", 2.35, 1e-3, 500.0, "Hill coefficient", _M3),
        Param("b0", "mm/s", 24.35, 0.5, 1000.0, "Hill coefficient", _M3),
        Param("c0", "N", -7.4, -500.0, 0.0, "Mashima coefficient (> -P0: the asymptote lies above Fc)", _M3),
        Param("d0", "mm/s", 30.3, 0.5, 1000.0, "Mashima coefficient", _M3),
    )
    reads = (
        Port("act", "1", "act.A"),
        Port("xm", "mm", "length.xm"),
        Port("force_offset", "N", None, "zero"),
        Port("capacity_gain", "1", None, "unity"),
        Port("asw", "1", "act.asw", "zero", optional=True, enables="use_split"),
        Port("ssw", "1", "act.ssw", "zero", optional=True, enables="use_split"),
    )
    exposes = {"F": "N", "Fse": "N", "Fc": "N", "vce": "mm/s", "nasym": "1", "P0": "N", "KSE": "1/mm", "xce": "mm",
               "x0": "mm", "nsub": "1", "nsplit": "1"}
    states = (State("dxce", "mm", 1e-6),)

    def input_warnings(self, trace: Any, params: Mapping[str, float] | None) -> list[str]:
        """A length where eq 12 leaves less than 0.1 % of P0 (the muscle makes almost no force there)."""
        v = self.values(params)
        lo, hi = float(np.min(trace.xm_mm)), float(np.max(trace.xm_mm))
        worst = lo if abs(lo - v["g1"]) > abs(hi - v["g1"]) else hi
        g = float(np.exp(-((worst - v["g1"]) / v["g2"]) ** 2))
        if g >= 1e-3:
            return []
        return [f"length {worst:g} mm leaves a force-length factor g(Xm) = {g:.2g} (optimum g1 = {v['g1']:g} mm, "
                f"width g2 = {v['g2']:g} mm): the muscle makes almost no force there; lengths are in mm relative "
                "to the physiological maximum (0 mm)"]

    def run_warnings(self) -> list[str]:
        """Information only: how many fixed steps ended on the eccentric saturation (beyond 95 % of eq 11's
        asymptote), where the CE yields; reported in the result's settings, not as a warning."""
        return []

    def asymptote_steps(self) -> int:
        """Fixed steps that ended beyond 95 % of the Mashima asymptote (the CE was yielding)."""
        return int(self.obj.nasym)

    def values(self, params: Mapping[str, float] | None) -> dict[str, float]:
        v = super().values(params)
        if not v["c0"] > -v["P0"]:
            raise InputError(f"KimForce: c0 = {v['c0']:g} N must exceed -P0 = {-v['P0']:g} N (eq 11's asymptote "
                             "(2 + c0/P0) Fc must lie above Fc); give a larger c0")
        return v


def kim_excitation(length_compensation: bool = True, movement_compensation: bool = False,
                   ca: Mapping[str, float] | None = None, act: Mapping[str, float] | None = None,
                   ) -> dict[str, Component]:
    """Modules 1-2 as slots {"ca": KimCalcium, "act": KimActivation}: eq 18 and eqs 19-20 switched by name,
    parameter overrides per module (e.g. ``act={"C3": 50.0}``)."""
    return {"ca": KimCalcium(length_compensation, **dict(ca or {})),
            "act": KimActivation(movement_compensation, **dict(act or {}))}


def kim_contraction(**overrides: float) -> dict[str, Component]:
    """Module 3 as slot {"force": KimForce}."""
    return {"force": KimForce(**overrides)}


COMPONENTS: tuple[type[Component], ...] = (KimCalcium, KimActivation, KimForce)


