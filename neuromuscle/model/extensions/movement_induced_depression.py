"""Extension "movement_induced_depression": seed 001's eq 19 switched on in KimAct (no mod file of its own).

Equation (t ms on the movement clock, t = 0 at movement onset):  alpha(t) = alpha + alpha1 (1 + tanh((t -
alpha2)/alpha3)),  A = Atil^alpha(t), floored at 1e-3 while eq 19 is active.  Parameters are KimAct's own
(``kim_m2.alpha1`` ...): alpha1 (1) in [0, 20], alpha2 (ms) in [0, 5000], alpha3 (ms) in [1, 5000] (``_EQ19`` in
neuromuscle/model/kim.py); CT09 4.77, 400 ms, 160 ms.  Neutral: alpha1 = 0 (alpha(t) = alpha; bit-identical to
eq 19 off while A stays above the floor: CT09's resting A is 0.0036).  Selecting it sets KimAct.movdep = 1 and
nothing else (eq 20 keeps its own switch); an isometric trial has no movement onset, so it changes nothing there.
"""

from __future__ import annotations

from ..kim import KimActivation
from . import SwitchExtension


class MovementInducedDepression(SwitchExtension):
    """Force sinks progressively during movement: the activation exponent rises after movement onset (eq 19)."""

    name = "movement_induced_depression"
    namespace = KimActivation.namespace
    slot = "act"
    owner = KimActivation
    switch = "movement_depression"
    parameters = SwitchExtension.borrow(KimActivation, {"alpha1": 0.0, "alpha2": None, "alpha3": None})
