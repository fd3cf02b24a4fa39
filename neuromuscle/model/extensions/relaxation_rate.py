"""Extension "relaxation_rate": constant factors on Ca2+ re-uptake and on tau_A (mod/ext_relaxation.mod).

Equations: the SR pump U (eq 4) is multiplied by ``uptake`` (KimCa's uptake_gain port) and Module 2's time
constant tau_A (eq 8) by ``tauA`` (KimAct's tauA_gain port).  tauA > 1 slows the rise and the decay of activation
(CT09 twitch, tauA = 2: peak 0.34x, half-relaxation 41 -> 81 ms); uptake sets the size of the Ca2+ transient more
than its decay (uptake = 2: a smaller, earlier twitch, peak 0.41x, half-relaxation 41 -> 51 ms; uptake < 1 a
larger, later one), so the two together move the twitch's size and its relaxation apart.
Neutral (and default): uptake = tauA = 1.  Bounds: both in [0.3, 3] (SERCA content and pump rate differ ~3x
between fast and slow fibres, and relaxation times ~3x between motor-unit types and over 10 degC).
No state, no spikes.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param
from . import Extension

_SRC = ("relaxation bounds: factor 0.3-3 (SERCA pump rate and relaxation times differ ~3x between fast and slow "
        "fibres and over 10 degC, Q10 ~ 2-3)")


class RelaxationRate(Extension):
    """The model relaxes slower or faster than the data: re-uptake times ``uptake``, tau_A times ``tauA``."""

    name = "relaxation_rate"
    suffix = "ExtRelaxation"
    namespace = "relaxation_rate"
    parameters = (
        Param("uptake", "1", 1.0, 0.3, 3.0, "factor on the SR pump (eq 4)", _SRC, neutral=1.0),
        Param("tauA", "1", 1.0, 0.3, 3.0, "factor on tau_A (eq 8)", _SRC, neutral=1.0),
    )
    exposes = {"uptake": "1", "tauA": "1"}
    targets = {"ca.uptake_gain": "uptake", "act.tauA_gain": "tauA"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations for the SciPy reference: {"uptake_gain", "tauA_gain"} as constant functions of t."""
        uptake, tau_a = float(values["uptake"]), float(values["tauA"])
        return {"uptake_gain": lambda t: uptake, "tauA_gain": lambda t: tau_a}
