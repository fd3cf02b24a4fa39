TITLE Motoneuron fast sodium current (soma)

COMMENT
Motoneuron fast sodium current (spike upstroke), soma: i = gbar m^3 h (v - ena).

Kinetics: Booth, Rinzel & Kiehn 1997 (J Neurophysiol 78:3371-3385, two-compartment motoneuron, Table 1) in the
form used by Kim 2017 (J Neurophysiol 118:3246, ModelDB 266732) and Kim et al. 2020 (ModelDB 267184), Naf.mod:
  alpha_m = 0.4 (v+49) / (1 - exp(-(v+49)/5)),  beta_m = 0.4 (v+25) / (exp((v+25)/5) - 1)   (1/ms, v in mV)
  h_inf = 1 / (1 + exp((v+58)/7)),  tau_h = 30 / (exp((v+60)/15) + exp(-(v+60)/16))          (ms)
Written here anew (in mn_naf.inc, shared with mn_soma); the removable singularities of alpha_m, beta_m are handled
by vtrap.  Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_naf
    THREADSAFE
    USEION na READ ena WRITE ina
    RANGE gbar, g
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0.7 (S/cm2)
}

ASSIGNED {
    v (mV)
    ena (mV)
    ina (mA/cm2)
    g (S/cm2)
    minf (1)
    mtau (ms)
    hinf (1)
    htau (ms)
}

STATE { m h }

BREAKPOINT {
    SOLVE states METHOD cnexp
    g = naf_g(gbar, m, h)
    ina = g * (v - ena)
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
    naf_rates(v)
}

INCLUDE "mn_naf.inc"
