TITLE Motoneuron dendritic L-type calcium PIC as a nonspecific current (the pool's fast path)

COMMENT
The dendritic L-type calcium PIC of mn_cal (the same equations, in mn_cal.inc, parameters and sources; see
mn_cal.mod) as a
NONSPECIFIC current, for the pool's fast path: its calcium enters no pool, so no calcium ion is needed.
  i = gbar m (v - erev),  m' = (m_inf - m) / mtau,  m_inf = 1 / (1 + exp(-(v - vhalf)/slope))
plus the compartment's leak gleak (v - eleak) and its share of the common synaptic conductance
(gsyn + fcommon gcommon) (v - esyn) (mn_syn's current; gsyn set per instance, or gcommon, a pool's drive in uS
shared by every cell), so that the reduced cell's dendrite runs no pas and no mn_syn (all 0 by default: a cell
that inserts those beside mn_pic gets the same currents from them).  ipic is the PIC's current alone.

Fixed step: m <- m + (1 - exp(-dt/mtau)) (m_inf - m), as NEURON's cnexp, with the logistic read from a table
over x = (v - vhalf)/slope (-60 to 60 in steps of 0.01, linear interpolation; vhalf and slope may differ from
cell to cell) and the factor computed once per dt.  usetable_mn_pic = 0 computes the logistic exactly.  With
substeps = k the gate advances once every k fixed steps, by one step of k dt at the voltage of the last (its time
constant is 60 ms; the current is computed every step); 1 is the every-step update.  CVODE: the exact right-hand
side.  Units: mV, ms, S/cm2.
ENDCOMMENT

NEURON {
    SUFFIX mn_pic
    THREADSAFE
    : 1 while NEURON integrates with CVODE (set at every finitialize by the package; from hoc: variable_step_<name> = 1)
    GLOBAL variable_step
    NONSPECIFIC_CURRENT i
    RANGE gbar, g, erev, vhalf, slope, mtau, mfac, dtseen, tstep
    RANGE gleak, eleak, gsyn, esyn, fcommon, ipic, substeps
    : the pool's common synaptic drive, one Vector.play for every cell (fcommon: this compartment's share)
    GLOBAL gcommon
}

UNITS {
    (mA) = (milliamp)
    (mV) = (millivolt)
    (S) = (siemens)
    (uS) = (microsiemens)
}

PARAMETER {
    gbar = 0.0003 (S/cm2)
    erev = 60 (mV)
    vhalf = -43 (mV)
    slope = 6 (mV)
    mtau = 60 (ms)
    gleak = 0 (S/cm2)
    eleak = -70 (mV)
    gsyn = 0 (S/cm2)
    esyn = 0 (mV)
    gcommon = 0 (uS)
    fcommon = 0 (S/cm2/uS)
    variable_step = 0 (1)
    substeps = 1 (1)
}

ASSIGNED {
    v (mV)
    dt (ms)
    tstep (ms)
    i (mA/cm2)
    ipic (mA/cm2)
    g (S/cm2)
    gtot (S/cm2)
    gs (S/cm2)
    sinf (1)
    mfac (1)
    dtseen (ms)
    am (/ms)
    bm (/ms)
    zeroed (1)
    kcount (1)
}

STATE { m }

INITIAL {
    m = cal_minf(v)
    dtseen = -1
    zeroed = 0
    kcount = 0
    tstep = t
}

BREAKPOINT {
    SOLVE states METHOD euler
    : i is linear in v: NEURON takes di/dv = gtot instead of a second evaluation
    CONDUCTANCE gtot
    g = gbar * m
    gs = gsyn + fcommon * gcommon
    gtot = g + gleak + gs
    ipic = g * (v - erev)
    i = ipic + ohmic(gleak, v, eleak) + ohmic(gs, v, esyn)
}

DERIVATIVE states {
    LOCAL hfull, nst
    if (variable_step) {
        zeroed = 0
        am = cal_minf(v) / mtau
        bm = 1 / mtau
    } else {
        kcount = kcount + 1
        if (kcount >= substeps) {
            kcount = 0
            : the whole step (dt is halved in this block under secondorder: fixed_step.inc)
            nst = euler_steps(t, tstep, dt)
            hfull = substeps*dt*nst
            if (hfull != dtseen) {
                mfac = 1 - exp(-hfull / mtau)
                dtseen = hfull
            }
            logistic((v - vhalf) / slope)
            m = m + mfac * (sinf - m)
        }
        if (zeroed == 0) {
            : the state is already advanced: nothing is left for METHOD euler to add
            am = 0
            bm = 0
            zeroed = 1
        }
    }
    tstep = t
    m' = am - bm * m
}

PROCEDURE logistic(x (1)) {
    TABLE sinf FROM -60 TO 60 WITH 12000
    sinf = cal_logistic(x)
}

INCLUDE "mn_cal.inc"
INCLUDE "mn_ohmic.inc"
INCLUDE "fixed_step.inc"
