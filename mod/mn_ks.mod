TITLE Motoneuron slow potassium current (late spike-frequency adaptation, soma)

COMMENT
A slow potassium current that each spike activates a little and that decays over seconds: the late adaptation of
motoneurons, whose discharge under a constant current or a constant synaptic drive slows over tens of seconds,
more in cells that fire faster (Kernell & Monster 1982, Exp Brain Res; Spielmann, Laouris, Nordstrom, Robinson,
Reinking & Stuart 1993, J Physiol; several mechanisms reviewed by Powers, Sawczuk, Musick & Binder 1999, J Physiol
Paris), and a source of the rate decline of human motor units at constant force and of part of their paired-unit
Delta F (Revill & Fuglevand 2011, J Neurophysiol).  A phenomenological form, written here anew:
  i = gbar m (v - ek),  m' = (m_inf(v) - m) / mtau,  m_inf = 1 / (1 + exp(-(v - vhalf)/slope))
with vhalf -20 mV and slope 2 mV: m_inf is 0 between spikes and 1 during them, so m holds the fraction of time
spent in spikes over the last mtau; steady m grows with the rate.  Off unless the motoneuron's g_ks_S_per_cm2 > 0
(neuromuscle.pool.motoneuron).  Linear in m with a constant time constant: cnexp is exact for v held over a step.
Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_ks
    THREADSAFE
    NONSPECIFIC_CURRENT i
    RANGE gbar, g, ek, vhalf, slope, mtau
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0 (S/cm2)
    ek = -80 (mV)
    vhalf = -20 (mV)
    slope = 2 (mV)
    mtau = 10000 (ms)
}

ASSIGNED {
    v (mV)
    i (mA/cm2)
    g (S/cm2)
}

STATE { m }

BREAKPOINT {
    SOLVE states METHOD cnexp
    gated_current(v)
}

INITIAL {
    m = gate_inf(v, vhalf, slope)
}

DERIVATIVE states {
    m' = (gate_inf(v, vhalf, slope) - m) / mtau
}

INCLUDE "mn_gate.inc"
