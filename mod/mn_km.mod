TITLE Motoneuron M-like potassium current (minimum steady discharge rate, soma)

COMMENT
A potassium current that activates slowly just below the spike threshold and does not inactivate, like the M
current of Kv7 channels: spinal motoneurons carry one (Alaburda, Perrier & Hounsgaard 2002, J Physiol; Kv7 in
mouse motoneurons: Lombardo & Harrington 2016, J Neurophysiol).  Near threshold it turns the onset of repetitive
firing abrupt: a cell either fires at or above a minimum steady rate or falls silent, instead of firing ever more
slowly as its drive approaches threshold.  Cat motoneurons have such a minimum rate, the longer their AHP the lower
it is (Kernell 1965, Acta Physiol Scand), and human motor units start near a preferred rate soon after recruitment
(Kiehn & Eken 1997, J Neurophysiol).  A phenomenological form, written here anew:
  i = gbar m (v - ek),  m' = (m_inf(v) - m) / mtau,  m_inf = 1 / (1 + exp(-(v - vhalf)/slope))
with vhalf -55 mV, slope 4 mV, mtau 100 ms by default.  Off unless the motoneuron's g_km_S_per_cm2 > 0
(neuromuscle.pool.motoneuron).  Linear in m with a constant time constant: cnexp is exact for v held over a step.
Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_km
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
    vhalf = -55 (mV)
    slope = 4 (mV)
    mtau = 100 (ms)
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
