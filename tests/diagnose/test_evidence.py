"""The held-out numbers of a candidate (:mod:`neuromuscle.diagnose.evidence`): the chi-square gain and its penalty
stated once, and the score that ranks candidates judged on different splits."""

import numpy as np

from conftest import ar1
from neuromuscle.diagnose.evidence import gather, heldout_chi2_gain
from neuromuscle.diagnose.residuals import noise_level

N = 600


def _forces(rng):
    """Three held-out trials: a model before that misses by a slow bump and a candidate that removes most of it."""
    t = np.linspace(0.0, 3.0, N)
    bump = np.exp(-((t - 1.5) / 0.4) ** 2)
    meas, before, after, noise = {}, {}, {}, {}
    for k in range(3):
        meas[k] = 4.0 * np.sin(t + k) + ar1(rng, N, 0.05, 0.6)
        before[k] = 4.0 * np.sin(t + k) + 0.4 * bump
        after[k] = 4.0 * np.sin(t + k) + 0.05 * bump
        noise[k] = noise_level(meas[k] - 4.0 * np.sin(t + k))
    return list(meas), meas, before, after, noise


def test_the_held_out_chi_square_gain_is_the_one_the_rules_read():
    """heldout_chi2_gain gives gather's dX2 and BIC penalty to the last bit (one statement of the formula), and the
    gain is positive where the candidate removes the misfit, negative the other way round."""
    ids, meas, before, after, noise = _forces(np.random.default_rng(7))
    ev = gather(ids, meas, before, after, noise, 3, [], (0.0, 0.0), None)
    chi2, penalty = heldout_chi2_gain(ids, meas, before, after, noise, 3)
    assert (chi2, penalty) == (ev.chi2_gain, ev.bic_penalty)
    assert chi2 > penalty > 0
    assert heldout_chi2_gain(ids, meas, after, before, noise, 3)[0] == -chi2


def test_a_candidate_judged_on_another_split_is_scored_on_the_steps_own_trials():
    """The score of a candidate judged by cross-validation over trials takes its held-out term from the ranking
    gain (its fit on every calibration trial against the step's model before), not from the cross-validated gain,
    whose model before was fitted without some trials and lost part of its fit: without a ranking gain the score
    is the cross-validated one."""
    ids, meas, before, after, noise = _forces(np.random.default_rng(8))
    worse_before = {k: before[k] + 0.3 for k in ids}  # the model before refitted without the telling trials
    crossed = gather(ids, meas, worse_before, after, noise, 3, [], (40.0, 12.0), None)
    plain = gather(ids, meas, before, after, noise, 3, [], (40.0, 12.0), None)
    assert crossed.chi2_gain > plain.chi2_gain  # the refit's loss would count as the candidate's gain
    unranked = crossed.score
    crossed.ranking_chi2_gain, crossed.ranking_penalty = heldout_chi2_gain(ids, meas, before, after, noise, 3)
    assert crossed.score == plain.score < unranked
    assert crossed.to_json()["ranking_chi2_gain"] == plain.chi2_gain
    assert "scored on the held-out trials alone" in crossed.text()
