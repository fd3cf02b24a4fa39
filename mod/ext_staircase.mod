COMMENT
Model extension "staircase" (shared/spec/diagnosis.md: twitch amplitude changes over successive stimuli at low
rates, negative or positive): a slow state S (1) that every spike builds up and that decays between spikes,
scaling the Ca2+ release by 1 + k S.  The sign of k gives a positive (k > 0) or a negative (k < 0) staircase.

Equations (units: k 1, u 1 per spike, tau ms, t ms):
    dS/dt = -S / tau                              between spikes
    S -> S + w u (1 - S)                          at a spike of NetCon weight w (1 for one spike); S in [0, 1)
    gain = 1 + k S                                drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
A train at period T settles at S = u / (1 - (1 - u) exp(-T/tau)) just after each spike: the staircase saturates
at gain 1 + k for T << tau and vanishes for T >> tau (a low-rate effect that rate and history both set).
With k = 0 (its neutral value) gain is exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/staircase.py): k in [-0.6, 1], u in [0.005, 0.5], tau in [0.5, 120] s.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain.  A
spike reaching KimCa and this mechanism at the same t: KimCa reads gain only in its next state update, after
both events are delivered, so the order of delivery does not matter.
Numerics: linear decay, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same DERIVATIVE;
the jump is an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtStaircase
    THREADSAFE
    RANGE k, u, tau, gain
}

PARAMETER {
    k = 0.3 (1)
    u = 0.05 (1)
    tau = 5000 (ms)
}

ASSIGNED {
    gain (1)
}

STATE {
    S (1)
}

INITIAL {
    S = 0
    gain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    S' = -S/tau
    gain = 1 + k*S
}

NET_RECEIVE(w (1)) {
    S = S + w*u*(1 - S)
    gain = 1 + k*S
}
