TITLE SpindleIa: muscle spindle primary (group Ia) afferent, Prochazka's rate equation

COMMENT
A muscle spindle primary ending (group Ia afferent): the rate equation Prochazka & Gorassini fitted to the ensemble
firing of cat hamstring spindle primaries during walking (1998, J Physiol 507:277-291), restated by Prochazka (1999,
Quantifying proprioception, Prog Brain Res 123:133-142): a power law of the stretch velocity plus terms in the
stretch, a fusimotor drive that follows the muscle's activation, and a constant:

    rate = kv sgn(v) (|v|/vref)^0.6 + kd (d/dref) + ke fus + r0          (/s)

v = vm (mm/s, positive = lengthening), d = xm - xref (mm, the stretch from the reference length xref), fus (1):
the EMG-like fusimotor drive in % of maximal activation.  Defaults: kv = 4.3 /s, kd = 2 /s per mm, r0 = 82 /s
(Prochazka & Gorassini 1998: v in mm/s, d in mm; their fit of nine hamstring primaries over 132 step cycles
predicted the ensemble rate with r.m.s. errors below 14 % of its modulation depth); vref = dref = 1 (mm/s, mm)
carry the units of the fit.  ke = 0.5 /s per %: the fusimotor term of the spinal circuit model of Moraud et al.
(2016, Neuron 89:814-828; ModelDB 189786), 50 /s at maximal normalised EMG (that model pairs it with a constant
of 50 /s); the EMG coefficient of the 1998 fit itself was not found.  A shortening muscle (v < 0) lowers the
rate symmetrically; the rate is held at 0 or above (afferent_encoder.inc).

Coupling: POINTER xm -> muscle length (mm) of a MuscleLength point process; POINTER vm -> its velocity (mm/s).
Spikes: the shared encoder (afferent_encoder.inc) integrates the rate to threshold and calls net_event; a NetCon
from this point process (or ParallelContext.cell) carries them to the motoneurons.  Deterministic: no random
numbers; phase0 (1) staggers afferents that read the same length.
ENDCOMMENT

NEURON {
    POINT_PROCESS SpindleIa
    THREADSAFE
    POINTER xm, vm
    RANGE kv, vref, kd, dref, ke, fus, r0, xref, sample_ms, max_rate, phase0, rate, phase
}

PARAMETER {
    kv = 4.3 (/s)
    vref = 1 (mm/s)
    kd = 2 (/s)
    dref = 1 (mm)
    ke = 0.5 (/s)
    fus = 0 (1)
    r0 = 82 (/s)
    xref = -8 (mm)
}

ASSIGNED {
    xm (mm)
    vm (mm/s)
}

FUNCTION rate_now() (/s) {
    LOCAL p
    if (vm >= 0) {
        p = pow(vm/vref, 0.6)
    } else {
        p = -pow(-vm/vref, 0.6)
    }
    rate_now = kv*p + kd*(xm - xref)/dref + ke*fus + r0
}

PROCEDURE receptor_initial() {
    : no state of its own
}

INCLUDE "afferent_encoder.inc"
