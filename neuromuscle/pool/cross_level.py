"""Carrying a calibration across contraction levels: the models fitted on one trial (:func:`.fit_both`) predict the
whole of another trial of the same muscle, with every fitted value (scale and offset included) unchanged.

The human units carry over through the recruitment threshold in % MVC: the target's units take the speed and
force that the source's fit gives their thresholds (each trial's force normalised to its own level, so % MVC is
shared).  The twitch sum carries over through the recruitment rank (its x), which is all it has.  The completed
pool (:mod:`.unrecorded_units`) carries over its fitted speeds, delay and scale; the target's unrecorded units come
from the target's own discharges and the muscle's published pool.  Score: NRMSE (% of
the target's recorded range) over the whole target trial.  Units: ms, % MVC.
"""

from __future__ import annotations

import numpy as np

from ..analysis.metrics import nrmse_percent
from .discharge_force import DischargeFits, recruitment_rank
from .human_units import relative_force
from .twitch_sum import twitch_sum_basis
from .unrecorded_units import CompletedPool, CompletedPoolFit, transferred_pool_force


def transferred_predictions(source: DischargeFits, target: DischargeFits) -> tuple[np.ndarray, np.ndarray]:
    """(human units, twitch sum): the target trial's force (% MVC at ``target.t_ms``) predicted with the source's
    fitted values."""
    h, r = source.human, source.reference
    human = h.scale * relative_force(target.bases, target.thresholds_percent_mvc, h.params) + h.offset
    d = target.trial.discharges_ms
    twitch = r.scale * twitch_sum_basis(d, target.t_ms, recruitment_rank(len(d)), r.rp, r.tl_ms, r.rt,
                                        r.delay_ms) + r.offset
    return human, twitch


def transfer_nrmse(source: DischargeFits, target: DischargeFits) -> dict[str, float]:
    """NRMSE (%) over the whole target trial of both models calibrated on ``source``, and for comparison of the
    target's own fits (which saw its first half)."""
    human, twitch = transferred_predictions(source, target)
    y = target.recorded
    return {"human_units": nrmse_percent(y, human), "twitch_sum": nrmse_percent(y, twitch),
            "human_units_own": nrmse_percent(y, target.human.predicted),
            "twitch_sum_own": nrmse_percent(y, target.reference.predicted)}


def pool_transfer_nrmse(source: CompletedPoolFit, target: CompletedPool, recorded: np.ndarray,
                        own: CompletedPoolFit) -> dict[str, float]:
    """NRMSE (%) over the whole target trial (``recorded``, % MVC at ``target.t_ms``) of the completed pool
    calibrated on ``source``, and of the target's own fit ``own``."""
    return {"completed_pool": nrmse_percent(recorded, transferred_pool_force(source, target)),
            "completed_pool_own": nrmse_percent(recorded, own.predicted)}
