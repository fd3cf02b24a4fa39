COMMENT
Model extension "relaxation_rate" (shared/spec/diagnosis.md: the model relaxes slower or faster than the data; the
re-uptake adjustment): the SR pump (eq 4) changes its speed over the relaxation after each spike.  A state W (1)
is reset to 0 by every spike and recovers towards 1 with time constant tau; the pump is multiplied by 1 + k W.
So k > 0 is a pump that speeds up late after a spike (relaxation faster than the model's once the Ca2+ transient
has peaked), k < 0 one that slows down late; during a fused tetanus W stays near 0 and nothing changes.

Equations (units: k 1, tau ms, t ms):
    dW/dt = (1 - W) / tau                         between spikes; W = 1 at rest (INITIAL: long since a spike)
    W -> (1 - w) W                                at a spike of NetCon weight w (1 for one spike: W -> 0)
    gain = 1 + k W                                drives KimCa's uptake_gain port: U = gain Umax (...)^2
After a single spike at t0, W = 1 - exp(-(t - t0)/tau) (a first-order recovery; synth's hidden relaxation effect
is a third-order Hill function of the time since the last spike, a different form: docs/synth.md).
A constant factor on the pump (this extension's form until stop 21, with a factor on tau_A) recalibrated Module 1:
synth moves every preparation's pump by ~20 %, so it named calibration misfit, and a factor on tau_A is Module 2's
C3, which the reference and every candidate's fit refit anyway.
With k = 0 (its neutral value) gain is exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/relaxation_rate.py): k in [-0.7, 3], tau in [5, 500] ms.
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.uptake_gain.  KimCa
reads the gain only in its next state update, after every event of that time is delivered.
Numerics: linear relaxation, METHOD cnexp exact between spikes in fixed step; CVODE integrates the same
DERIVATIVE; the reset is an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtRelaxation
    THREADSAFE
    RANGE k, tau, gain
}

PARAMETER {
    k = 0.5 (1)
    tau = 50 (ms)
}

ASSIGNED {
    gain (1)
}

STATE {
    W (1)
}

INITIAL {
    W = 1
    gain = 1 + k
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    W' = (1 - W)/tau
    gain = 1 + k*W
}

NET_RECEIVE(w (1)) {
    W = (1 - w)*W
    gain = 1 + k*W
}
