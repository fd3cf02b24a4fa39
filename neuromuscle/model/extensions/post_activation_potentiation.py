"""Extension "post_activation_potentiation": one slow state, raised by high-rate activity, raises release and
slows activation (mod/ExtPAP.mod).

Equations (ms, per spike): dP/dt = -P/tau, dF/dt = -F/tau_f; at each spike P -> P + u F (1 - P) with F as the
previous spikes left it, then F -> 1; KimCa's release is multiplied by gain = 1 + k_rel P and KimAct's tau_A by
tgain = 1 + k_tau P (two ports driven from one state).  After one spike F = exp(-ISI/tau_f): a conditioning
tetanus (short intervals) raises P, a lone twitch or a low-rate train hardly does (potentiation by myosin light
chain phosphorylation needs Ca2+ that stays high), and P outlasts the tetanus by tens of seconds: later twitches
are larger and relax more slowly.  Neutral: k_rel = k_tau = 0.  Bounds: k_rel in [0, 2] (post-tetanic twitch
potentiation up to ~+150 % in fast rodent muscle, ~0 in slow muscle); k_tau in [0, 1.5] (half-relaxation
prolonged by up to ~50 %); u in [0.001, 0.5] per spike at F = 1 (a 1 s tetanus at 100 Hz brings P to 0.1-1);
tau 5 s to 10 min (potentiation decays with a half-time of 0.5-5 min); tau_f 2-100 ms (at 100 ms a 10 Hz train
potentiates at a third of the tetanic rate per spike, at 10 ms not at all).

Why the fast trace F: if every spike raised P by u whatever the interval, the extension would potentiate low-rate
trains as much as tetani, and on potentiation built by short intervals (under ~15 ms) the rate-selective doublet
extension would fit better than this one.

A longer tau_A alone lowers a twitch, so k_rel must outweigh k_tau for the twitch to grow.  CT09 at -8 mm, k_rel
1.2, k_tau 0.5, u 0.05, tau 30 s, tau_f 20 ms, a twitch 550 ms after 20 spikes: at 100 Hz (u F = 0.03 per spike)
peak +25.0 %, half-relaxation +8.2 %, time to peak 81 -> 93 ms; at 10 Hz peak +0.5 %, half-relaxation +0.1 %.
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension, Telling
from .spike_trace import SpikeTrace

_SRC = ("PAP bounds: post-tetanic twitch potentiation up to ~+150 %, half-relaxation up to ~+50 %, decay "
        "half-time 0.5-5 min (fast rodent and cat muscle; MacIntosh 2003, Vandenboom 2004)")


class PostActivationPotentiation(Extension):
    """After activity, twitches grow and relaxation slows: release times 1 + k_rel P, tau_A times 1 + k_tau P,
    P a slow per-spike potentiation."""

    shows = "after activity, twitches grow and relaxation slows"
    telling = Telling("isometric stimuli after a pause that follows a burst of activity", moving=False,
                      burst_after_pause=True)
    variable = "recent_activity"
    name = "post_activation_potentiation"
    suffix = "ExtPAP"
    namespace = "post_activation_potentiation"
    receives_spikes = True
    parameters = (
        Param("k_rel", "1", 0.5, 0.0, 2.0, "release gain at full potentiation", _SRC, neutral=0.0),
        Param("k_tau", "1", 0.3, 0.0, 1.5, "tau_A lengthening at full potentiation", _SRC, neutral=0.0),
        Param("u", "1", 0.05, 0.001, 0.5, "potentiation per spike at a short interval (F = 1)", _SRC),
        Param("tau", "ms", 60_000.0, 5_000.0, 600_000.0, "decay time constant", _SRC),
        Param("tau_f", "ms", 20.0, 2.0, 100.0, "interval scale of the potentiation per spike", _SRC),
    )
    exposes = {"gain": "1", "tgain": "1"}
    states = (State("P", "1", 1e-6), State("F", "1", 1e-6))
    targets = {"ca.release_gain": "gain", "act.tauA_gain": "tgain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations in closed form for the SciPy reference: {"release_gain", "tauA_gain"} (t_ms)."""
        k_rel, k_tau = float(values["k_rel"]), float(values["k_tau"])
        recent = SpikeTrace(spikes_ms, 1.0, float(values["tau_f"]))
        potentiation = SpikeTrace(spikes_ms, float(values["u"]) * recent.before, float(values["tau"]))
        return {"release_gain": lambda t: 1.0 + k_rel * potentiation(t),
                "tauA_gain": lambda t: 1.0 + k_tau * potentiation(t)}
