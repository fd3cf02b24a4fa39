TITLE TendonOrganIb: Golgi tendon organ (group Ib) afferent, Prochazka's rate equation

COMMENT
A Golgi tendon organ (group Ib afferent): a force receptor in series with the muscle fibres, its rate (/s)
proportional to the force they pull with:

    rate = kf F/fmax + r0          (/s)

F (N): the force of the muscle unit it reads; fmax (N): the force the rate is scaled by (the unit's maximal
force, set from Python).  Defaults: kf = 333 /s, r0 = 0 /s.  The rate is held at 0 or above
(afferent_encoder.inc).  The gain 333 /s is the one quoted for Prochazka's tendon organ model (Prochazka 1999,
Prog Brain Res 123:133-142); no published source of it, nor of its units, was found: treat it as a placeholder.
The published tendon organ rate models checked (Lin & Crago 2002; Mileusnic & Loeb 2006), and why neither replaces
it, are listed in the pools guide (docs/guide/pools.md).
For scale: a soleus tendon organ fires about 314 /s per g of force on its own capsule, about two orders of
magnitude more than per g measured at the tendon (Stephens & Stauffer 1975), and responds to the contraction of
one or two in-series muscle fibres, under 0.1 g (Houk & Henneman 1967, J Neurophysiol 30:466-481).

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
    RANGE kf, fmax, r0, sample_ms, max_rate, phase0, rate, phase
}

PARAMETER {
    kf = 333 (/s)
    fmax = 1 (N)
    r0 = 0 (/s)
}

ASSIGNED {
    F (N)
}

FUNCTION rate_now() (/s) {
    rate_now = kf*F/fmax + r0
}

INCLUDE "afferent_encoder.inc"
