TITLE Model extensions force enhancement after stretch and force depression after shortening

COMMENT
Model extensions "force_enhancement_after_stretch" (sgn = 1) and "force_depression_after_shortening" (sgn = -1)
(a cause of the diagnosis catalogue: force after an active stretch stays above, after active shortening below, the
isometric force at the same length): a history-dependent element in parallel with Module 3's CE-SE.

A state D (1) integrates the muscle's lengthening (sgn = 1) or shortening (sgn = -1), weighted by the force the
series element carries meanwhile (the work done on / by the muscle), saturates at 1, and fades slowly:
    Fse = P0 KSE max(Xm - XCE, 0)                                     (N; eq 9, from KimForce's own state)
    w   = (Fse/P0) max(sgn Vm, 0) / L                                  (1/s; Vm mm/s, L mm)
    dD/dt = w (1 - D)/1000 - D/tau                                     (1/ms; tau ms)
    offset = sgn k D Fse                                               (N) -> KimForce's force_offset port
so the output is F = Fse (1 + sgn k D): enhanced after stretch, depressed after shortening, in proportion to the
force (it vanishes with the activation) and never negative (k <= 1, 0 <= D < 1).  A small active stretch or
shortening of amplitude dX at force F raises D by about (F/P0) dX/L.  Isometric trials (Vm = 0): D stays 0.
Units: k 1, L mm, tau ms, Xm and XCE mm, Vm mm/s, P0 N, KSE /mm.
Neutral: k = 0 (offset exactly 0: F = Fse + 0, bit-identical to the baseline in fixed step).

Coupling: POINTER xm, vm -> MuscleLength (mm, mm/s); POINTER dxce, x0 -> KimForce's CE length change (STATE,
mm) and reference length (mm), P0, KSE -> its parameters (N, /mm): the SE force is computed here from states, so
it is that of the current evaluation even though this mechanism is evaluated before KimForce (a RANGE Fse read
from KimForce would lag one evaluation).
Exposes RANGE offset (N) for POINTER KimForce.force_offset, and D.
Numerics: D' is linear in D with a coefficient frozen over the step: METHOD cnexp in fixed step; CVODE integrates
the same DERIVATIVE.  O(1) per step.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtForceHistory
    THREADSAFE
    RANGE k, L, tau, sgn, offset, Fse, w
    POINTER xm, vm, dxce, x0, P0, KSE
}

PARAMETER {
    k = 0.2 (1)
    L = 5 (mm)
    tau = 5000 (ms)
    sgn = 1 (1)
}

ASSIGNED {
    xm (mm)
    vm (mm/s)
    dxce (mm)
    x0 (mm)
    P0 (N)
    KSE (/mm)
    offset (N)
    Fse (N)
    w (/ms)
    vl (mm/s)
}

STATE {
    D (1)
}

INITIAL {
    D = 0
    drive()
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    drive()
    D' = w*(1 - D) - D/tau
}

PROCEDURE drive() {
    Fse = P0*KSE*(xm - x0 - dxce)
    if (Fse < 0) {
        Fse = 0
    }
    vl = sgn*vm
    if (vl < 0) {
        vl = 0
    }
    w = (Fse/P0)*(vl/L)/(1000)
    offset = sgn*k*D*Fse
}
