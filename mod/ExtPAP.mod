TITLE Model extension post_activation_potentiation: release and tau_A raised after high-rate activity

COMMENT
Model extension "post_activation_potentiation" (a cause of the diagnosis catalogue: after activity, twitches grow and
relaxation slows): one slow potentiation state P (1) that high-rate activity raises and that decays over tens of
seconds; it raises the Ca2+ release and lengthens Module 2's time constant tau_A.  Potentiation (myosin light
chain phosphorylation by Ca2+-calmodulin-dependent kinase) needs Ca2+ that stays high: a conditioning tetanus
produces it, isolated twitches and low-rate trains hardly do.  So a spike raises P in proportion to a fast trace F
(1) that the previous spikes left: F = exp(-ISI/tau_f) after one spike, so the increment falls off exponentially
with the interval before the spike and a lone spike adds nothing.
Equations (units: k_rel 1, k_tau 1, u 1 per spike, tau ms, tau_f ms, t ms):
    dP/dt = -P / tau,   dF/dt = -F / tau_f        between spikes
    at a spike of NetCon weight w (1 for one spike), in this order:
        P -> P + w u F (1 - P)                    F as the previous spikes left it
        F -> F + w (1 - F)
    gain = 1 + k_rel P                            drives KimCa's release_gain port: R = gain [CaSR] Rmax (S2 - S12)
    tgain = 1 + k_tau P                           drives KimAct's tauA_gain port: tau_A = tgain C3 / cosh(...)
P and F stay in [0, 1).  With k_rel = k_tau = 0 (their neutral values) both gains are exactly 1: the unit is
bit-identical to the baseline.
The build per spike is rate-selective: an extension that every spike built whatever the interval would
potentiate low-rate trains as much as a tetanus.  synth's hidden form is a sixth-order
Hill function of the interval, summed with a 40 s leak and saturated exponentially (docs/guide/synth.md).
Bounds (neuromuscle/model/extensions/post_activation_potentiation.py): k_rel in [0, 2], k_tau in [0, 1.5],
u in [0.001, 0.5], tau in [5, 600] s, tau_f in [2, 100] ms.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.release_gain and
RANGE tgain (1) for POINTER KimAct.tauA_gain.  Both mechanisms read their port only in their next state update,
after every event at the same t is delivered, so the order of delivery does not matter.
Numerics: linear decays, METHOD cnexp is exact between spikes in fixed step; CVODE integrates the same DERIVATIVE;
the jumps are an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtPAP
    THREADSAFE
    RANGE k_rel, k_tau, u, tau, tau_f, gain, tgain
}

PARAMETER {
    k_rel = 0.5 (1)
    k_tau = 0.3 (1)
    u = 0.05 (1)
    tau = 60000 (ms)
    tau_f = 20 (ms)
}

ASSIGNED {
    gain (1)
    tgain (1)
}

STATE {
    P (1)
    F (1)
}

INITIAL {
    P = 0
    F = 0
    gain = 1
    tgain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    P' = -P/tau
    F' = -F/tau_f
    gain = 1 + k_rel*P
    tgain = 1 + k_tau*P
}

NET_RECEIVE(w (1)) {
    P = P + w*u*F*(1 - P)
    F = F + w*(1 - F)
    gain = 1 + k_rel*P
    tgain = 1 + k_tau*P
}
