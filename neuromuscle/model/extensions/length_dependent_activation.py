"""Extension "length_dependent_activation": eq 18 of Kim et al. 2015 switched on in KimCa (no mod file of its own).

Equation (Xm mm, K5 1/(M ms)):  K5 = phi(Xm) K5i,  phi(Xm) = phi1 Xm + phi2 for Xm <= X_opt (= g1), else
phi3 Xm + phi4.  Parameters are KimCa's own (qualified ``kim_m1.phi1`` ...): phi1, phi3 in 1/mm within
[-0.5, 0.5], phi2, phi4 (1) within [-10, 10] (``_EQ18`` in neuromuscle/model/kim.py); CT09 0.03, 1.23, 0.01, 1.08.
Neutral: phi1 = phi3 = 0, phi2 = phi4 = 1 (phi = 1: K5 = K5i, bit-identical to eq 18 off).  Selecting it sets
KimCa.lencomp = 1 and the values given; KimAct's eq 20 reads the same phi1, phi2 (one fact, in KimCa).
"""

from __future__ import annotations

from ..kim import KimCalcium
from . import ACTIVATION_PARAMETERS, LENGTH_PARAMETERS, SwitchExtension, Telling


class LengthDependentActivation(SwitchExtension):
    """Activation, not only force, depends on length: troponin binding K5 scaled by phi(Xm) (eq 18)."""

    shows = "force falls off away from the optimum more than g(Xm) allows, most at low rates"
    #: At any rate: below the optimum eq 18 lowers the binding rate enough to lower an unfused 40 Hz train's force
    #: too (Table 1's phi on CT09 at -16 mm: -84 % at 10 Hz, -10 % at 40 Hz, -3 % at 100 Hz).
    telling = Telling("isometric stimulated trials more than 2 mm from the optimum", moving=False,
                      min_length_offset_mm=2.0)
    variable = "length"
    #: Its fitted line (two slopes, two intercepts) already gives the effect a size at each length a file holds
    #: isometric trials at, and trials at one length cannot differ in it: rule R8 neither resizes it nor asks it
    #: to be more than a resize of the causes before it.
    static = True
    interacts = LENGTH_PARAMETERS + ACTIVATION_PARAMETERS
    name = "length_dependent_activation"
    namespace = KimCalcium.namespace
    slot = "ca"
    owner = KimCalcium
    switch = "length_compensation"
    parameters = SwitchExtension.borrow(KimCalcium, {"phi1": 0.0, "phi2": 1.0, "phi3": 0.0, "phi4": 1.0})
