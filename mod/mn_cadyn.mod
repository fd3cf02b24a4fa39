TITLE Motoneuron submembrane calcium pool (soma)

COMMENT
Motoneuron submembrane calcium, soma: the Ca that gates the AHP current (mn_kca).  One pool of depth `depth`
filled by the calcium current and emptied to `cainf` with time constant `taur` (cai here is the Ca above its
resting level, as in Booth et al.: cainf = 0 keeps the AHP current off at rest):
  cai' = -ica / (2 F depth) + (cainf - cai) / taur          (mM/ms; inward ica < 0 raises cai)
Form: Destexhe, Contreras, Sejnowski & Steriade 1994 (J Neurophysiol 72:803) first-order pool; its role and the
decay rate setting the AHP duration follow Booth, Rinzel & Kiehn 1997 (dCa/dt = f(-alpha I_Ca - kCa Ca)), the
motoneuron type setting taur (slow units: longer AHP).  Written here anew (in mn_cadyn.inc, shared with mn_soma).  Units: mM, ms, um, mA/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_cadyn
    THREADSAFE
    USEION ca READ ica WRITE cai
    RANGE depth, taur, cainf
}

UNITS {
    (mA) = (milliamp)
    (mM) = (milli/liter)
    (um) = (micron)
    FARADAY = (faraday) (coulomb)
}

PARAMETER {
    depth = 1 (um)
    taur = 40 (ms)
    cainf = 0 (mM)
}

ASSIGNED {
    ica (mA/cm2)
}

STATE { cai (mM) }

INITIAL {
    cai = cainf
}

BREAKPOINT {
    SOLVE state METHOD cnexp
}

DERIVATIVE state {
    cai' = ca_entry(ica) + (cainf - cai) / taur
}

INCLUDE "mn_cadyn.inc"
