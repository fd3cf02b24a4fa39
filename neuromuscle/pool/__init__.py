"""Motoneuron pools: reduced motoneurons (S, FR, FF), their muscle units, drives, MPI runs, results."""

from .definition import PoolDefinition, UnitSpec
from .motoneuron import Motoneuron, MotoneuronParameters, motoneuron_parameters
from .pool import Pool
from .result import PoolResult, load_pool_result
from .units import TWITCH_SPEED, p0_spread_N, unit_muscle_parameters

__all__ = ["Motoneuron", "MotoneuronParameters", "Pool", "PoolDefinition", "PoolResult", "TWITCH_SPEED",
           "UnitSpec", "load_pool_result", "motoneuron_parameters", "p0_spread_N", "unit_muscle_parameters"]
