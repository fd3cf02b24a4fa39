"""Building and running simulations: the MuscleUnit (components wired with a parameter set), the Simulator
(NEURON's integrator settings, set and restored), recordings by name, results with provenance, ``simulate`` for one
unit, ``simulate_batch`` for one protocol under several parameter sets in one run and ``simulate_protocols`` for
several protocols in one run."""

from .recordings import Recorder
from .results import SimulationResult, load_result, save_result
from .run import default_recordings, simulate, simulate_batch, simulate_protocols
from .simulator import MAX_DIFFERENCE_DT_MS, MAX_DT_MS, Simulator
from .unit import CONTRACTIONS, EXCITATIONS, MuscleUnit

__all__ = ["CONTRACTIONS", "EXCITATIONS", "MAX_DIFFERENCE_DT_MS", "MAX_DT_MS", "MuscleUnit", "Recorder",
           "SimulationResult", "Simulator", "default_recordings", "load_result", "save_result", "simulate",
           "simulate_batch", "simulate_protocols"]
