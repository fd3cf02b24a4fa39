TITLE A current clamp whose amplitude is shared by every instance

COMMENT
A current clamp whose amplitude is one value shared by every instance: i = gain * amp (nA), with amp a GLOBAL.
A pool's common current is then one Vector.play (into amp) instead of one per motoneuron, and each clamp costs
one multiplication per step.  gain (1) scales a cell's share.  Units: nA.
ENDCOMMENT

NEURON {
    POINT_PROCESS CommonClamp
    THREADSAFE
    ELECTRODE_CURRENT i
    GLOBAL amp
    RANGE gain, i
}

UNITS {
    (nA) = (nanoamp)
}

PARAMETER {
    amp = 0 (nA)
    gain = 1 (1)
}

ASSIGNED {
    i (nA)
}

BREAKPOINT {
    i = gain * amp
}
