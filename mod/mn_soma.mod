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
ENDCOMMENT

NEURON {
    SUFFIX mn_soma
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    NONSPECIFIC_CURRENT i
    RANGE gnaf, gkdr, gcan, gkca, ena, ek, eca, ptau, qtau, kd, depth, taur, cainf, ica, inaf, ik
    RANGE pfac, qfac, cfac, dtseen, tstep
    RANGE gleak, eleak, gsyn, esyn, fcommon
    : the pool's common synaptic drive, one Vector.play for every cell (fcommon: this compartment's share)
    GLOBAL gcommon
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (mM) = (milli/liter)
    (um) = (micron)
    (S) = (siemens)
    (uS) = (microsiemens)
    FARADAY = (faraday) (coulomb)
}

PARAMETER {
    gnaf = 0.7 (S/cm2)
    gkdr = 0.2 (S/cm2)
    gcan = 0.01 (S/cm2)
    gkca = 0.02 (S/cm2)
    ena = 50 (mV)
    ek = -80 (mV)
    eca = 80 (mV)
    ptau = 15 (ms)
    qtau = 50 (ms)
    kd = 0.0005 (mM)
    depth = 1 (um)
    taur = 40 (ms)
    cainf = 0 (mM)
    gleak = 0 (S/cm2)
    eleak = -70 (mV)
    gsyn = 0 (S/cm2)
    esyn = 0 (mV)
    gcommon = 0 (uS)
    fcommon = 0 (S/cm2/uS)
    variable_step = 0 (1)
}

ASSIGNED {
    v (mV)
    dt (ms)
    i (mA/cm2)
    ica (mA/cm2)
    inaf (mA/cm2)
    ik (mA/cm2)
    gna (S/cm2)
    gk (S/cm2)
    gca (S/cm2)
    gtot (S/cm2)
    gs (S/cm2)
    minf (1)
    mfac (1)
    hinf (1)
    hfac (1)
    ninf (1)
    nfac (1)
    pinf (1)
    qinf (1)
    mtau (ms)
    htau (ms)
    ntau (ms)
    pfac (1)
    qfac (1)
    cfac (1)
    dtseen (ms)
    tstep (ms)
    dtgate (ms)
    am (/ms)  bm (/ms)  ah (/ms)  bh (/ms)  an (/ms)  bn (/ms)  ap (/ms)  bp (/ms)  aq (/ms)  bq (/ms)
    ac (mM/ms)  bc (/ms)
    zeroed (1)
}

STATE { m h n p q cai (mM) }

INITIAL {
    exact_rates(v)
    m = minf
    h = hinf
    n = ninf
    p = pinf
    q = qinf
    cai = cainf
    dtseen = -1
    zeroed = 0
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
    : i is linear in v: NEURON takes di/dv = gtot instead of a second evaluation
    CONDUCTANCE gtot
    gna = naf_g(gnaf, m, h)
    gk = kdr_g(gkdr, n) + kca_g(gkca, cai)
    gca = can_g(gcan, p, q)
    gs = gsyn + fcommon * gcommon
    gtot = gna + gk + gca + gleak + gs
    inaf = gna * (v - ena)
    ik = gk * (v - ek)
    ica = gca * (v - eca)
    i = inaf + ik + ica + ohmic(gleak, v, eleak) + ohmic(gs, v, esyn)
}

DERIVATIVE states {
    LOCAL hfull, nst
    if (variable_step) {
        zeroed = 0
        exact_rates(v)
        am = minf / mtau  bm = 1 / mtau
        ah = hinf / htau  bh = 1 / htau
        an = ninf / ntau  bn = 1 / ntau
        ap = pinf / ptau  bp = 1 / ptau
        aq = qinf / qtau  bq = 1 / qtau
        ac = ca_entry(ica) + cainf / taur
        bc = 1 / taur
    } else {
        : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
        nst = euler_steps(t, tstep, dt)
        hfull = dt*nst
        if (hfull != dtseen) {
            : the factors of the gates with constant time constants, once per step length
            pfac = 1 - exp(-hfull / ptau)
            qfac = 1 - exp(-hfull / qtau)
            cfac = 1 - exp(-hfull / taur)
            dtseen = hfull
        }
        tabled(v)
        m = m + mfac * (minf - m)
        h = h + hfac * (hinf - h)
        n = n + nfac * (ninf - n)
        if (hfull > 1.5*dtgate) {
            : the factors are for a shorter step than this one (computed exactly in this block, whose dt
            : secondorder halves; the table's are for NEURON's dt): the second half, at the same v
            m = m + mfac * (minf - m)
            h = h + hfac * (hinf - h)
            n = n + nfac * (ninf - n)
        }
        p = p + pfac * (pinf - p)
        q = q + qfac * (qinf - q)
        : cnexp of cai' = ac - cai/taur: cai <- cai + (1 - exp(-dt/taur)) (ac taur - cai)
        cai = cai + cfac * (taur * ca_entry(ica) + cainf - cai)
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

PROCEDURE tabled(v (mV)) {
    : the fixed step's gate targets and factors at v (tabulated; exact when usetable_mn_soma = 0)
    TABLE minf, mfac, hinf, hfac, ninf, nfac, pinf, qinf, dtgate DEPEND dt FROM -120 TO 80 WITH 8000
    exact_rates(v)
    mfac = 1 - exp(-dt / mtau)
    hfac = 1 - exp(-dt / htau)
    nfac = 1 - exp(-dt / ntau)
    : the step these factors are for
    dtgate = dt
}

PROCEDURE exact_rates(v (mV)) {
    naf_rates(v)
    kdr_rates(v)
    pinf = can_minf(v)
    qinf = can_hinf(v)
}

INCLUDE "mn_naf.inc"
INCLUDE "mn_kdr.inc"
INCLUDE "mn_can.inc"
INCLUDE "mn_cadyn.inc"
INCLUDE "mn_kca.inc"
INCLUDE "mn_ohmic.inc"
INCLUDE "fixed_step.inc"
