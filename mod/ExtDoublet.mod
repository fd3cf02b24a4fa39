TITLE Model extension doublet_potentiation: release amplified after short inter-spike intervals

COMMENT
Model extension "doublet_potentiation" (a cause of the diagnosis catalogue: extra force after short inter-spike intervals,
5-15 ms): a fast facilitation F (1) left by each spike for a few ms; a spike that arrives while F is up has its
release amplified, through a held gain H (1) that lasts about as long as one spike's release.

Equations (units: k 1, tau_f ms, tau_h ms, t ms):
    dF/dt = -F / tau_f,   dH/dt = -H / tau_h      between spikes
    at a spike of NetCon weight w (1 for one spike), in this order:
        H -> H + w F (1 - H)                      F as the previous spikes left it (F = exp(-ISI/tau_f) after one)
        F -> F + w (1 - F)
    gain = 1 + k H                                drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
A single spike finds F = 0 and leaves H, hence the twitch, exactly unchanged (after a long interval F ~ 0): only
short intervals potentiate, by a factor that falls off as exp(-ISI/tau_f); H and F stay in [0, 1), gain in
[1, 1 + k).  With k = 0 (its neutral value) gain is exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/doublet_potentiation.py): k in [0, 4], tau_f in [2, 30] ms, tau_h in
[5, 500] ms.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain.  A
spike reaching KimCa and this mechanism at the same t: KimCa reads gain only in its next state update, after
both events are delivered, so the order of delivery does not matter.
Numerics: linear decays, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same
DERIVATIVE; the jumps are an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtDoublet
    THREADSAFE
    RANGE k, tau_f, tau_h, gain
}

PARAMETER {
    k = 1 (1)
    tau_f = 8 (ms)
    tau_h = 25 (ms)
}

ASSIGNED {
    gain (1)
}

STATE {
    F (1)
    H (1)
}

INITIAL {
    F = 0
    H = 0
    gain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    F' = -F/tau_f
    H' = -H/tau_h
    gain = 1 + k*H
}

NET_RECEIVE(w (1)) {
    H = H + w*F*(1 - H)
    F = F + w*(1 - F)
    gain = 1 + k*H
}
