"""Fit parameters of the three-module muscle to measured trials (the sum of squared force errors, eq 5
of van Zandwijk et al. 1998).

Reads like the experiment::

    data = read_measured("cat_soleus.h5")
    problem = FitProblem(list(data.trials.values()), base=load_parameters("CT09"), free=["C1", "C3"])
    result = fit(problem, workers=2, checkpoint="fit.json")
    result.parameters.save("fitted.json"); result.summary()

Modules, one decision each: ``problem`` (what to fit), ``evaluate`` (a trial's simulation; serial == parallel
map), ``transforms`` (search space and default bounds), ``objectives`` (sse / nrmse), ``optimizers``
(trust region, PRAXIS, Levenberg-Marquardt), ``uncertainty`` (intervals and identifiability, shared with the
Hatze twitch fit), ``intervals`` (the fit's interval methods: HAC covariance, integrator error),
``checkpoint`` (progress, checkpoint, resume), ``run`` (``fit`` and ``FitResult``).  The simulation of a measured
trial and the synthetic trials are :mod:`neuromuscle.measured.simulation`'s (exported here too).
"""

from ..measured.simulation import ar1_noise, synthetic_trial, trial_simulation
from .checkpoint import CHECKPOINT_SCHEMA, read_checkpoint
from .evaluate import SimulationOptions
from .intervals import INTERVAL_METHODS, fit_uncertainty
from .objectives import OBJECTIVES
from .optimizers import LMResult, levenberg_marquardt
from .problem import FitProblem
from .run import METHODS, FitResult, fit
from .uncertainty import COVARIANCES, Rules, Uncertainty, describe_method, estimate_uncertainty

__all__ = ["CHECKPOINT_SCHEMA", "COVARIANCES", "INTERVAL_METHODS", "METHODS", "OBJECTIVES", "FitProblem",
           "FitResult", "LMResult", "Rules", "SimulationOptions", "Uncertainty", "ar1_noise", "describe_method",
           "estimate_uncertainty", "fit", "fit_uncertainty", "levenberg_marquardt", "read_checkpoint",
           "synthetic_trial", "trial_simulation"]
