TITLE Motoneuron N-type calcium current (soma)

COMMENT
Motoneuron N-type (high-threshold) calcium current, soma: the spike-triggered Ca entry that activates the
afterhyperpolarisation's K(Ca) current (mn_kca through mn_cadyn).  i = gbar m^2 h (v - erev).

Kinetics: Booth, Rinzel & Kiehn 1997 (J Neurophysiol 78:3371-3385, I_Ca-N, Table 1) in the form of Kim 2017
(ModelDB 266732) and Kim et al. 2020 (ModelDB 267184), CaN.mod:
  m_inf = 1 / (1 + exp(-(v+25)/5)), tau_m = 15 ms;  h_inf = 1 / (1 + exp((v+43)/5)), tau_h = 50 ms
Reversal: a fixed erev (mV; Booth et al. use E_Ca = 80 mV) instead of the published Nernst-minus-70 mV.
Written here anew (in mn_can.inc, shared with mn_soma).  Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_can
    THREADSAFE
    USEION ca WRITE ica
    RANGE gbar, g, erev, mtau, htau
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0.01 (S/cm2)
    erev = 80 (mV)
    mtau = 15 (ms)
    htau = 50 (ms)
}

ASSIGNED {
    v (mV)
    ica (mA/cm2)
    g (S/cm2)
    minf (1)
    hinf (1)
}

STATE { m h }

BREAKPOINT {
    SOLVE states METHOD cnexp
    g = can_g(gbar, m, h)
    ica = g * (v - erev)
}

INITIAL {
    rates(v)
    m = minf
    h = hinf
}

DERIVATIVE states {
    rates(v)
    m' = (minf - m) / mtau
    h' = (hinf - h) / htau
}

PROCEDURE rates(v (mV)) {
    minf = can_minf(v)
    hinf = can_hinf(v)
}

INCLUDE "mn_can.inc"
