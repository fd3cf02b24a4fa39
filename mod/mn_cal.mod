TITLE Motoneuron dendritic L-type calcium current (the persistent inward current)

COMMENT
Motoneuron dendritic L-type (Cav1.3) calcium current: the persistent inward current (PIC) behind plateau
potentials, self-sustained firing and recruitment/derecruitment hysteresis.  Non-inactivating:
  i = gbar m (v - erev),  m' = (m_inf - m) / mtau,  m_inf = 1 / (1 + exp(-(v - vhalf)/slope))
Kinetics: Booth, Rinzel & Kiehn 1997 (J Neurophysiol 78:3371-3385, I_Ca-L: m_inf half-activation -40 mV, slope
7 mV, tau 40 ms) as set by Kim 2017 (J Neurophysiol 118:3246, ModelDB 266732: CaL.mod, vhalf -43 mV, slope 6 mV,
tau 60 ms, erev 60 mV).  Here a density mechanism (S/cm2) on the dendrite; its calcium does not enter the
submembrane pool of the soma.  Written here anew (in mn_cal.inc, shared with mn_pic).  Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_cal
    THREADSAFE
    USEION ca WRITE ica
    RANGE gbar, g, erev, vhalf, slope, mtau
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
}

PARAMETER {
    gbar = 0.0003 (S/cm2)
    erev = 60 (mV)
    vhalf = -43 (mV)
    slope = 6 (mV)
    mtau = 60 (ms)
}

ASSIGNED {
    v (mV)
    ica (mA/cm2)
    g (S/cm2)
    minf (1)
}

STATE { m }

BREAKPOINT {
    SOLVE states METHOD cnexp
    g = gbar * m
    ica = g * (v - erev)
}

INITIAL {
    minf = cal_minf(v)
    m = minf
}

DERIVATIVE states {
    minf = cal_minf(v)
    m' = (minf - m) / mtau
}

INCLUDE "mn_cal.inc"
