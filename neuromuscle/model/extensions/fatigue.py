"""Extension "fatigue": a slow depletion state that scales Ca2+ release (mod/ext_fatigue.mod).

Equations (ms, per spike): dD/dt = -D/tau_rec; at each spike D -> D + k (1 - D); KimCa's release is multiplied by
gain = 1 - D.  Neutral: k = 0.  Bounds: k in [0, 0.2] per spike (0.2 halves release within 3 spikes, beyond any
fatigue the seeds discuss); tau_rec 100 ms to 10 min (post-tetanic recovery times of mammalian fibres).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension

_SRC = "fatigue bounds: per-spike depletion up to 0.2; recovery 0.1 s to 10 min (mammalian fibres)"


class Fatigue(Extension):
    """Force declines over long high-rate trains: release scaled by 1 - D, D a slow per-spike depletion."""

    name = "fatigue"
    suffix = "ExtFatigue"
    namespace = "fatigue"
    receives_spikes = True
    parameters = (
        Param("k", "1", 0.01, 0.0, 0.2, "depletion per spike", _SRC, neutral=0.0),
        Param("tau_rec", "ms", 10_000.0, 100.0, 600_000.0, "recovery time constant", _SRC),
    )
    exposes = {"gain": "1"}
    states = (State("D", "1", 1e-6),)
    targets = {"ca.release_gain": "gain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations solved in closed form for the SciPy reference: {"release_gain": gain(t_ms)}."""
        k, tau = float(values["k"]), float(values["tau_rec"])
        spikes = np.asarray(spikes_ms, dtype=float)
        after = np.empty(spikes.size)  # D just after each spike
        d, last = 0.0, 0.0
        for i, ts in enumerate(spikes):
            d *= np.exp(-(ts - last) / tau)
            d += k * (1.0 - d)
            after[i], last = d, ts

        def gain(t: float) -> float:
            i = int(np.searchsorted(spikes, t, side="right")) - 1
            return 1.0 if i < 0 else 1.0 - after[i] * float(np.exp(-(t - spikes[i]) / tau))

        return {"release_gain": gain}
