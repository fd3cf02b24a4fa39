"""Synthetic measured data with a hidden effect (``neuromuscle synth``): the test bed of the diagnosis.

A preparation is the Kim Modules 1-3 (eq 18 and eqs 19-20 off) with every parameter moved from CT09 by its own
log-normal factor, run through a protocol set (``protocols``: extended by default, or standard) in NEURON, with at
most one hidden effect (``effects``: a canonical cause in a form unlike the catalogue's extension, or an
out-of-catalogue artefact) played into the baseline's modulation ports (``play``), plus AR(1) transducer noise
(``dataset``)::

    data = make_dataset("staircase", strength=0.5, seed=3)        # MeasuredData; truth in /synth
    write_dataset("prep.h5", None, 0.0, seed=3)                     # a null preparation
    truth(read_measured("prep.h5"))["parameters"]                   # for tests only

docs/guide/synth.md states every hidden form, its strength range and how it differs from the extension that should
find it.
"""

from .dataset import TRUTH_PATH, cause_names, make_dataset, trial_input, truth, without_truth, write_dataset
from .effects import ALL, CAUSES, OUTSIDE, HiddenEffect, hidden_effect
from .protocols import PROTOCOL_SETS, extended_protocols, protocol_set, standard_protocols

__all__ = ["ALL", "CAUSES", "OUTSIDE", "PROTOCOL_SETS", "TRUTH_PATH", "HiddenEffect", "cause_names",
           "extended_protocols", "hidden_effect", "make_dataset", "protocol_set", "standard_protocols", "trial_input",
           "truth", "without_truth", "write_dataset"]
