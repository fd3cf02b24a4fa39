TITLE TendonOrganIb: Golgi tendon organ (group Ib) afferent, Lin & Crago's model

COMMENT
A Golgi tendon organ (group Ib afferent): a force receptor in series with the muscle fibres.  Its rate (/s) is the
model of Lin & Crago (2002, Ann Biomed Eng 30:54-67), built for the decerebrate cat soleus stretch reflex: a
logarithm of the muscle's force, passed through second-order linear dynamics of unit steady gain,

    x = g1 ln(Fm/g2 + 1)                                         (/s)
    rate = H(s) x,   H(s) = (1.7 s^2 + 2.58 s + 0.4) / (s^2 + 2.2 s + 0.4)   (s in /s)

Fm (N): the muscle's force.  Defaults g1 = 60 /s, g2 = 4 N.  H's poles are at 0.2 and 2 /s and its zeros at
0.18 and 1.34 /s: a step of force first raises the rate to 1.7 times its steady value, which it then approaches
over seconds.  Written as partial fractions, with two first-order low-passes of x,

    z1' = (x - z1)/tau1,  tau1 = 5000 ms;   z2' = (x - z2)/tau2,  tau2 = 500 ms
    rate = 1.7 x - (2/15) z1 - (17/30) z2

(1.7 - 2/15 - 17/30 = 1: the steady rate is x).  tau1 and tau2 are H's poles, and the three coefficients belong
to them, so they are fixed (GLOBAL), not settings of a receptor.  The paper itself was not at hand; the equation
and every coefficient are those of two re-implementations that agree on each (the pools guide,
docs/guide/pools.md, lists them and where a third differs).

One receptor reads the force F (N) of one muscle unit: fscale (1) scales it to the muscle's, Fm = fscale F (the
reflex sets fscale to the pool's summed P0 over the unit's P0: the muscle's force were every unit pulling at this
unit's fraction of its P0).  A negative force counts as none.  The rate is held in [0, max_rate]
(afferent_encoder.inc).  INITIAL starts both low-passes at the steady state of the force there.

Coupling: POINTER F -> the force (N) of the muscle unit's contraction mechanism (KimForce.F, KimUnit.F).
Registration order: this file is registered before the Kim modules: it reads the force of the previous step
(one time step's lag, far below the afferent's conduction delay).
Spikes: the shared encoder (afferent_encoder.inc) integrates the rate to threshold and calls net_event.
Deterministic: no random numbers; phase0 (1) staggers afferents.
ENDCOMMENT

NEURON {
    POINT_PROCESS TendonOrganIb
    THREADSAFE
    POINTER F
    RANGE g1, g2, fscale, sample_ms, max_rate, phase0, rate, phase
}

PARAMETER {
    g1 = 60 (/s)
    g2 = 4 (N)
    fscale = 1 (1)
    tau1 = 5000 (ms)
    tau2 = 500 (ms)
}

ASSIGNED {
    F (N)
}

STATE {
    z1 (/s)
    z2 (/s)
}

BREAKPOINT {
    SOLVE lowpass METHOD cnexp
}

DERIVATIVE lowpass {
    z1' = (static_rate() - z1)/tau1
    z2' = (static_rate() - z2)/tau2
}

FUNCTION static_rate() (/s) {
    if (F > 0) {
        static_rate = g1*log(fscale*F/g2 + 1)
    } else {
        static_rate = 0
    }
}

PROCEDURE receptor_initial() {
    z1 = static_rate()
    z2 = static_rate()
}

FUNCTION rate_now() (/s) {
    rate_now = 1.7*static_rate() - (2/15)*z1 - (17/30)*z2
}

INCLUDE "afferent_encoder.inc"
