TITLE Model extension movement_induced_depression: Ca2+ sensitivity falling on a movement clock

COMMENT
Model extension "movement_induced_depression" (a cause of the diagnosis catalogue: force sinks progressively during movement
at low rates): the Ca2+ sensitivity of activation falls on the eq 19 time course of Kim, Sandercock & Heckman 2015, on a movement clock that
runs while the muscle moves and runs down at rest.
    eq 19 (Kim et al. 2015):  alpha(t) = alpha + alpha1 (1 + tanh((t - alpha2)/alpha3)),  t on a movement clock
Two departures from eq 19, each measured on the diagnosis suite (docs/reference/extensions.md):
  - the clock.  The paper's clock counts the time since the movement onset and never stops, so its depression deepens
    through every hold that follows a movement (the authors' own code applied eq 19 only while the length was
    accelerating: docs/reference/kim2015.md).  Here c (ms) counts time spent moving, at a rate that saturates
    with speed, and decays at rest with a fitted time constant trec;
  - what falls.  A rising exponent (A = Atil^alpha(t)) also speeds the relaxation after the last stimulus, where
    Atil decays (A/Atil^alpha = Atil^(alpha(t) - alpha) -> 0): fitted to movement data it left the end of every
    moving train ~2-3 noise sd too low.  Here the half-activation point of eq 8 moves up, C1 -> C1 + shift (KimAct's
    C1_shift port): the same less force at low rates (low [CaSPT]/T0) and little in a fused tetanus, without
    reshaping relaxation.
Equations (t ms):
    m      = Vm^2 / (Vm^2 + v0^2)                        (1: -> 1 well above v0, exactly 0 when the length is held)
    dc/dt  = m - (1 - m) c / trec                        (c = 0 before any movement)
    D      = (tanh((c - t50)/width) - tanh(-t50/width)) / (1 - tanh(-t50/width))     (1: 0 at c = 0, -> 1)
    shift  = k D        -> KimAct: Atil_inf = 0.5 (1 + tanh((x - C1 - shift)/C2))
D is exactly 0 before the first movement and in isometric trials, so no onset is needed and nothing jumps (CVODE
sees continuous rates).  Moving steadily at Vm the clock runs at m ms/ms (1 ms/ms, as the paper's clock, well above
v0) towards its ceiling (Vm/v0)^2 trec: a slow movement depresses later and less than a fast one; held still, c
decays as exp(-t/trec) and the depression recovers.
synth's hidden movement effect (docs/guide/synth.md) is a loss of Ca2+ release, 1 - a m, with m a saturating state
driven by the distance moved (|v|/20 mm) that recovers with 2 s: a different mechanism (SR release, Module 1; here
the myofilaments' sensitivity, Module 2) and a different form (driven by distance, not by time spent moving through
a sigmoid).
Units: k 1 (normalised [CaSPT], as C1 and C2); t50, width, trec, c ms; v0, Vm mm/s; shift, D, m 1.
Bounds (neuromuscle/model/extensions/movement_induced_depression.py): k [0, 0.5], t50 [0, 5000] ms, width
[1, 5000] ms (eq 19's alpha2, alpha3 bounds), trec [20, 1e5] ms, v0 [0.5, 50] mm/s.  Neutral: k = 0 (shift exactly
0: the unit is bit-identical to the baseline).
Coupling: POINTER vm -> MuscleLength's velocity (mm/s).  Exposes RANGE shift (1) for POINTER KimAct.C1_shift, D
and m.
Numerics: c' is linear in c with Vm frozen over the step: METHOD cnexp (exact then) in fixed step; CVODE
integrates the same DERIVATIVE.  shift is computed after c's update (the step's end value), before KimAct reads it
(Ext* mechanisms are registered before kim_m*: their file names sort first).  O(1) per step, THREADSAFE.
ENDCOMMENT

NEURON {
    POINT_PROCESS ExtMovement
    THREADSAFE
    RANGE k, t50, width, trec, v0, shift, D, m
    POINTER vm
}

PARAMETER {
    k = 0.05 (1)
    t50 = 400 (ms)
    width = 160 (ms)
    trec = 1000 (ms)
    v0 = 5 (mm/s)
}

ASSIGNED {
    vm (mm/s)
    shift (1)
    D (1)
    m (1)
    q (/ms)
}

STATE {
    c (ms)
}

INITIAL {
    c = 0
    drive()
    output()
}

BREAKPOINT {
    SOLVE states METHOD cnexp
}

DERIVATIVE states {
    drive()
    c' = m - c*q
    output()
}

PROCEDURE drive() {
    : m and (1 - m)/trec written without a subtraction: q > 0 for every finite Vm (cnexp divides by it)
    LOCAL v2, r2
    UNITSOFF
    v2 = vm*vm
    r2 = v0*v0
    m = v2/(v2 + r2)
    q = r2/(v2 + r2)/trec
    UNITSON
}

PROCEDURE output() {
    LOCAL h0
    h0 = tanh(-t50/width)
    D = (tanh((c - t50)/width) - h0)/(1 - h0)
    shift = k*D
}
