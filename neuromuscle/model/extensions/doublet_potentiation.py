"""Extension "doublet_potentiation": short-interval facilitation of Ca2+ release (mod/ExtDoublet.mod).

Equations (ms, per spike): dF/dt = -F/tau_f, dH/dt = -H/tau_h; at each spike first H -> H + F (1 - H) (F as the
previous spikes left it), then F -> F + (1 - F); KimCa's release is multiplied by gain = 1 + k H.  A single
twitch is exactly unchanged (F = 0), low-rate trains nearly (F ~ 0 after a long interval); after an interval ISI
the facilitation is about k exp(-ISI/tau_f).  Neutral: k = 0.  Bounds: k in [0, 4] (release amplified at most 5x
while H lasts: CT09 at 8 ms, tau_f 10 ms, k 4: doublet peak +22 % with tau_h 25 ms, +50 % with 300 ms, against
doublet gains of tens of percent in slow units); tau_f 2-30 ms (the extra force fades over inter-spike intervals of
5-25 ms); tau_h 5-500 ms (from one spike's release, tau2 = 25 ms in CT09, to the catch-like enhancement that an
initial doublet leaves over the following few hundred ms of a train).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension, Telling
from .spike_trace import SpikeTrace

_SRC = ("doublet bounds: catch-like extra force after 5-15 ms intervals, fading by 25 ms, lasting up to a few "
        "hundred ms of the following train (Burke et al. 1970, Binder-Macleod & Kesar 2005)")


class DoubletPotentiation(Extension):
    """Extra force after short inter-spike intervals: a spike arriving within a few ms of the previous one has
    its release amplified by 1 + k H."""

    shows = "extra force after short inter-spike intervals (5-15 ms)"
    telling = Telling("isometric trains with an interval <= 15 ms among longer ones (doublets, random trains)",
                      moving=False, short_interval_ms=15.0)
    variable = "isi"
    name = "doublet_potentiation"
    suffix = "ExtDoublet"
    namespace = "doublet_potentiation"
    receives_spikes = True
    parameters = (
        Param("k", "1", 1.0, 0.0, 4.0, "release amplification at zero interval", _SRC, neutral=0.0),
        Param("tau_f", "ms", 8.0, 2.0, 30.0, "facilitation decay (interval dependence)", _SRC),
        Param("tau_h", "ms", 25.0, 5.0, 500.0, "duration of the amplified release", _SRC),
    )
    exposes = {"gain": "1"}
    states = (State("F", "1", 1e-4), State("H", "1", 1e-4))
    targets = {"ca.release_gain": "gain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations solved in closed form for the SciPy reference: {"release_gain": gain(t_ms)}."""
        k = float(values["k"])
        facilitation = SpikeTrace(spikes_ms, 1.0, float(values["tau_f"]))
        held = SpikeTrace(spikes_ms, facilitation.before, float(values["tau_h"]))
        return {"release_gain": lambda t: 1.0 + k * held(t)}
