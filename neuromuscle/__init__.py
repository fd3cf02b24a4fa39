"""neuromuscle: the three-module muscle of Kim, Sandercock & Heckman 2015 inside NEURON."""

from .errors import InputError, MechanismBuildError, NeuromuscleError, NumericalError
from .length import LengthTrace
from .mechanisms import load_mechanisms, mechanism_hash
from .parameters import ParameterSet, load_parameters
from .unit import MuscleUnit, SimulationResult, simulate

__version__ = "0.1.0"

__all__ = ["InputError", "LengthTrace", "MechanismBuildError", "MuscleUnit", "NeuromuscleError",
           "NumericalError", "ParameterSet", "SimulationResult", "load_mechanisms", "load_parameters",
           "mechanism_hash", "simulate", "__version__"]
