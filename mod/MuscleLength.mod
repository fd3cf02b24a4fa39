TITLE Muscle length and velocity input shared by the muscle mechanisms of one muscle

COMMENT
Muscle length input shared by the muscle mechanisms of one muscle (Kim, Sandercock & Heckman 2015, Module 3's input).

RANGE xm (mm): muscle length relative to the physiological maximum (0 mm); negative is shorter.
RANGE vm (mm/s): its velocity, positive = lengthening.
Both are driven by NEURON's own means: Vector.play(ml._ref_xm, tvec, 1) (continuous), or set directly for an
isometric trial.  Mechanisms read them through POINTERs (KimCa.xm, KimAct.xm/vm, KimForce.xm).
No states, no current: it costs nothing per step beyond the play.
ENDCOMMENT

NEURON {
    POINT_PROCESS MuscleLength
    THREADSAFE
    RANGE xm, vm
}

PARAMETER {
    xm = -8 (mm)
    vm = 0 (mm/s)
}
