TITLE The motoneuron soma's five channels in one mechanism (the pool's fast path)

COMMENT
The motoneuron soma's five mechanisms in one (the pool's fast path): mn_naf, mn_kdr, mn_can, mn_cadyn and mn_kca
with the same equations (INCLUDEd from their .inc files), parameters and sources (see each of those files), as one
NONSPECIFIC current
  i = gnaf m^3 h (v - ena) + (gkdr n^4 + gkca cai/(cai + kd)) (v - ek) + gcan p^2 q (v - eca)
  cai' = -(10000) ica / (2 F depth) + (cainf - cai) / taur,   ica = gcan p^2 q (v - eca)
plus the soma's leak gleak (v - eleak) and its share of the common synaptic conductance
(gsyn + fcommon gcommon) (v - esyn) (mn_syn's current; gsyn set per instance, or gcommon, a pool's drive in uS
shared by every cell), where p, q are mn_can's m, h.  The submembrane calcium is this mechanism's own state (no
ion is shared: only the AHP channel reads it), so NEURON runs one mechanism and no ion mechanism in the soma
instead of five and three, and no pas or mn_syn (the leak and the synaptic terms are 0 by default: a cell that
inserts pas and mn_syn beside mn_soma gets the same currents from those).

Fixed step: each gate advances as NEURON's cnexp would, g <- g + (1 - exp(-dt/tau(v))) (ginf(v) - g), with
ginf(v) and 1 - exp(-dt/tau(v)) read from a table over v (-120 to 80 mV in 0.025 mV, linear interpolation,
rebuilt when dt changes): no exp is evaluated per step.  usetable_mn_soma = 0 computes them exactly.  CVODE:
the exact right-hand sides (no table).  Units: mV, ms, S/cm2, mM, um.
The declarations, currents, initial state and fixed step are in mn_soma.inc, which mn_soma_fixed (the fixed step
alone, at a lower cost per step) includes too.
ENDCOMMENT

NEURON {
    SUFFIX mn_soma
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
}

INCLUDE "mn_soma.inc"

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
            : the states are already advanced: nothing is left for METHOD euler to add
            am = 0  bm = 0  ah = 0  bh = 0  an = 0  bn = 0  ap = 0  bp = 0  aq = 0  bq = 0  ac = 0  bc = 0
            zeroed = 1
        }
    }
    tstep = t
    m' = am - bm * m
    h' = ah - bh * h
    n' = an - bn * n
    p' = ap - bp * p
    q' = aq - bq * q
    cai' = ac - bc * cai
}
