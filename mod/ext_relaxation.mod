COMMENT
Model extension "relaxation_rate" (shared/spec/diagnosis.md: the model relaxes slower or faster than the data):
constant factors on the SR pump (re-uptake, eq 4) and on Module 2's time constant tau_A (eq 8).

Equations (units: uptake 1, tauA 1):
    U = uptake Umax (...)^2                       RANGE uptake drives KimCa's uptake_gain port (eq 4 scaled)
    tau_A = tauA C3 / cosh((x - C4)/(2 C5))       RANGE tauA drives KimAct's tauA_gain port (eq 8 scaled)
tauA > 1 slows both the rise and the decay of activation (CT09 twitch at -8 mm, tauA = 2: peak 0.34x,
half-relaxation 41 -> 81 ms).  uptake sets the size of the Ca2+ transient more than its decay: uptake > 1 gives a
smaller, earlier twitch that relaxes a little more slowly from its peak (uptake = 2: peak 0.41x, time to peak
81 -> 66 ms, half-relaxation 41 -> 51 ms), uptake < 1 a larger, later one.  With uptake = tauA = 1 (their
neutral values, the defaults) the unit is bit-identical to the baseline.
Bounds (neuromuscle/model/extensions/relaxation_rate.py): both in [0.3, 3].
Coupling: no spikes, no states; the POINTERs read the two PARAMETERs directly, so a value set between runs (or
during one, from hoc) takes effect at the next step.  O(1): nothing is computed.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtRelaxation
    THREADSAFE
    RANGE uptake, tauA
}

PARAMETER {
    uptake = 1 (1)
    tauA = 1 (1)
}
