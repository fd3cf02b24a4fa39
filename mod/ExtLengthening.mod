TITLE Model extension lengthening_below_optimum: less Ca2+ release while lengthening below the optimum

COMMENT
Model extension "lengthening_below_optimum" (a cause of the diagnosis catalogue: excess model force while lengthening below
the optimum): while the muscle lengthens at or below its optimal length, the Ca2+ release falls, by a fraction
that saturates exponentially with the lengthening velocity.  It acts where eq 18 does (Module 1, on Ca2+), not on
A as eq 20 does: a loss of Ca2+ matters at low stimulation rates and little in a fused tetanus, where the
troponin is saturated, as Kim, Sandercock & Heckman 2015 say of the error it compensates ("more predominant for low frequencies
(<= 20 Hz) when the length was shorter than the optimal muscle length during lengthening").
Equations (units: k 1, v0 mm/s, tau_on ms, Xm and xopt mm, Vm mm/s positive = lengthening, t ms):
    target = k (1 - exp(-Vm/v0))      if Xm <= xopt and Vm > 0
           = 0                        otherwise
    dE/dt  = (target - E) / tau_on                (E in [0, k]: the depression follows the gate within tau_on)
    gain   = 1 - E                                drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
synth's hidden lengthening effect is a hyperbolic velocity term under a logistic length gate (docs/guide/synth.md); this
is an exponential saturation under a hard gate at the optimum, smoothed in time by tau_on.
With k = 0 (its neutral value) the target is exactly 0, E stays 0 and gain is exactly 1: the unit is bit-identical
to the baseline.  Isometric trials (Vm = 0): gain exactly 1 whatever k.
Bounds (neuromuscle/model/extensions/lengthening_below_optimum.py): k in [0, 0.9], v0 in [1, 200] mm/s; tau_on
= 5 ms is fixed (not fitted): it only keeps the gain continuous for CVODE where the gate switches.
Coupling: POINTER xm, vm -> MuscleLength (mm, mm/s); POINTER xopt -> KimCa's xopt (mm, = g1).  Exposes RANGE gain
(1) for POINTER KimCa.release_gain and E.
Numerics: E' is linear in E with the target frozen over the step: METHOD cnexp in fixed step; CVODE integrates
the same DERIVATIVE.  O(1) per step.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtLengthening
    THREADSAFE
    RANGE k, v0, tau_on, gain, target
    POINTER xm, vm, xopt
}

PARAMETER {
    k = 0.3 (1)
    v0 = 10 (mm/s)
    tau_on = 5 (ms)
}

ASSIGNED {
    xm (mm)
    vm (mm/s)
    xopt (mm)
    gain (1)
    target (1)
}

STATE {
    E (1)
}

INITIAL {
    E = 0
    drive()
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    drive()
    E' = (target - E)/tau_on
}

PROCEDURE drive() {
    if (xm <= xopt && vm > 0) {
        target = k*(1 - exp(-vm/v0))
    } else {
        target = 0
    }
    gain = 1 - E
}
