"""Extension "post_activation_potentiation": one slow state raises release and slows activation (mod/ext_pap.mod).

Equations (ms, per spike): dP/dt = -P/tau; at each spike P -> P + u (1 - P); KimCa's release is multiplied by
gain = 1 + k_rel P and KimAct's tau_A by tgain = 1 + k_tau P (two ports driven from one state).  A conditioning
tetanus (many spikes) raises P most, and P outlasts it by tens of seconds: later twitches are larger and relax
more slowly.  Neutral: k_rel = k_tau = 0.  Bounds: k_rel in [0, 2] (post-tetanic twitch potentiation up to
~+150 % in fast rodent muscle, ~0 in slow muscle); k_tau in [0, 1.5] (half-relaxation prolonged by up to ~50 %);
u in [0.001, 0.2] per spike (a 1 s tetanus at 100 Hz brings P to 0.1-1); tau 5 s to 10 min (potentiation decays
with a half-time of 0.5-5 min).  A longer tau_A alone lowers a twitch, so k_rel must outweigh k_tau for the twitch
to grow (CT09, 20 spikes at 100 Hz then a twitch 550 ms later, k_rel 1.2, k_tau 0.5, u 0.03: peak +26 %,
half-relaxation +9 %).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension
from .spike_trace import SpikeTrace

_SRC = ("PAP bounds: post-tetanic twitch potentiation up to ~+150 %, half-relaxation up to ~+50 %, decay "
        "half-time 0.5-5 min (fast rodent and cat muscle; MacIntosh 2003, Vandenboom 2004)")


class PostActivationPotentiation(Extension):
    """After activity, twitches grow and relaxation slows: release times 1 + k_rel P, tau_A times 1 + k_tau P,
    P a slow per-spike potentiation."""

    name = "post_activation_potentiation"
    suffix = "ExtPAP"
    namespace = "post_activation_potentiation"
    receives_spikes = True
    parameters = (
        Param("k_rel", "1", 0.5, 0.0, 2.0, "release gain at full potentiation", _SRC, neutral=0.0),
        Param("k_tau", "1", 0.3, 0.0, 1.5, "tau_A lengthening at full potentiation", _SRC, neutral=0.0),
        Param("u", "1", 0.01, 0.001, 0.2, "potentiation per spike", _SRC),
        Param("tau", "ms", 60_000.0, 5_000.0, 600_000.0, "decay time constant", _SRC),
    )
    exposes = {"gain": "1", "tgain": "1"}
    states = (State("P", "1", 1e-6),)
    targets = {"ca.release_gain": "gain", "act.tauA_gain": "tgain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations in closed form for the SciPy reference: {"release_gain", "tauA_gain"} (t_ms)."""
        k_rel, k_tau = float(values["k_rel"]), float(values["k_tau"])
        potentiation = SpikeTrace(spikes_ms, float(values["u"]), float(values["tau"]))
        return {"release_gain": lambda t: 1.0 + k_rel * potentiation(t),
                "tauA_gain": lambda t: 1.0 + k_tau * potentiation(t)}
