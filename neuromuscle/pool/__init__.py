"""Motoneuron pools: reduced motoneurons (S, FR, FF), their muscle units, drives, recordings, MPI runs, results
(HDF5 and NWB)."""

from .definition import PoolDefinition, UnitSpec
from .drives import Drive
from .motoneuron import Motoneuron, MotoneuronParameters, MotoneuronProfile, motoneuron_parameters, motoneuron_profile
from .nwb import read_pool_nwb, write_pool_nwb
from .pool import Pool
from .recording import Recording
from .result import PoolResult, load_pool_result
from .units import TWITCH_SPEED, p0_spread_N, unit_muscle_parameters

__all__ = ["Drive", "Motoneuron", "MotoneuronParameters", "MotoneuronProfile", "Pool", "PoolDefinition", "PoolResult",
           "Recording", "TWITCH_SPEED", "UnitSpec", "load_pool_result", "motoneuron_parameters", "motoneuron_profile",
           "p0_spread_N",
           "read_pool_nwb", "unit_muscle_parameters", "write_pool_nwb"]
