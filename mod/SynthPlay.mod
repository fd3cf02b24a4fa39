TITLE Played modulation for synthetic data (no equations: played values only)

COMMENT
Played modulation for synthetic data (neuromuscle.synth): the hidden effect of a synthetic preparation, computed
beforehand in Python as time series and played into this mechanism's RANGE variables by NEURON's Vector.play
(continuous, linear interpolation between samples), which the baseline mechanisms read through their modulation
ports.  It is NOT a model extension of the catalogue: no equation lives here, only the played values.

RANGE release_gain (1) -> KimCa.release_gain   (release R multiplied by it)
RANGE uptake_gain  (1) -> KimCa.uptake_gain    (pump U multiplied by it)
RANGE tauA_gain    (1) -> KimAct.tauA_gain     (tau_A multiplied by it)
RANGE force_offset (N) -> KimForce.force_offset (added to the output force F)
Units: the gains are dimensionless (1), force_offset in N, the played times in ms.
Neutral values (when nothing is played into one): 1, 1, 1, 0 N.
Numerics: no states, no BREAKPOINT work: the play costs O(1) per step (fixed step and CVODE alike).
ENDCOMMENT

NEURON {
    POINT_PROCESS SynthPlay
    THREADSAFE
    RANGE release_gain, uptake_gain, tauA_gain, force_offset
}

PARAMETER {
    release_gain = 1 (1)
    uptake_gain = 1 (1)
    tauA_gain = 1 (1)
    force_offset = 0 (N)
}
