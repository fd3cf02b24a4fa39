"""neuromuscle: the three-module muscle of Kim, Sandercock & Heckman 2015 inside NEURON."""

from .errors import InputError, MechanismBuildError, NeuromuscleError, NumericalError
from .model import MuscleUnit, hatze_contraction, hatze_excitation, kim_contraction, kim_excitation
from .model.mechanisms import load_mechanisms, mechanism_hash
from .parameters import ParameterSet, load_parameters
from .protocols import LengthTrace
from .sim import SimulationResult, Simulator, simulate

__version__ = "0.1.0"

__all__ = ["InputError", "LengthTrace", "MechanismBuildError", "MuscleUnit", "NeuromuscleError",
           "NumericalError", "ParameterSet", "SimulationResult", "Simulator", "hatze_contraction",
           "hatze_excitation", "kim_contraction", "kim_excitation", "load_mechanisms", "load_parameters",
           "mechanism_hash", "simulate", "__version__"]
