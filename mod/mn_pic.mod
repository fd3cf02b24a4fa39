TITLE Motoneuron dendritic L-type calcium PIC as a nonspecific current (the pool's fast path)

COMMENT
The dendritic L-type calcium PIC of mn_cal (the same equations, in mn_cal.inc, parameters and sources; see
mn_cal.mod) as a
NONSPECIFIC current, for the pool's fast path: its calcium enters no pool, so no calcium ion is needed.
  i = gbar m (v - erev),  m' = (m_inf - m) / mtau,  m_inf = 1 / (1 + exp(-(v - vhalf)/slope))
plus the compartment's leak gleak (v - eleak) and its share of the common synaptic conductance
(gsyn + fcommon gcommon) (v - esyn) (mn_syn's current; gsyn set per instance, or gcommon, a pool's drive in uS
shared by every cell), so that the reduced cell's dendrite runs no pas and no mn_syn (all 0 by default: a cell
that inserts those beside mn_pic gets the same currents from them).  ipic is the PIC's current alone.

Fixed step: m <- m + (1 - exp(-dt/mtau)) (m_inf - m), as NEURON's cnexp, with the logistic read from a table
over x = (v - vhalf)/slope (-60 to 60 in steps of 0.01, linear interpolation; vhalf and slope may differ from
cell to cell) and the factor computed once per dt.  usetable_mn_pic = 0 computes the logistic exactly.  With
substeps = k the gate advances once every k fixed steps, by one step of k dt at the voltage of the last (its time
constant is 60 ms; the current is computed every step); 1 is the every-step update.  CVODE: the exact right-hand
side.  Units: mV, ms, S/cm2.
The declarations, currents, initial state and fixed step are in mn_pic.inc, which mn_pic_fixed (the fixed step
alone, at a lower cost per step) includes too.
ENDCOMMENT

NEURON {
    SUFFIX mn_pic
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
}

INCLUDE "mn_pic.inc"

INITIAL {
    initial_state()
}

BREAKPOINT {
    SOLVE states METHOD euler
    : i is linear in v: NEURON takes di/dv = gtot instead of a second evaluation
    CONDUCTANCE gtot
    currents(v)
}

DERIVATIVE states {
    if (variable_step) {
        zeroed = 0
        rhs_rates()
    } else {
        fixed_step()
        if (zeroed == 0) {
            : the state is already advanced: nothing is left for METHOD euler to add
            am = 0
            bm = 0
            zeroed = 1
        }
    }
    tstep = t
    m' = am - bm * m
}
