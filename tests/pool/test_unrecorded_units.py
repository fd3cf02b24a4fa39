"""The unrecorded part of the pool: on a synthetic pool whose every unit follows a known onion-skin rate model, a
sample of it recorded, the completion reads the rate model back from the recruitment instants, recovers the
excitation, the unrecorded units' count, thresholds and discharges, and the fit recovers the force the unrecorded
units made; bad input is refused naming the file and the field."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.discharges import DischargeTrial
from neuromuscle.pool.follow_force import HUMAN_MUSCLES
from neuromuscle.pool.human_units import SpeedBases
from neuromuscle.pool.twitch_sum import unit_twitch_force
from neuromuscle.pool.unrecorded_units import (PUBLISHED_P0_SPREAD, STEP_MS, CompletedPool, RateModel,
                                               complete_pool, excitation, fit_completed_pool, fit_rate_model,
                                               group_thresholds, muscle_of, neighbour_rate, pool_force,
                                               published_p0, recorded_activity,
                                               smoothed_rates, synthetic_discharges, transferred_pool_force,
                                               unrecorded_thresholds)

pytestmark = pytest.mark.heavy(cost_s=40)

TRUTH = RateModel(10.0, 0.1, 0.4, (0.0, 100.0))
DURATION_MS = 17000.0
TA = HUMAN_MUSCLES["TA"]
POOL = TA.thresholds(np.arange(TA.motor_units) / (TA.motor_units - 1))
SPEEDS = (0.5, 1.0, 2.0)


def trapezoid(t_ms: np.ndarray, top: float = 30.0) -> np.ndarray:
    """0 for 1 s, up to ``top`` % MVC in 5 s, 5 s plateau, down in 5 s, 1 s rest."""
    return top * np.interp(t_ms, [0, 1000, 6000, 11000, 16000, 17000], [0, 0, 1, 1, 0, 0])


def twitch_bases(trains, duration_ms, speeds):
    """Unit forces per newton without NEURON: Fuglevand twitches of contraction time 81 ms / speed, 1 ms apart."""
    t = np.arange(0.0, duration_ms, 1.0)
    return SpeedBases(t, tuple(speeds), np.stack([[unit_twitch_force(d, t, 81.0 / s) for d in trains]
                                                  for s in speeds]))


@pytest.fixture(scope="module")
def sample():
    """Every pool unit reached by a 30 % MVC trapezoid discharging under TRUTH; every 6th one recorded."""
    t = np.arange(0.0, DURATION_MS, STEP_MS)
    e = trapezoid(t)
    active = POOL[POOL < 30.0]
    trains = [synthetic_discharges(e, t, th, TRUTH) for th in active]
    picked = np.arange(2, active.size, 6)
    others = np.setdiff1d(np.arange(active.size), picked)
    trial = DischargeTrial("X_30.mat", 0.0, DURATION_MS, [trains[i] for i in picked], picked,
                           t, e)
    return t, e, active, trains, picked, others, trial


def test_synthetic_discharges_follow_the_rate_above_threshold():
    t = np.arange(0.0, DURATION_MS, STEP_MS)
    e = trapezoid(t)
    d = synthetic_discharges(e, t, 12.0, TRUTH)
    on = t[e >= 12.0]
    assert d[0] == pytest.approx(on[0]) and d[-1] <= on[-1] + STEP_MS
    expected = np.sum(TRUTH.rate(12.0, e)) * STEP_MS / 1000.0
    assert abs(d.size - expected) <= 2
    mid = d[(d > 7000) & (d < 10000)]
    assert 1000.0 / np.mean(np.diff(mid)) == pytest.approx(10.0 + 1.2 + 0.4 * 18.0, rel=0.02)


def test_rate_model_and_excitation_are_read_back_from_the_recorded_sample(sample):
    t, e, _, _, picked, _, trial = sample
    th = POOL[POOL < 30.0][picked]
    rates, active = smoothed_rates(trial.discharges_ms, t)
    model = fit_rate_model(trial.discharges_ms, th, t, rates, active, until_ms=DURATION_MS)
    assert model.k_hz_per_percent == pytest.approx(TRUTH.k_hz_per_percent, rel=0.15)
    assert model.a0_hz == pytest.approx(TRUTH.a0_hz, abs=1.5)
    assert model.threshold_range == (th.min(), th.max())
    est = excitation(rates, active, th, t, model)
    plateau = (t > 6500) & (t < 10500)
    assert np.max(np.abs(est[plateau] - e[plateau])) < 1.5
    assert np.sqrt(np.mean((est - e) ** 2)) < 2.0


def test_unrecorded_units_take_the_pools_count_and_thresholds():
    recorded = POOL[[5, 50, 51, 200]] + 0.01
    rest = unrecorded_thresholds(POOL, recorded)
    assert rest.size == POOL.size - 4
    assert not np.isin(POOL[[5, 50, 51, 200]], rest).any()
    assert unrecorded_thresholds(POOL[:3], POOL[:10]).size == 0
    groups = group_thresholds(rest[rest < 30.0], 2.0)
    assert np.array_equal(np.concatenate(groups), np.sort(rest[rest < 30.0]))
    assert all(g.max() - g.min() <= 2.0 for g in groups)
    with pytest.raises(InputError, match="group width"):
        group_thresholds(rest, 0.0)


def test_completion_recovers_the_unrecorded_units_and_their_force(sample):
    t, e, active, trains, picked, others, trial = sample
    th = active[picked]
    recorded = twitch_bases(trial.discharges_ms, DURATION_MS, SPEEDS)
    pool = complete_pool(trial, th, recorded, until_ms=DURATION_MS, muscle=TA, simulate=twitch_bases)
    # every pool unit below the top of the excitation that was not recorded, at the pool's thresholds (the top of
    # the estimated excitation within about 1 % MVC of the truth's: a few units near 30 % MVC more or less)
    assert abs(pool.n_unrecorded - others.size) <= 0.03 * others.size
    members = np.concatenate(pool.groups)
    assert np.all(np.isin(members, POOL))
    # their discharges: as many as the unrecorded units of the truth fired
    made = sum(g.size * d.size for g, d in zip(pool.groups, pool.group_discharges_ms))
    assert made == pytest.approx(sum(trains[i].size for i in others), rel=0.08)
    # the truth: every unit of the pool with its own train, S0 1, RS 2, P0 as published for TA
    truth = {"S0": 1.0, "RS": 2.0, "delay_ms": 30.0}
    everyone = twitch_bases(trains, DURATION_MS, SPEEDS)
    full = CompletedPool(active, everyone, [], None, everyone.t_ms, e, TRUTH, "TA")
    target = 0.05 * pool_force(full, truth)
    unrecorded_truth = target - 0.05 * pool_force(CompletedPool(th, recorded, [], None, recorded.t_ms, e, TRUTH,
                                                                "TA"), truth)
    assert unrecorded_truth.max() > 0.6 * target.max()      # most of the force is the unrecorded units'
    half = (0.0, DURATION_MS / 2)
    fit = fit_completed_pool(pool, target, calibration_ms=half, heldout_ms=(half[1], DURATION_MS))
    assert fit.nrmse_heldout_percent < 5.0
    recorded_only = CompletedPool(th, recorded, [], None, recorded.t_ms, e, TRUTH, "TA")
    fitted_unrecorded = fit.predicted - fit.scale * pool_force(recorded_only, fit.params)
    assert np.sqrt(np.mean((fitted_unrecorded - unrecorded_truth) ** 2)) < 0.06 * unrecorded_truth.max()
    # carried to its own trial, the fit is its prediction
    assert np.allclose(transferred_pool_force(fit, pool), fit.predicted)
    assert "RP" not in fit.params     # no relative-force parameter: the published spread
    # with RP fitted instead, a force made with RP 20 is recovered as well
    rp_truth = dict(truth, RP=20.0)
    target = 0.05 * pool_force(full, rp_truth)
    fit = fit_completed_pool(pool, target, calibration_ms=half, heldout_ms=(half[1], DURATION_MS), p0_from="fitted")
    assert fit.nrmse_heldout_percent < 5.0 and "RP" in fit.params
    with pytest.raises(InputError, match="p0_from"):
        fit_completed_pool(pool, target, calibration_ms=half, heldout_ms=(half[1], DURATION_MS), p0_from="guess")


def test_published_p0_grows_with_threshold_to_the_spreads_range():
    th = np.array([0.0, 10.0, 30.0, 50.0, 90.0])
    p0 = published_p0("TA", th)
    assert p0[0] == pytest.approx(1.0) and p0[-1] == pytest.approx(PUBLISHED_P0_SPREAD["TA"][0], rel=1e-3)
    assert np.all(np.diff(p0) > 0) and p0[2] < 3.0 < p0[3]
    with pytest.raises(InputError, match="muscle"):
        published_p0("soleus", th)


def test_bad_input_is_refused_naming_file_and_field(sample):
    t, e, active, _, picked, _, trial = sample
    recorded = twitch_bases(trial.discharges_ms, DURATION_MS, SPEEDS)
    with pytest.raises(InputError, match=r"X_30\.mat: recruitment thresholds"):
        complete_pool(trial, active[picked][:-1], recorded, until_ms=DURATION_MS, simulate=twitch_bases)
    with pytest.raises(InputError, match=r"X_30\.mat: recruitment thresholds"):
        complete_pool(trial, np.full(picked.size, np.nan), recorded, until_ms=DURATION_MS, simulate=twitch_bases)
    with pytest.raises(InputError, match=r"X_30\.mat: recruitment thresholds must lie in 0\.\.100"):
        complete_pool(trial, active[picked] + 90.0, recorded, until_ms=DURATION_MS, simulate=twitch_bases)
    with pytest.raises(InputError, match=r"X_30\.mat: discharges: fewer than 3"):
        complete_pool(trial, active[picked], recorded, until_ms=0.0, simulate=twitch_bases)


def test_muscle_from_the_file_name():
    assert muscle_of("data/GM_30.mat").name == "GM"
    assert muscle_of("S1_30_256.mat").name == muscle_of("TA_35_D.mat").name == "TA"


def test_neighbour_rates_sit_between_the_recorded_units_in_time_and_rate(sample):
    t, e, active, trains, picked, _, trial = sample
    th = active[picked]
    rates, on = smoothed_rates(trial.discharges_ms, t)
    model = fit_rate_model(trial.discharges_ms, th, t, rates, on, until_ms=DURATION_MS)
    act = recorded_activity(trial.discharges_ms, th, t, rates, on, excitation(rates, on, th, t, model))
    assert act.rise == pytest.approx(30.0 / 5000.0, rel=0.1) and act.fall == pytest.approx(30.0 / 5000.0, rel=0.1)
    mid = 0.5 * (th[3] + th[4])
    r = neighbour_rate(mid, act, model)
    first = t[np.flatnonzero(r)[0]]
    assert act.first_ms[3] - STEP_MS <= first <= act.first_ms[4] + STEP_MS
    plateau = (t > 7000) & (t < 10000)
    assert np.all(r[plateau] <= rates[3][plateau] + 1e-9) and np.all(r[plateau] >= rates[4][plateau] - 1e-9)
    # below the lowest recorded unit: recruited earlier, derecruited later, faster; above the ceiling: never
    low = neighbour_rate(th[0] / 2, act, model)
    assert t[np.flatnonzero(low)[0]] < act.first_ms[0] and t[np.flatnonzero(low)[-1]] > act.last_ms[0] - STEP_MS
    assert not neighbour_rate(act.ceiling + 1.0, act, model).any()
    # a recording whose units are not swept by ramps is refused
    flat = [np.full(3, d[0]) + [0.0, 50.0, 100.0] for d in trial.discharges_ms[::-1]]
    with pytest.raises(InputError, match="X_30.mat: discharges: the thresholds do not rise"):
        recorded_activity(flat, th, t, rates, on, e, source="X_30.mat")
