TITLE Kim, Sandercock & Heckman 2015, Modules 1-3 in one mechanism: spikes to Ca2+ to activation to force (KimUnit)

COMMENT
The three modules of Kim, Sandercock & Heckman 2015 in one mechanism: spikes -> Ca2+ -> activation -> force.

The equations and their arithmetic are those of KimCa (kim_m1_calcium.mod, eqs 1-7, 18), KimAct
(kim_m2_activation.mod, eqs 8, 19-20) and KimForce (kim_m3_force.mod, eqs 9-12): this file INCLUDEs the same
kim_m1_calcium.inc, kim_m2_activation.inc and kim_m3_force.inc, so the fixed step gives the three mechanisms'
numbers bit for bit (tests/model/test_fused.py) and CVODE sees the same right-hand side and the same diagonal
Jacobian.  What is gone is the overhead around the arithmetic: no POINTERs between the modules (one read of the
length per step), one per-instance loop instead of three, no Jacobian loops, the shared parameters read directly.
Read the three files' headers for the equations, units and numerics; only what differs is written here.

Coupling: POINTER xm, vm -> muscle length (mm) and velocity (mm/s) of a MuscleLength point process (one per rank
in a pool).  The six modulation ports of the three mechanisms, with the same names and meaning (release_gain,
uptake_gain: KimCa; tauA_gain, C1_shift: KimAct; force_offset, capacity_gain: KimForce), read only when
use_ports = 1 (the Python wiring sets it when an extension is attached, and points unused ones at RANGE unity or
zero); with use_ports = 0 (default) they need not be set.  A unit with extensions gives the three mechanisms'
numbers bit for bit too: each port is read in the step where the three mechanisms read it (the extensions and
PortCombine register before this file).
Spikes: NET_RECEIVE with weight w, as KimCa.

Registration order: this file's lower-case name places it after every other muscle mechanism (extensions,
PortCombine, afferents, MuscleLength), as the three Kim mechanisms' files are: whatever reads the unit (a tendon
organ's force) or drives it (an extension's gain) sees the same step of it in both forms.

Order within a step, as NEURON runs the three mechanisms (KimCa, KimAct, KimForce are registered in that order):
Module 1 with the previous step's Atil, Module 2 with the new [CaSPT], Module 3 with the new A.

Fixed step: the states are assigned directly in the DERIVATIVE block (y + h (D/h) for Modules 1 and 3, the exact
update for Atil, as the three mechanisms compute them), and every derivative is then zero, so METHOD euler adds
exactly nothing.  CVODE (variable_step = 1): the DERIVATIVE block gives the three right-hand sides.

Slower muscle (substeps = k >= 1, fixed step only): the muscle advances once every k membrane steps, by one step
of k dt at the end of those k (spikes arriving in between act at the next muscle step; the outputs hold between
muscle steps).  k = 1 is the three-mechanism update.  The movement clock (eqs 19-20) is read at the muscle step's
midpoint, as KimAct reads it at the fixed step's.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimUnit
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
}

INCLUDE "kim_unit.inc"

INITIAL {
    unit_initial()
}

BREAKPOINT {
    SOLVE states METHOD euler
}

DERIVATIVE states {
    LOCAL nst
    : the length is read once per evaluation (under the fixed step, once per update: a POINTER read is a generic
    : data handle in NEURON 9)
    if (variable_step) {
        xl = xm
        rhs_all()
    } else {
        kcount = kcount + 1
        if (kcount >= substeps) {
            kcount = 0
            xl = xm
            : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
            nst = euler_steps(t, tstep, dt)
            step_all(substeps*dt*nst)
        }
        if (zeroed == 0) {
            : the states are already advanced: nothing is left for METHOD euler to add (set once per run;
            : rhs_all, under CVODE, sets them again)
            a1 = 0  a2 = 0  a3 = 0  a4 = 0  a5 = 0  a6 = 0  a7 = 0
            b1 = 0  b2 = 0  b3 = 0  b4 = 0  b5 = 0  b6 = 0  b7 = 0
            kAd = 0
            aa = 0
            bb = 0
            zeroed = 1
        }
    }
    tstep = t
    CaSR' = a1 - b1*CaSR
    CaSRCS' = a2 - b2*CaSRCS
    CaSP' = a3 - b3*CaSP
    CaSPB' = a4 - b4*CaSPB
    CaSPT' = a5 - b5*CaSPT
    S2' = a6 - b6*S2
    S12' = a7 - b7*S12
    atil' = (Ainf - atil)*kAd
    dxce' = aa - bb*dxce
    if (variable_step) {
        : KimForce's DERIVATIVE ends with se_force() (its CVODE output F)
        se_force()
    }
}

PROCEDURE rhs_all() {
    : CVODE: KimCa's, KimAct's and KimForce's right-hand sides in registration order
    zeroed = 0
    ca_rhs(atil, xl)
    act_rates(CaSPT)
    kAd = kA
    activation(t, 1, xl, vm)
    al = A
    read_capacity()
    ce_rhs()
}
