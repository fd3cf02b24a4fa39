TITLE Model extension relaxation_rate: the SR pump's speed changing with recent activity

COMMENT
Model extension "relaxation_rate" (a cause of the diagnosis catalogue: the model relaxes slower or faster than the data; the
re-uptake adjustment): the SR pump (eq 4) changes its speed with recent activity.  An activity state X (1) is 0 at
rest, every spike raises it by the fraction d of what is left to 1, and it decays with time constant tau; the pump
is multiplied by 1 - k X.  So the pump at rest, and in the late relaxation of a lone twitch, is the model's own
(Umax keeps its meaning), and k > 0 is Ca2+ removal slowed by recent activity (relaxation after a tetanus slower
than the model's: parvalbumin saturating and the SR loading in fast muscle), k < 0 removal sped up by it.

Equations (units: k 1, tau ms, d 1, t ms):
    dX/dt = -X / tau                              between spikes; X = 0 at rest (INITIAL: long since a spike)
    X -> X + d w (1 - X)                          at a spike of NetCon weight w (1 per spike)
    gain = 1 - k X                                drives KimCa's uptake_gain port: U = gain Umax (...)^2
With d = 1 every spike sets X to 1 and the pump's course after a tetanus is that after a twitch: a pump changed
early after each spike and back to the model's late in the relaxation.  With d < 1 a lone twitch raises X only to
d and a high-rate train towards 1, so the change grows with the recent spike count and outlasts a train by ~tau:
no constant Module 1 parameter gives that (a constant factor on the pump is Umax).  After one spike at t0,
X = d exp(-(t - t0)/tau).  synth's hidden relaxation effect is another form: the pump divided by 1 + a L, L a
first-order Hill function of a leaky spike count (docs/guide/synth.md).
The pump at rest is the model's own (Umax keeps its meaning), and a constant factor on the pump or on tau_A would be
calibration, not a cause (Umax; Module 2's C3).
With k = 0 (its neutral value) gain is exactly 1: the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/relaxation_rate.py): k in [-2, 0.95], tau in [5, 500] ms, d in [0.02, 1].
Coupling: receives the unit's spikes (NET_RECEIVE); exposes RANGE gain (1) for POINTER KimCa.uptake_gain.  KimCa
reads the gain only in its next state update, after every event of that time is delivered.
Numerics: linear decay, METHOD cnexp exact between spikes in fixed step; CVODE integrates the same DERIVATIVE; the
jump is an event.  O(1) per step whatever the spike count.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtRelaxation
    THREADSAFE
    RANGE k, tau, d, gain
}

PARAMETER {
    k = 0.3 (1)
    tau = 300 (ms)
    d = 0.1 (1)
}

ASSIGNED {
    gain (1)
}

STATE {
    X (1)
}

INITIAL {
    X = 0
    gain = 1
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    X' = -X/tau
    gain = 1 - k*X
}

NET_RECEIVE(w (1)) {
    X = X + d*w*(1 - X)
    gain = 1 - k*X
}
