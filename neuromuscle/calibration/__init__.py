"""Staged calibration of the three-module muscle (Kim et al. 2015, section 2.2.2), each stage usable
alone.

Modules: ``module3`` (KSE, force-length, force-velocity), ``module2`` (C1..C5, alpha by a fit), ``length_compensation``
(phi1..phi4), ``staged`` (the paper's order on one data file), ``stage`` (what a stage returns), ``trials``
(which trials a stage uses), ``examples`` (Module 3 on published cat soleus data).
"""

from .examples import real_data_calibration
from .length_compensation import calibrate_length_compensation, twitch_trials
from .module2 import MODULE2_FREE, calibrate_module2, module2_trials
from .module3 import (calibrate_force_length, calibrate_force_velocity, calibrate_kse, gaussian_force_length,
                      hill_tension, mashima_tension)
from .stage import StageResult
from .staged import FORCE_LENGTH_PATH, FORCE_VELOCITY_PATH, StagedCalibration, staged_calibration
from .trials import OPTIMUM_TOLERANCE_MM

__all__ = ["FORCE_LENGTH_PATH", "FORCE_VELOCITY_PATH", "MODULE2_FREE", "OPTIMUM_TOLERANCE_MM", "StageResult",
           "StagedCalibration", "calibrate_force_length", "calibrate_force_velocity", "calibrate_kse",
           "calibrate_length_compensation", "calibrate_module2", "gaussian_force_length", "hill_tension",
           "mashima_tension", "module2_trials", "real_data_calibration", "staged_calibration", "twitch_trials"]
