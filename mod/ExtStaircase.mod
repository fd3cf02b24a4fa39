TITLE Model extension staircase: twitch amplitude changing over successive stimuli at low rates

COMMENT
Model extension "staircase" (a cause of the diagnosis catalogue: twitch amplitude changes over successive stimuli at low
rates, negative or positive): a slow state S (1) that spikes at low rates build up and that decays between
spikes, scaling the Ca2+ release by 1 + k S.  The sign of k gives a positive (k > 0) or a negative (k < 0)
staircase.  A spike builds S in proportion to (1 - F)^3, F (1) a fast trace of the earlier spikes: F =
exp(-ISI/tau_f) after one spike, so a spike that follows its predecessor closely (a tetanus) adds next to nothing
and one after a long interval (a low-rate train) adds u.  The staircase is the catalogue's low-rate cause;
potentiation by high-rate firing is post_activation_potentiation's (mod/ExtPAP.mod, whose build-up is the
counterpart, u F).

Equations (units: k 1, u 1 per spike, tau ms, tau_f ms, t ms):
    dS/dt = -S / tau,   dF/dt = -F / tau_f        between spikes
    at a spike of NetCon weight w (1 for one spike), in this order:
        S -> S + w u (1 - F)^3 (1 - S)            F as the previous spikes left it
        F -> F + w (1 - F)
    gain = 1 + k S                                drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
S and F stay in [0, 1).  A train at period T >> tau_f settles at S = u / (1 - (1 - u) exp(-T/tau)) just after
each spike: the staircase saturates at gain 1 + k for tau_f << T << tau and vanishes for T >> tau and for
T << tau_f.  The cube makes the interval gate steep: at tau_f = 40 ms (the lower bound) a 100 Hz interval builds
1 % of a lone spike's u, a 20 Hz one 36 % and a 10 Hz one 77 %.  A shallower gate would let a fit make the
staircase a potentiation built by tetani (post_activation_potentiation's), and one that every spike passed would
raise the release of unfused 20-40 Hz trains, where force follows release closely.
With k = 0 (its neutral value) gain is exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/staircase.py): k in [-0.6, 1], u in [0.005, 0.5], tau in [0.5, 120] s,
tau_f in [40, 200] ms.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain.  A
spike reaching KimCa and this mechanism at the same t: KimCa reads gain only in its next state update, after
both events are delivered, so the order of delivery does not matter.
Numerics: linear decay, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same DERIVATIVE;
the jumps are an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtStaircase
    THREADSAFE
    RANGE k, u, tau, tau_f, gain
}

PARAMETER {
    k = 0.3 (1)
    u = 0.05 (1)
    tau = 5000 (ms)
    tau_f = 60 (ms)
}

ASSIGNED {
    gain (1)
}

STATE {
    S (1)
    F (1)
}

INITIAL {
    S = 0
    F = 0
    gain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    S' = -S/tau
    F' = -F/tau_f
    gain = 1 + k*S
}

NET_RECEIVE(w (1)) {
    S = S + w*u*(1 - F)*(1 - F)*(1 - F)*(1 - S)
    F = F + w*(1 - F)
    gain = 1 + k*S
}
