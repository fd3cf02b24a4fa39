"""Extension "relaxation_rate": the SR pump changes its speed over the relaxation after each spike
(mod/ext_relaxation.mod).

Equations (ms, per spike): a state W is reset to 0 by every spike and recovers, dW/dt = (1 - W)/tau; KimCa's pump
U (eq 4) is multiplied by gain = 1 + k W.  k > 0: the pump speeds up late after a spike (the twitch relaxes faster
than the model's once the Ca2+ transient has peaked); k < 0: it slows down late.  In a fused tetanus W stays near 0.
Neutral: k = 0.  Bounds: k in [-0.7, 3] (late pump rate 0.3x to 4x: SERCA rates differ ~3x between fibre types and
over 10 degC); tau 5-500 ms (relaxation's slow, linear phase lasts tens of ms in mammalian fast muscle and
hundreds in slow, before the fast, exponential phase).

Until stop 21 this extension was two constant factors, on the pump and on tau_A.  Both were calibration, not a
cause: a constant factor on tau_A is Module 2's C3, refitted by the reference and by every candidate's fit, and a
constant factor on the pump is Module 1's Umax, which synth moves by ~20 % in every preparation (suite seed 1's
null was named relaxation_rate for 142 noise variances of such misfit).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension
from .spike_trace import SpikeTrace

_SRC = ("relaxation bounds: SERCA pump rate ~3x between fast and slow fibres and over 10 degC (Q10 ~ 2-3); "
        "relaxation's slow linear phase lasts tens (fast) to hundreds (slow muscle) of ms before the fast "
        "exponential phase")


class RelaxationRate(Extension):
    """The model relaxes slower or faster than the data: the SR pump times 1 + k W, W recovering to 1 with tau
    after each spike."""

    name = "relaxation_rate"
    suffix = "ExtRelaxation"
    namespace = "relaxation_rate"
    receives_spikes = True
    parameters = (
        Param("k", "1", 0.5, -0.7, 3.0, "late change of the SR pump's rate (eq 4)", _SRC, neutral=0.0),
        Param("tau", "ms", 50.0, 5.0, 500.0, "time constant of the pump's change after a spike", _SRC),
    )
    exposes = {"gain": "1"}
    states = (State("W", "1", 1e-6),)
    targets = {"ca.uptake_gain": "gain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations in closed form for the SciPy reference: {"uptake_gain": gain(t_ms)}, 1 - W being a
        per-spike trace that every spike sets to 1."""
        k = float(values["k"])
        since = SpikeTrace(spikes_ms, 1.0, float(values["tau"]))  # 0 before the first spike: W = 1 at rest
        return {"uptake_gain": lambda t: 1.0 + k * (1.0 - since(t))}
