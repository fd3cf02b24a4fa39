COMMENT
Model extension "post_activation_potentiation" (shared/spec/diagnosis.md: after activity, twitches grow and
relaxation slows): one slow potentiation state P (1) that every spike raises (so a tetanus raises it most) and
that decays over tens of seconds; it raises the Ca2+ release and lengthens Module 2's time constant tau_A.

Equations (units: k_rel 1, k_tau 1, u 1 per spike, tau ms, t ms):
    dP/dt = -P / tau                              between spikes
    P -> P + w u (1 - P)                          at a spike of NetCon weight w (1 for one spike); P in [0, 1)
    gain = 1 + k_rel P                            drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
    tgain = 1 + k_tau P                           drives KimAct's tauA_gain port: tau_A = tgain C3 / cosh(...)
With k_rel = k_tau = 0 (their neutral values) both gains are exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/post_activation_potentiation.py): k_rel in [0, 2], k_tau in [0, 1.5],
u in [0.001, 0.2], tau in [5, 600] s.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain and
RANGE tgain (1) for POINTER KimAct.tauA_gain.  Both mechanisms read their port only in their next state update,
after every event at the same t is delivered, so the order of delivery does not matter.
Numerics: linear decay, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same DERIVATIVE;
the jump is an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtPAP
    THREADSAFE
    RANGE k_rel, k_tau, u, tau, gain, tgain
}

PARAMETER {
    k_rel = 0.5 (1)
    k_tau = 0.3 (1)
    u = 0.01 (1)
    tau = 60000 (ms)
}

ASSIGNED {
    gain (1)
    tgain (1)
}

STATE {
    P (1)
}

INITIAL {
    P = 0
    gain = 1
    tgain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    P' = -P/tau
    gain = 1 + k_rel*P
    tgain = 1 + k_tau*P
}

NET_RECEIVE(w (1)) {
    P = P + w*u*(1 - P)
    gain = 1 + k_rel*P
    tgain = 1 + k_tau*P
}
