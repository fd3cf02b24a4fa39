TITLE PortCombine: two modulation signals combined into one port

COMMENT
Combines two model extensions that drive the same modulation port of a muscle mechanism (for instance a
staircase and fatigue, both scaling KimCa's Ca2+ release), so that several causes can act in one unit:

    out = a * b     when mode = 0 (gains: release_gain, uptake_gain, tauA_gain; 1 is neutral)
    out = a + b     when mode = 1 (offsets: KimForce's force_offset in N; 0 is neutral)

a and b are POINTERs to the extensions' RANGE outputs; the port's POINTER points at out.  More than two are
combined by chaining.  out is evaluated once per step, with the other mechanisms' state updates; depending on
the order of the mechanisms it carries the inputs of this step or of the previous one: a lag of at most one time
step in a modulation that changes over milliseconds to seconds.  The unit's Python
wiring (neuromuscle.model.unit) inserts one only where two extensions share a port; a unit with one extension per
port has none, and its traces are unchanged.
ENDCOMMENT

NEURON {
    POINT_PROCESS PortCombine
    THREADSAFE
    RANGE mode, out
    POINTER a, b
}

PARAMETER {
    mode = 0 (1)
}

ASSIGNED {
    a (1)
    b (1)
    out (1)
}

INITIAL {
    : the inputs' own INITIAL blocks may run after this one: start from the neutral value, as every extension
    : starts at rest
    if (mode == 0) {
        out = 1
    } else {
        out = 0
    }
}

BREAKPOINT {
    combine()
}

PROCEDURE combine() {
    if (mode == 0) {
        out = a * b
    } else {
        out = a + b
    }
}
