TITLE Kim, Sandercock & Heckman 2015, Modules 1-3 in one mechanism for NEURON's fixed step alone (KimUnitFixed)

COMMENT
KimUnit (kim_unit.mod) for NEURON's fixed step alone (CoreNEURON included), at a lower cost per step: the same
declarations, initial state and fixed step (kim_unit.inc, and through it the three modules' equations in
kim_m1_calcium.inc, kim_m2_activation.inc and kim_m3_force.inc), so its numbers are KimUnit's bit for bit
(tests/model/test_kim_unit_fixed.py).

Why a second mechanism: KimUnit solves its nine states by METHOD euler, whose right-hand sides CVODE needs; under
the fixed step NEURON then runs that method's generic loop for every unit on every step (the nine derivatives
evaluated, zero because KimUnit assigns the states itself, and added, twice a step under secondorder), also on
the steps the muscle skips (substeps > 1).  Here the block's derivatives are the constant 0, which METHOD cnexp
turns into nine inline additions of nothing: the step is the unit's update and little else.

Under CVODE the unit would stand still: use KimUnit.  The package refuses to run a KimUnitFixed under CVODE (from
hoc: the unit's refused is 1 after an finitialize under CVODE, where variable_step_KimUnitFixed = 1).

Order within a step: the unit advances in its BREAKPOINT's SOLVE, in registration order, as KimUnit does (this
file's name places it after kim_unit.mod, after every other muscle mechanism), with t at the step's end.
substeps = k >= 1: the muscle advances once every k steps by one step of k dt, as KimUnit's; METHOD cnexp does
not halve dt under secondorder, so each update is k dt, as KimUnit's.
Spikes: NET_RECEIVE with weight w, as KimCa.  Coupling and ports: as KimUnit.
ENDCOMMENT

NEURON {
    POINT_PROCESS KimUnitFixed
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package)
    GLOBAL variable_step
    RANGE refused
}

INCLUDE "kim_unit.inc"

ASSIGNED {
    : 1 when initialised under CVODE, which this mechanism cannot follow
    refused (1)
}

INITIAL {
    unit_initial()
    refused = variable_step
}

BREAKPOINT {
    SOLVE advance METHOD cnexp
}

DERIVATIVE advance {
    : the fixed step's update; the derivatives below are zero (the states are already advanced)
    if (variable_step == 0) {
        kcount = kcount + 1
        if (kcount >= substeps) {
            kcount = 0
            xl = xm
            step_all(substeps*dt)
        }
        tstep = t
    }
    CaSR' = 0
    CaSRCS' = 0
    CaSP' = 0
    CaSPB' = 0
    CaSPT' = 0
    S2' = 0
    S12' = 0
    atil' = 0
    dxce' = 0
}
