TITLE mn_syn: a common excitatory synaptic conductance spread over a motoneuron's membrane

COMMENT
The drive of a motor-unit pool (neuromuscle.pool.Pool.drive_synaptic): every motoneuron receives the same total
synaptic conductance, spread uniformly over its soma and dendrite, with reversal e (0 mV for glutamatergic
excitation).  g (S/cm2) is set by Vector.play in steps (events, not an interpolation every time step):

    i = g (v - e)          (mA/cm2)

A conductance rather than a current saturates the discharge as the membrane depolarises towards e.  A density
mechanism of the package's own, so that NEURON and CoreNEURON run the same drive.
ENDCOMMENT

NEURON {
    SUFFIX mn_syn
    NONSPECIFIC_CURRENT i
    RANGE g, e
    THREADSAFE
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    g = 0 (S/cm2)
    e = 0 (mV)
}

ASSIGNED {
    v (mV)
    i (mA/cm2)
}

BREAKPOINT {
    i = ohmic(g, v, e)
}

INCLUDE "mn_ohmic.inc"
