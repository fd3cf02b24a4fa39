TITLE mn_pic for NEURON's fixed step alone (mn_pic_fixed)

COMMENT
mn_pic (mn_pic.mod) for NEURON's fixed step alone (CoreNEURON included), at a lower cost per step: the same
declarations, currents, initial state and fixed step (mn_pic.inc), so the same equations and tables.

Why a second mechanism: mn_pic hands its states to METHOD euler, whose right-hand sides CVODE needs; under the
fixed step NEURON then runs that method's generic loop for every instance on every step (the derivatives evaluated,
zero because the mechanism assigns its states itself, and added, twice a step under secondorder).  Here the
block's derivatives are the constant 0, which METHOD cnexp compiles into inline additions of nothing.

METHOD cnexp does not halve dt under secondorder: each call is one whole step, and the gate factors (and mn_pic's
table) are those of NEURON's dt.  Under backward Euler the numbers are mn_pic's bit for bit; under
Crank-Nicolson equal to rounding where mn_pic takes two half steps of a gate whose factors are tabulated
(tests/pool/test_motoneuron_channels.py).

Under CVODE the states would stand still: use mn_pic.  The package refuses to run mn_pic_fixed under CVODE.
Units: as mn_pic's (mV, ms, S/cm2).
ENDCOMMENT

NEURON {
    SUFFIX mn_pic_fixed
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package)
    GLOBAL variable_step
}

INCLUDE "mn_pic.inc"

INITIAL {
    initial_state()
}

BREAKPOINT {
    SOLVE advance METHOD cnexp
    : i is linear in v: NEURON takes di/dv = gtot instead of a second evaluation
    CONDUCTANCE gtot
    currents(v)
}

DERIVATIVE advance {
    : the fixed step's update; the derivatives below are zero (the states are already advanced)
    if (variable_step == 0) {
        fixed_step()
    }
    tstep = t
    m' = 0
}
