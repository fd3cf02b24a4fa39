"""Extension "movement_induced_depression": the Ca2+ sensitivity of activation falls on the time course of
eq 19 of Kim et al. 2015, on a movement clock that runs down at rest (mod/ExtMovement.mod, driving KimAct's
C1_shift port).

Equations (ms, mm/s): m = Vm^2/(Vm^2 + v0^2); the clock c (ms) obeys dc/dt = m - (1 - m) c/trec from c = 0;
D = (tanh((c - t50)/width) - tanh(-t50/width)) / (1 - tanh(-t50/width)) in [0, 1); eq 8's half-activation point
C1 -> C1 + k D.  Moving well above v0, c counts time spent moving as the paper's clock counts time since the onset
(slower movements run it slower, towards a ceiling (Vm/v0)^2 trec); held still, it decays with trec and the
depression recovers.  Neutral: k = 0 (shift exactly 0, bit-identical to the baseline); isometric trials: c = 0,
shift exactly 0, whatever the values.
Bounds: k in [0, 0.5] (normalised [CaSPT]: CT09's C1 0.128 and C2 0.093; 0.5 leaves a twitch almost nothing),
default 0.05; t50 in [0, 5000] ms and width in [1, 5000] ms (eq 19's alpha2 and alpha3: bounds and CT09's 400 ms
and 160 ms as defaults); trec in [20, 1e5] ms, default 1000 ms (force depressed by a movement recovers at rest
within a fraction of a second to seconds; 1e5 ms hardly runs down within a trial); v0 in [0.5, 50] mm/s, default
5 mm/s (from slow stretches of a few mm/s to the fastest of the cat hindlimb's working range, as the lengthening
extension's v0).

Why not the paper's eq 19 itself (KimAct's ``movdep``: clock = time since the movement onset, A = Atil^alpha(t);
still the baseline's own switch for ``kim_excitation(movement_compensation=True)``): its depression never recovers,
so it cannot follow a preparation whose force recovers in the holds after a movement.  Why the sensitivity and not
the exponent: docs/reference/extensions.md.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..component import Param, Port, State
from ..kim import KimActivation
from . import ACTIVATION_PARAMETERS, MOVEMENT_PARAMETERS, Extension, Telling

if TYPE_CHECKING:
    from .twin import Observables, StateModulation

_SRC = ("movement-induced depression: force depressed by a movement recovers at rest within a fraction of a second "
        "to seconds (cat soleus, human triceps surae); the time course of eq 19 of Kim et al. 2015 "
        "(CT09 alpha2 400 ms, alpha3 160 ms), applied by its authors only while the length changed")


def _eq19(name: str, as_name: str) -> Param:
    """KimAct's eq 19 parameter ``name`` as this extension's ``as_name`` (same unit, bounds, default, source)."""
    return replace(KimActivation.param(name), name=as_name)


def clock_rates(vm_mm_s: float, trec_ms: float, v0_mm_s: float) -> tuple[float, float]:
    """(m, q) of dc/dt = m - q c at velocity Vm (mm/s): m = Vm^2/(Vm^2 + v0^2) (1), q = (1 - m)/trec (1/ms)."""
    v2, r2 = vm_mm_s * vm_mm_s, v0_mm_s * v0_mm_s
    return v2 / (v2 + r2), r2 / (v2 + r2) / trec_ms


def depression(clock_ms: float, t50_ms: float, width_ms: float) -> float:
    """D (1) on the clock c (ms): eq 19's tanh rise, 0 at c = 0 and -> 1."""
    h0 = math.tanh(-t50_ms / width_ms)
    return (math.tanh((clock_ms - t50_ms) / width_ms) - h0) / (1.0 - h0)


class MovementInducedDepression(Extension):
    """Force sinks progressively during movement: eq 8's half-activation point rises by k D(c), c a clock of time
    spent moving (m = Vm^2/(Vm^2 + v0^2) ms/ms) that runs down at rest with trec."""

    shows = "force sinks progressively during movement at low rates"
    telling = Telling("stimulated trials with movement at <= 20 Hz", moving=True, max_rate_hz=20.0)
    variable = "time_since_movement_onset"
    moves = True
    interacts = MOVEMENT_PARAMETERS + ACTIVATION_PARAMETERS
    name = "movement_induced_depression"
    suffix = "ExtMovement"
    namespace = "movement_induced_depression"
    parameters = (
        Param("k", "1", 0.05, 0.0, 0.5, "rise of eq 8's half-activation point C1 at full depression", _SRC,
              neutral=0.0),
        _eq19("alpha2", "t50"),
        _eq19("alpha3", "width"),
        Param("trec", "ms", 1000.0, 20.0, 1e5, "time constant of the movement clock's run-down at rest", _SRC),
        Param("v0", "mm/s", 5.0, 0.5, 50.0, "speed at which the movement clock runs at half rate", _SRC),
    )
    reads = (Port("vm", "mm/s", "length.vm"),)
    exposes = {"shift": "1", "D": "1", "m": "1"}
    states = (State("c", "ms", 1e-3),)
    targets = {"act.C1_shift": "shift"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> StateModulation:
        """The same equations for the SciPy reference: the clock integrated with Modules 1-3, driving C1_shift."""
        from .twin import StateModulation

        k, t50, width, trec, v0 = (float(values[n]) for n in ("k", "t50", "width", "trec", "v0"))

        def rhs(t: float, y: np.ndarray, obs: Observables) -> list[float]:
            m, q = clock_rates(obs.vm_mm_s, trec, v0)
            return [m - q * float(y[0])]

        return StateModulation((0.0,), rhs, {"C1_shift": lambda t, y, obs: k * depression(float(y[0]), t50, width)})
