"""What gets built into NEURON: components (one per mechanism), extensions, the mechanism cache.

A MuscleUnit wires the components with a parameter set: ``neuromuscle.sim.unit``."""

from .component import Component, Param, Port, State
from .hatze import HatzeExcitation, HatzeMTC, HatzeTrend, hatze_contraction, hatze_excitation
from .kim import KimActivation, KimCalcium, KimForce, kim_contraction, kim_excitation
from .kim_unit import KimUnit, kim_fused
from .length import MuscleLength
from .mechanisms import load_mechanisms, mechanism_hash

__all__ = ["Component", "HatzeExcitation", "HatzeMTC", "HatzeTrend",
           "KimActivation", "KimCalcium", "KimForce", "KimUnit", "MuscleLength", "Param", "Port", "State",
           "hatze_contraction", "hatze_excitation", "kim_contraction", "kim_excitation", "kim_fused", "load_mechanisms",
           "mechanism_hash"]
