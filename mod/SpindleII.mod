TITLE SpindleII: muscle spindle secondary (group II) afferent, Prochazka's rate equation

COMMENT
A muscle spindle secondary ending (group II afferent): a length receptor, its rate (/s) linear in the stretch with
a fusimotor term and a constant, no velocity term:

    rate = kd (d/dref) + ke fus + r0          (/s)

d = xm - xref (mm, the stretch from the reference length xref), fus (1): the EMG-like fusimotor drive in % of
maximal activation.  Defaults: kd = 13.5 /s per mm, r0 = 80 /s, ke = 0.2 /s per %, dref = 1 mm: the group II
equation of the spinal circuit model of Moraud et al. (2016, Neuron 89:814-828; ModelDB 189786), which builds on
Prochazka's fits (Prochazka 1999, Prog Brain Res 123:133-142): 80 + 13.5 d + 20 EMG with d in mm and EMG
normalised to its maximum (20 /s at maximal activation, 0.2 /s per %).  The rate is held at 0 or above
(afferent_encoder.inc).

Coupling: POINTER xm -> muscle length (mm) of a MuscleLength point process.
Spikes: the shared encoder (afferent_encoder.inc) integrates the rate to threshold and calls net_event.
Deterministic: no random numbers; phase0 (1) staggers afferents that read the same length.
ENDCOMMENT

NEURON {
    POINT_PROCESS SpindleII
    THREADSAFE
    POINTER xm
    RANGE kd, dref, ke, fus, r0, xref, sample_ms, max_rate, phase0, rate, phase
}

PARAMETER {
    kd = 13.5 (/s)
    dref = 1 (mm)
    ke = 0.2 (/s)
    fus = 0 (1)
    r0 = 80 (/s)
    xref = -8 (mm)
}

ASSIGNED {
    xm (mm)
}

FUNCTION rate_now() (/s) {
    rate_now = kd*(xm - xref)/dref + ke*fus + r0
}

PROCEDURE receptor_initial() {
    : no state of its own
}

INCLUDE "afferent_encoder.inc"
