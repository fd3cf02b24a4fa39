"""Extension "staircase": a slow state, built by low-rate spikes, that scales Ca2+ release, up or down
(mod/ExtStaircase.mod).

Equations (ms, per spike): dS/dt = -S/tau, dF/dt = -F/tau_f; at each spike S -> S + u (1 - F)^3 (1 - S) with F as
the previous spikes left it, then F -> 1; KimCa's release is multiplied by gain = 1 + k S, so k > 0 is a positive
staircase (twitches grow over successive stimuli) and k < 0 a negative one.  After one spike F = exp(-ISI/tau_f):
a spike after a long interval builds S by u, one that closely follows its predecessor (a tetanus) next to nothing,
the counterpart of post_activation_potentiation's u F.  Neutral: k = 0.  Bounds: k in [-0.6, 1] (release at most
-60 % or doubled at full build-up: twitch changes of about -40 % in slow muscle to +100 % in fast rodent muscle at
2-10 Hz); u in [0.005, 0.5] per spike (the staircase saturates within 2-200 stimuli; measured ones within 10-50);
tau 0.5 s to 2 min (from the decay of a Ca2+-handling change between twitches at >= 2 Hz to myosin light-chain
dephosphorylation); tau_f 40-200 ms.  The build per spike after an interval ISI is (1 - exp(-ISI/tau_f))^3 of u:

| ISI (rate)       | tau_f = 40 ms | 60 ms (default) | 200 ms |
|------------------|---------------|-----------------|--------|
| 10 ms (100 Hz)   | 0.011         | 0.0036          | 0.0001 |
| 20 ms (50 Hz)    | 0.06          | 0.02            | 0.0009 |
| 50 ms (20 Hz)    | 0.36          | 0.18            | 0.01   |
| 100 ms (10 Hz)   | 0.77          | 0.53            | 0.06   |
| 500 ms (2 Hz)    | 1.00          | 1.00            | 0.77   |

Why the cube and the 40 ms bound: a build that ignored the interval would also raise the release of the unfused
20-40 Hz trains, where force follows release closely; a shallow gate (u (1 - F), tau_f down to 2 ms) would let a fit
make the staircase a potentiation built by tetani that recovers within a second, which is what a removal slowed by
recent activity does to twitches after a tetanus, so the staircase would take relaxation_rate's cases.  The cube
keeps a low-rate interval's full build and makes a tetanus's negligible, which is what the catalogue's definition
asks (a tetanus's potentiation is post_activation_potentiation's).
"""

from __future__ import annotations

from typing import Callable, Mapping

import numpy as np

from ..component import Param, State
from . import Extension, Telling
from .spike_trace import SpikeTrace

_SRC = ("staircase bounds: twitch change -40 % (slow muscle) to +100 % (fast rodent muscle) over 10-50 stimuli "
        "at 2-10 Hz, decaying in 0.5 s (Ca2+ handling) to 2 min (myosin light-chain dephosphorylation); "
        "Krarup 1981, MacIntosh & Willis 2000")

_SRC_F = ("staircase interval scale: measured staircases are low-rate (0.5-10 Hz, intervals >= 100 ms) effects; "
          "the build per spike is (1 - exp(-ISI/tau_f))^3: at 40 ms a 100 Hz interval builds 1 % and a 10 Hz one "
          "77 % of a lone spike's, at 200 ms a 2 Hz one 77 % (potentiation by tetani is "
          "post_activation_potentiation's)")


class Staircase(Extension):
    """Twitch amplitude changes over successive stimuli at low rates: release scaled by 1 + k S, S a slow
    build-up by spikes after long intervals."""

    shows = "twitch amplitude changes over successive stimuli at low rates"
    telling = Telling("isometric trains of >= 5 stimuli at <= 15 Hz", moving=False, min_stimuli=5, max_rate_hz=15.0)
    variable = "position_in_train"
    name = "staircase"
    suffix = "ExtStaircase"
    namespace = "staircase"
    receives_spikes = True
    parameters = (
        Param("k", "1", 0.3, -0.6, 1.0, "release change at full build-up (sign: positive or negative staircase)",
              _SRC, neutral=0.0),
        Param("u", "1", 0.05, 0.005, 0.5, "build-up per spike", _SRC),
        Param("tau", "ms", 5000.0, 500.0, 120_000.0, "decay time constant", _SRC),
        Param("tau_f", "ms", 60.0, 40.0, 200.0, "interval scale below which a spike builds little", _SRC_F),
    )
    exposes = {"gain": "1"}
    states = (State("S", "1", 1e-6), State("F", "1", 1e-6))
    targets = {"ca.release_gain": "gain"}

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> dict[str, Callable]:
        """The same equations solved in closed form for the SciPy reference: {"release_gain": gain(t_ms)}."""
        k = float(values["k"])
        recent = SpikeTrace(spikes_ms, 1.0, float(values["tau_f"]))
        build = SpikeTrace(spikes_ms, float(values["u"]) * (1.0 - recent.before) ** 3, float(values["tau"]))
        return {"release_gain": lambda t: 1.0 + k * build(t)}
