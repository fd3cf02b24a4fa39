"""Across contraction levels: a calibration carried to its own trial reproduces that trial's prediction exactly;
carried to another level it predicts the target's whole trial, the human units through the thresholds (% MVC)."""

import numpy as np
import pytest

from neuromuscle.analysis.metrics import nrmse_percent
from neuromuscle.pool.cross_level import pool_transfer_nrmse, transfer_nrmse, transferred_predictions
from neuromuscle.pool.discharge_force import fit_both, read_discharges
from neuromuscle.pool.unrecorded_units import complete_pool, fit_completed_pool, transferred_pool_force


@pytest.fixture(scope="module")
def two_levels(tmp_path_factory, small_caillet):
    d = tmp_path_factory.mktemp("levels")
    high = read_discharges(small_caillet(d / "X_30.mat", seed=2)).trial()
    low = read_discharges(small_caillet(d / "X_21.mat", seed=5, top=0.7)).trial()
    return fit_both(high, dt_ms=0.1), fit_both(low, dt_ms=0.1)


def test_carried_to_its_own_trial_it_is_the_trial_fit(two_levels):
    high, _ = two_levels
    human, twitch = transferred_predictions(high, high)
    assert np.allclose(human, high.human.predicted) and np.allclose(twitch, high.reference.predicted)
    scores = transfer_nrmse(high, high)
    assert scores["human_units"] == pytest.approx(scores["human_units_own"])


def test_carried_to_another_level_it_uses_the_targets_thresholds(two_levels):
    high, low = two_levels
    assert low.thresholds_percent_mvc.max() < 0.9 * high.thresholds_percent_mvc.max() + 1.0
    human, twitch = transferred_predictions(high, low)
    assert human.shape == twitch.shape == low.recorded.shape
    scores = transfer_nrmse(high, low)
    assert scores["human_units"] == pytest.approx(nrmse_percent(low.recorded, human))
    # the transferred prediction is a prediction: it follows the target's contraction, not a copy of the source's
    assert np.corrcoef(human, low.recorded)[0, 1] > 0.8


def test_whole_trial_fit_reuses_the_bases_and_has_no_held_out_time(two_levels):
    high, low = two_levels
    whole = fit_both(high.trial, calibration_fraction=1.0, bases=high.bases)
    assert whole.bases is high.bases
    assert whole.human.nrmse_heldout_percent == whole.human.nrmse_calibration_percent
    assert whole.human.calibration_ms[1] > high.trial.duration_ms
    # fitted on all of it, it describes its own trial at least as well as the first-half fit does
    assert whole.human.nrmse_calibration_percent <= nrmse_percent(high.recorded, high.human.predicted) + 1e-6
    assert transfer_nrmse(whole, low)["human_units"] > 0.0


def test_completed_pool_carries_its_fit_and_completes_the_target_from_its_own_discharges(two_levels):
    high, low = two_levels
    pools = {}
    for k, f in (("high", high), ("low", low)):
        pool = complete_pool(f.trial, f.thresholds_percent_mvc, f.bases, until_ms=f.human.calibration_ms[1],
                             dt_ms=0.1)
        pools[k] = pool, fit_completed_pool(pool, f.recorded, calibration_ms=f.human.calibration_ms,
                                            heldout_ms=f.human.heldout_ms)
    own = pool_transfer_nrmse(pools["high"][1], pools["high"][0], high.recorded, pools["high"][1])
    assert own["completed_pool"] == pytest.approx(own["completed_pool_own"])
    s = pool_transfer_nrmse(pools["high"][1], pools["low"][0], low.recorded, pools["low"][1])
    assert s["completed_pool"] == pytest.approx(nrmse_percent(low.recorded, transferred_pool_force(
        pools["high"][1], pools["low"][0])))
    # the lower trial recruits fewer of the pool's units
    assert pools["low"][0].n_unrecorded < pools["high"][0].n_unrecorded
