"""Extensions "force_enhancement_after_stretch" and "force_depression_after_shortening": a history-dependent
element in parallel with Module 3 (mod/ExtForceHistory.mod; one mechanism, sign sgn = +1 / -1).

Equations (t ms, lengths mm, Vm mm/s positive = lengthening, forces N):
    Fse = P0 KSE max(Xm - XCE, 0)                          the series-elastic force of Module 3 (eq 9)
    dD/dt = (Fse/P0) max(sgn Vm, 0)/(1000 L) (1 - D) - D/tau
    force_offset = sgn k D Fse       ->  F = Fse (1 + sgn k D)
D (1) grows with the muscle's active lengthening (FE) or shortening (FD), weighted by the force meanwhile (the
work done on / by the muscle), saturates at 1 and fades with tau.  The extra force follows the force, so it
vanishes with the activation, and F >= 0.  Isometric trials (Vm = 0) are untouched.
Parameters: k (1) in [0, 1], default 0.2, neutral 0 (F = Fse exactly); L (mm) in [0.5, 50], default 5; tau (ms)
in [1000, 100000], default 5000.  Bounds: residual force enhancement after stretch and force depression after
shortening amount to a few to some tens of percent of the isometric force, grow with the stretch or shortening
amplitude (saturating within millimetres to centimetres of a cat hindlimb muscle) and last for seconds of
activation (Abbott & Aubert 1952; Edman et al. 1978, 1982; Herzog & Leonard 1997, 2002).  tau starts at 1 s: a
history that fades within a tenth of a second is not residual, it follows the movement, and so takes up a
preparation's force-velocity misfit on the moving trials (a lower bound of 100 ms lets a preparation without the
effect be named for it).  The cat soleus stretches of Herzog & Leonard 2002 fit tau = 9.5 s, loosely (their holds
last 2-4 s; docs/validation/real-data.md).
The two can be selected together: both drive KimForce's force_offset port, where a PortCombine adds their offsets.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..component import Param, Port, State
from . import LENGTH_PARAMETERS, MOVEMENT_PARAMETERS, Extension, Telling

if TYPE_CHECKING:
    from .twin import Observables, StateModulation

_SRC = ("force enhancement / depression after stretch / shortening: up to some tens of % of the isometric "
        "force, saturating over mm to cm, lasting seconds (Edman et al. 1978, 1982; Herzog & Leonard 1997, 2002)")


class _ForceHistory(Extension):
    """The history-dependent element; ``sign`` +1 integrates lengthening (enhancement), -1 shortening."""

    interacts = MOVEMENT_PARAMETERS + LENGTH_PARAMETERS

    suffix = "ExtForceHistory"
    sign: float
    parameters = (
        Param("k", "1", 0.2, 0.0, 1.0, "extra force at D = 1, as a fraction of the SE force", _SRC, neutral=0.0),
        Param("L", "mm", 5.0, 0.5, 50.0, "active length change that saturates the history state", _SRC),
        Param("tau", "ms", 5000.0, 1000.0, 100_000.0, "decay time constant of the history state", _SRC),
    )
    reads = (
        Port("xm", "mm", "length.xm"),
        Port("vm", "mm/s", "length.vm"),
        Port("dxce", "mm", "force.dxce"),
        Port("x0", "mm", "force.x0"),
        Port("P0", "N", "force.P0"),
        Port("KSE", "1/mm", "force.KSE"),
    )
    exposes = {"offset": "N", "Fse": "N"}
    states = (State("D", "1", 1e-6),)
    targets = {"force.force_offset": "offset"}

    def configure(self, params: Mapping[str, float] | None) -> None:
        self.obj.sgn = self.sign

    @classmethod
    def reference_modulation(cls, values: Mapping[str, float], spikes_ms: np.ndarray) -> StateModulation:
        """The same equations for the SciPy reference: D integrated with Modules 1-3, driving force_offset."""
        from .twin import StateModulation

        k, length, tau, sign = float(values["k"]), float(values["L"]), float(values["tau"]), cls.sign

        def rhs(t: float, y: np.ndarray, obs: Observables) -> list[float]:
            w = obs.fse_N / obs.params["P0"] * max(sign * obs.vm_mm_s, 0.0) / (1000.0 * length)
            return [w * (1.0 - y[0]) - y[0] / tau]

        def offset(t: float, y: np.ndarray, obs: Observables) -> float:
            return sign * k * float(y[0]) * obs.fse_N

        return StateModulation((0.0,), rhs, {"force_offset": offset})


class ForceEnhancementAfterStretch(_ForceHistory):
    """Force after an active stretch stays above the isometric force at the same length."""

    name = "force_enhancement_after_stretch"
    namespace = "force_enhancement"
    sign = 1.0
    shows = "force after an active stretch stays above the isometric force"
    telling = Telling("a stimulated hold after an active stretch", hold_after=1)
    variable = "stretch_history"
    after = 1


class ForceDepressionAfterShortening(_ForceHistory):
    """Force after active shortening stays below the isometric force at the same length."""

    name = "force_depression_after_shortening"
    namespace = "force_depression"
    sign = -1.0
    shows = "force after active shortening stays below the isometric force"
    telling = Telling("a stimulated hold after active shortening", hold_after=-1)
    variable = "stretch_history"
    after = -1
