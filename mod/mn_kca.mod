TITLE Motoneuron calcium-activated potassium current (the afterhyperpolarisation, soma)

COMMENT
Motoneuron calcium-activated potassium current (SK, the medium afterhyperpolarisation), soma:
  i = gbar cai / (cai + kd) (v - ek)
Instantaneous in cai, as in Booth, Rinzel & Kiehn 1997 (J Neurophysiol 78:3371-3385, I_K(Ca), K_d = 0.2 uM)
and Kim 2017 / Kim et al. 2020 (ModelDB 266732, 267184: KCa.mod, K_d = 0.5 uM); cai from mn_cadyn.
Written here anew (in mn_kca.inc, shared with mn_soma).  Units: mV, mM, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_kca
    THREADSAFE
    USEION ca READ cai
    USEION k READ ek WRITE ik
    RANGE gbar, g, kd
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (mM) = (milli/liter)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0.02 (S/cm2)
    kd = 0.0005 (mM)
}

ASSIGNED {
    v (mV)
    ek (mV)
    cai (mM)
    ik (mA/cm2)
    g (S/cm2)
}

BREAKPOINT {
    g = kca_g(gbar, cai)
    ik = g * (v - ek)
}

INCLUDE "mn_kca.inc"
