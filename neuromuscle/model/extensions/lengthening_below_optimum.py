"""Extension "lengthening_below_optimum": Ca2+ release falls while the muscle lengthens at or below its optimum
(mod/ExtLengthening.mod).

Equations (Xm mm, Vm mm/s positive = lengthening, t ms): target = k (1 - exp(-Vm/v0)) while Xm <= X_opt (= g1)
and Vm > 0, else 0; dE/dt = (target - E)/tau_on with tau_on = 5 ms (fixed); KimCa's release (eq 3) is multiplied
by gain = 1 - E.  Neutral: k = 0 (gain exactly 1).  Bounds: k in [0, 0.9] (a lengthening contraction at low rates
produces up to ~2x less force than the model's; eq 20 of Kim et al. 2015 at CT09 divides A by ~1.6 at the optimum and
100 mm/s; its authors found the error largest at <= 20 Hz); v0 in [1, 200] mm/s (half the effect at 0.7 v0: from
slow stretches of a few mm/s to the fastest of the cat hindlimb).

Why not the paper's eq 20 (A divided by (1 + beta phi(Xm)) (1 + gamma Vm)), the baseline's own switch
(``kim_excitation(movement_compensation=True)``): as a cause it loses on held-out trials (on the diagnosis suite's
lengthening cases its held-out gain was negative).  A divisor on A acts equally at every rate and grows without
bound with velocity; the paper's own discussion places the error at low rates, which a change of Ca2+ (Module 1, where
eq 18 acts) gives and a change of A does not.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..component import Param, Port, State
from . import MOVEMENT_PARAMETERS, Extension, Telling

if TYPE_CHECKING:
    from .twin import Observables, StateModulation

_SRC = ("lengthening below the optimum: low-rate force during lengthening up to ~2x below the model's (Kim et al. "
        "2015, eq 20 and discussion: the error is largest at <= 20 Hz below the optimum); velocities from a few mm/s "
        "to ~200 mm/s in the cat hindlimb")

#: The time (ms) the release loss takes to follow the gate (fixed, not fitted: mod/ExtLengthening.mod).
TAU_ON_MS = 5.0


class LengtheningBelowOptimum(Extension):
    """Excess model force while lengthening below the optimum: release times 1 - E, E following
    k (1 - exp(-Vm/v0)) while Xm <= X_opt and Vm > 0."""

    shows = "excess model force while lengthening below the optimum"
    telling = Telling("stimulated lengthening below the optimum", lengthening_below_optimum=True)
    variable = "velocity"
    moves = True
    interacts = MOVEMENT_PARAMETERS
    name = "lengthening_below_optimum"
    suffix = "ExtLengthening"
    namespace = "lengthening_below_optimum"
    parameters = (
        Param("k", "1", 0.3, 0.0, 0.9, "release loss at high lengthening velocity", _SRC, neutral=0.0),
        Param("v0", "mm/s", 10.0, 1.0, 200.0, "velocity scale of the release loss", _SRC),
    )
    reads = (
        Port("xm", "mm", "length.xm"),
        Port("vm", "mm/s", "length.vm"),
        Port("xopt", "mm", "ca.xopt"),
    )
    exposes = {"gain": "1", "target": "1"}
    states = (State("E", "1", 1e-6),)
    targets = {"ca.release_gain": "gain"}

    def configure(self, params: Mapping[str, float] | None) -> None:
        self.obj.tau_on = TAU_ON_MS

    @staticmethod
    def reference_modulation(values: Mapping[str, float], spikes_ms: np.ndarray) -> StateModulation:
        """The same equations for the SciPy reference: E integrated with Modules 1-3, driving release_gain."""
        from .twin import StateModulation

        k, v0 = float(values["k"]), float(values["v0"])

        def rhs(t: float, y: np.ndarray, obs: Observables) -> list[float]:
            on = obs.xm_mm <= obs.params["g1"] and obs.vm_mm_s > 0.0
            target = k * (1.0 - math.exp(-obs.vm_mm_s / v0)) if on else 0.0
            return [(target - y[0]) / TAU_ON_MS]

        return StateModulation((0.0,), rhs, {"release_gain": lambda t, y, obs: 1.0 - float(y[0])})
