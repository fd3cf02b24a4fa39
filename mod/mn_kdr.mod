TITLE Motoneuron delayed-rectifier potassium current (soma)

COMMENT
Motoneuron delayed-rectifier potassium current (spike repolarisation), soma: i = gbar n^4 (v - ek).

Kinetics: Booth, Rinzel & Kiehn 1997 (J Neurophysiol 78:3371-3385, Table 1) as shifted by Kim 2017 (ModelDB
266732) and Kim et al. 2020 (ModelDB 267184), KDr.mod:
  n_inf = 1 / (1 + exp(-(v+31)/15)),  tau_n = 5 / (exp((v+50)/40) + exp(-(v+50)/50))   (ms, v in mV)
Written here anew (in mn_kdr.inc, shared with mn_soma).  Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_kdr
    THREADSAFE
    USEION k READ ek WRITE ik
    RANGE gbar, g
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0.2 (S/cm2)
}

ASSIGNED {
    v (mV)
    ek (mV)
    ik (mA/cm2)
    g (S/cm2)
    ninf (1)
    ntau (ms)
}

STATE { n }

BREAKPOINT {
    SOLVE states METHOD cnexp
    g = kdr_g(gbar, n)
    ik = g * (v - ek)
}

INITIAL {
    rates(v)
    n = ninf
}

DERIVATIVE states {
    rates(v)
    n' = (ninf - n) / ntau
}

PROCEDURE rates(v (mV)) {
    kdr_rates(v)
}

INCLUDE "mn_kdr.inc"
