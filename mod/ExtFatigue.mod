TITLE Model extension fatigue: depletion of the releasable Ca2+ and of the force capacity over long high-rate trains

COMMENT
Model extension "fatigue" (a cause of the diagnosis catalogue: force declines over long high-rate trains): a slow
depletion, as a state D (1) that every spike raises and that recovers exponentially, of the releasable Ca2+ and of
the force the cross-bridges make at a given activation (Allen, Lamb & Westerblad 2008).

Equations (units: k 1 per spike, tau_rec ms, kc 1, t ms):
    dD/dt = -D / tau_rec                          between spikes
    D -> D + w k (1 - D)                          at a spike of NetCon weight w (1 for one spike)
    gain = 1 - D                                  drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
    cgain = 1 - kc D                              drives KimForce's capacity_gain port: Fc = P0 g(Xm) A cgain
With k = 0 (its neutral value) D stays 0 and both gains are exactly 1: the unit is bit-identical to the baseline.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain and
RANGE cgain (1) for POINTER KimForce.capacity_gain.  A spike reaching KimCa and this mechanism at the same t: KimCa
and KimForce read the gains only in their next state update, after both events are delivered, so the order of
delivery does not matter.
Numerics: linear decay, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same DERIVATIVE;
the jump is an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtFatigue
    THREADSAFE
    RANGE k, tau_rec, kc, gain, cgain
}

PARAMETER {
    k = 0.01 (1)
    tau_rec = 10000 (ms)
    kc = 0.5 (1)
}

ASSIGNED {
    gain (1)
    cgain (1)
}

STATE {
    D (1)
}

INITIAL {
    D = 0
    gain = 1
    cgain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    D' = -D/tau_rec
    gain = 1 - D
    cgain = 1 - kc*D
}

NET_RECEIVE(w (1)) {
    D = D + w*k*(1 - D)
    gain = 1 - D
    cgain = 1 - kc*D
}
