"""Extension "lengthening_below_optimum": seed 001's eq 20 switched on in KimAct (no mod file of its own).

Equation (Xm mm, Vm mm/s, positive = lengthening), after movement onset, while Xm <= X_opt (= g1) and Vm >= 0:
A = Atil^alpha / ((1 + beta phi(Xm)) (1 + gamma Vm)), phi of eq 18 (KimCa's phi1, phi2, whether eq 18 is on or
not); a non-positive divisor gives A = 0.  Parameters are KimAct's own (``kim_m2.beta``, ``kim_m2.gamma``): beta (1)
in [0, 10], gamma (s/mm) in [0, 0.1] (``_EQ19`` in neuromuscle/model/kim.py); CT09 0.47, 0.001 s/mm.  Neutral:
beta = gamma = 0 (divisor exactly 1: bit-identical to eq 20 off).  Selecting it sets KimAct.lengdiv = 1 and
nothing else (eq 19 keeps its own switch).
"""

from __future__ import annotations

from ..kim import KimActivation
from . import SwitchExtension


class LengtheningBelowOptimum(SwitchExtension):
    """Excess model force while lengthening below the optimum: A divided by (1 + beta phi)(1 + gamma Vm) (eq 20)."""

    name = "lengthening_below_optimum"
    namespace = KimActivation.namespace
    slot = "act"
    owner = KimActivation
    switch = "lengthening_divisor"
    parameters = SwitchExtension.borrow(KimActivation, {"beta": 0.0, "gamma": 0.0})
