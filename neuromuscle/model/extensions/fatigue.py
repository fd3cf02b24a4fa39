"""Extension "fatigue": a slow depletion state that scales Ca2+ release and the force capacity (mod/ExtFatigue.mod).

Equations (ms, per spike): dD/dt = -D/tau_rec; at each spike D -> D + k (1 - D); KimCa's release is multiplied by
gain = 1 - D and KimForce's capacity Fc = P0 g(Xm) A by cgain = 1 - kc D.  Fatigue lowers both the Ca2+ a spike
releases and the force the cross-bridges make at a given activation (Allen, Lamb & Westerblad 2008); at rates that
saturate activation only the second lowers force, so a release loss alone cannot make a tetanus decline.
Neutral: k = 0 (or kc = 0 for the capacity alone).  Bounds: k in [0, 0.2] per spike (0.2 halves release within 3
spikes, beyond any fatigue the seeds discuss); tau_rec 100 ms to 10 min (post-tetanic recovery times of mammalian
fibres); kc in [0, 1] (at 1 the capacity falls as release does).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import ACTIVATION_PARAMETERS, Extension, Telling
from .spike_trace import SpikeTrace

_SRC = "fatigue bounds: per-spike depletion up to 0.2; recovery 0.1 s to 10 min (mammalian fibres)"
_CAP = "fatigue lowers the force per cross-bridge as well as release (Allen, Lamb & Westerblad 2008)"


class Fatigue(Extension):
    """Force declines over long high-rate trains: release scaled by 1 - D and the force capacity by 1 - kc D, D a
    slow per-spike depletion."""

    shows = "force declines over long high-rate trains"
    telling = Telling("isometric trains of >= 1 s at >= 30 Hz", moving=False, min_train_s=1.0, min_rate_hz=30.0)
    variable = "recent_activity"
    interacts = ACTIVATION_PARAMETERS + ("P0",)
    name = "fatigue"
    suffix = "ExtFatigue"
    namespace = "fatigue"
    receives_spikes = True
    parameters = (
        Param("k", "1", 0.01, 0.0, 0.2, "depletion per spike", _SRC, neutral=0.0),
        Param("tau_rec", "ms", 10_000.0, 100.0, 600_000.0, "recovery time constant", _SRC),
        Param("kc", "1", 0.5, 0.0, 1.0, "loss of force capacity per unit depletion", _CAP, neutral=0.0),
    )
    exposes = {"gain": "1", "cgain": "1"}
    states = (State("D", "1", 1e-6),)
    targets = {"ca.release_gain": "gain", "force.capacity_gain": "cgain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations solved in closed form for the SciPy reference: {"release_gain": gain(t_ms),
        "capacity_gain": cgain(t_ms)}."""
        depletion = SpikeTrace(spikes_ms, float(values["k"]), float(values["tau_rec"]))
        kc = float(values["kc"])
        return {"release_gain": lambda t: 1.0 - depletion(t), "capacity_gain": lambda t: 1.0 - kc * depletion(t)}
