"""neuromuscle: the three-module muscle of Kim, Sandercock & Heckman 2015 inside NEURON."""

from ._version import __version__
from .errors import InputError, MechanismBuildError, NeuromuscleError, NumericalError
from .model import hatze_contraction, hatze_excitation, kim_contraction, kim_excitation
from .model.mechanisms import load_mechanisms, mechanism_hash
from .parameters import ParameterSet, load_parameters
from .protocols import LengthTrace
from .sim import MuscleUnit, SimulationResult, Simulator, simulate

__all__ = ["InputError", "LengthTrace", "MechanismBuildError", "MuscleUnit", "NeuromuscleError",
           "NumericalError", "ParameterSet", "SimulationResult", "Simulator", "hatze_contraction",
           "hatze_excitation", "kim_contraction", "kim_excitation", "load_mechanisms", "load_parameters",
           "mechanism_hash", "simulate", "__version__"]
