"""Evaluation of candidates (neuromuscle.fit.evaluate): a trial's simulation; batched and packed runs are the
lone runs; serial and parallel maps agree."""

from dataclasses import asdict, replace

import numpy as np
import pytest
from fit_synthetic import OPTS, far_start, synthetic_trial

from neuromuscle.errors import InputError
from neuromuscle.fit import FitProblem, fit, trial_simulation
from neuromuscle.fit import evaluate
from neuromuscle.fit.evaluate import TrialPool, trial_simulations
from neuromuscle.measured import Trial
from neuromuscle.sim import simulate


def test_trial_simulation_matches_simulate(ct09):
    t = np.arange(0.1, 0.25, 0.0005)  # a trial clock that does not start at 0
    tr = Trial(trial_id="a", protocol="twitch", time_s=t, force=np.zeros_like(t), force_unit="N",
               length_unit="mm", length_const=-8.0, stimulus_times_s=np.array([0.12]))
    got = trial_simulation(ct09, tr, 0.1, settle_ms=100.0)
    ref = simulate(ct09, [120.0], -8.0, 250.0, dt_ms=0.1, record_dt_ms=0.1)
    np.testing.assert_allclose(got, np.interp((t - 0.1) * 1000 + 100.0, ref.t_ms, ref.force_N), atol=1e-9)
    assert got.max() > 3.0


def test_trial_simulation_played_length_and_units(ct09):
    ramp = synthetic_trial(ct09, "ramp", [0.02], length=lambda t: -8.0 + 20.0 * np.clip(t - 0.05, 0, 0.1),
                           seed=2)
    iso = synthetic_trial(ct09, "iso", [0.02], seed=2)
    assert np.max(np.abs(ramp.force - iso.force)) > 0.3  # lengthening changes the force
    moment = Trial(trial_id="m", protocol="twitch", time_s=ramp.time_s, force=ramp.force, force_unit="N*m",
                   length_unit="mm", length_const=-8.0, stimulus_times_s=np.array([0.02]))
    with pytest.raises(InputError, match="'N' and 'mm'"):
        trial_simulation(ct09, moment)


def test_batched_runs_are_the_lone_runs(ct09, monkeypatch):
    """trial_simulations on a stretch: runs with mixed steps and extensions, more of one step than a batch holds
    (BATCH_UNITS = 2 here), come back in order as trial_simulation's forces, bit for bit."""
    monkeypatch.setattr(evaluate, "BATCH_UNITS", 2)
    ramp = synthetic_trial(ct09, "ramp", [0.02, 0.04, 0.06], length=lambda t: -8.0 + 20.0 * np.clip(t - 0.05, 0, 0.1))
    moved = ct09.with_values({"kim_m2.C1": ct09["kim_m2.C1"] * 1.05})
    params = [ct09, moved, ct09, ct09, moved]
    opts = [OPTS, OPTS, replace(OPTS, dt_ms=0.05), replace(OPTS, extensions=("fatigue",)),
            replace(OPTS, extensions=("force_enhancement_after_stretch",))]
    got = trial_simulations(params, ramp, opts)
    for p, o, g in zip(params, opts, got):
        np.testing.assert_array_equal(g, trial_simulation(p, ramp, **asdict(o)))
    assert not np.array_equal(got[0], got[1]) and not np.array_equal(got[0], got[4])
    with pytest.raises(ValueError, match="1 options for 2 parameter sets"):
        trial_simulations(params[:2], ramp, opts[:1])


def _trials_of_several_durations(ct09):
    """A ramp and isometric trials whose durations differ (and are off the 0.2 ms step grid: 0.3, 0.2173 and
    0.41 s at 0.1 ms samples), so packed runs end after some of their units' trials."""
    ramp = synthetic_trial(ct09, "ramp", [0.02, 0.04, 0.06], length=lambda t: -8.0 + 20.0 * np.clip(t - 0.05, 0, 0.1))
    out = [ramp]
    for tid, span, stim in (("short", 0.2173, [0.03]), ("long", 0.41, [0.02, 0.05, 0.33])):
        t = np.arange(0.0, span, 0.0001)
        out.append(Trial(trial_id=tid, protocol="twitch", time_s=t, force=np.zeros_like(t), force_unit="N",
                         length_unit="mm", length_const=-6.0, stimulus_times_s=np.array(stim)))
    return out


def test_packed_runs_of_several_trials_are_the_lone_runs(ct09, monkeypatch):
    """simulate_pairs packs runs of trials of different durations (and steps, and extensions) into shared NEURON
    runs; every pair's force is trial_simulation's alone, bit for bit, in order, for any pack size."""
    trials = _trials_of_several_durations(ct09)
    moved = ct09.with_values({"kim_m2.C1": ct09["kim_m2.C1"] * 1.05})
    opts = [OPTS, OPTS, replace(OPTS, dt_ms=0.2, record_dt_ms=0.5, settle_ms=0.0),
            replace(OPTS, extensions=("fatigue",))]
    pairs = [(p, t, o) for p, o in zip([ct09, moved, moved, ct09], opts) for t in trials]
    alone = [trial_simulation(p, t, **asdict(o)) for p, t, o in pairs]
    for size in (16, 3):
        got = evaluate.simulate_pairs(pairs, max_units=size)
        for (_, t, o), g, a in zip(pairs, got, alone):
            np.testing.assert_array_equal(g, a, err_msg=f"{t.trial_id} {o}")
    assert max(len(pack) for pack in evaluate._packed(pairs, 16)) > len({id(t) for t in trials}) - 1
    monkeypatch.setattr(evaluate, "PACK_SHARE", 1.0)  # one trial per run: the runs of one trial batched only
    assert all(len({id(pairs[i][1]) for i in pack}) == 1 for pack in evaluate._packed(pairs, 16))


def test_packs_take_the_longest_first_and_bound_the_waste():
    assert evaluate.packs([100.0, 400.0, 390.0, 150.0, 210.0], max_units=2, share=0.5) == [[1, 2], [4, 3], [0]]
    assert evaluate.packs([], max_units=4) == []
    assert evaluate.packs([5.0, 5.0, 5.0], max_units=4, share=0.5) == [[0, 1, 2]]


def test_pool_packs_several_trials_and_is_the_serial_simulation(ct09):
    trials = _trials_of_several_durations(ct09)
    params = [ct09, ct09.with_values({"kim_m2.C1": ct09["kim_m2.C1"] * 1.05})]
    with TrialPool(trials, workers=2) as pool:
        got = pool.simulate(params, trials[::-1], OPTS)
    serial = evaluate.simulate_batched(params, trials[::-1], [OPTS, OPTS])
    for g, s in zip(got, serial):
        for a, b in zip(g, s):
            np.testing.assert_array_equal(a, b)


def test_batched_serial_fit_is_the_per_candidate_fit(ct09, twitch_trials):
    """A fit in one process batches each Jacobian's candidates; one by one (a map given) it is the same fit."""
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    batched = fit(problem, progress=False, max_iterations=3)
    one_by_one = fit(problem, progress=False, max_iterations=3, map_fn=map)
    assert batched.estimates == one_by_one.estimates and batched.cost == one_by_one.cost
    assert [h["cost"] for h in batched.history] == [h["cost"] for h in one_by_one.history]


def test_serial_and_two_workers_identical(ct09, twitch_trials):
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    serial = fit(problem, progress=False, max_iterations=3)
    parallel = fit(problem, progress=False, max_iterations=3, workers=2)
    assert serial.estimates == parallel.estimates
    assert serial.cost == parallel.cost and serial.std_errors == parallel.std_errors
    assert [h["cost"] for h in serial.history] == [h["cost"] for h in parallel.history]
    assert serial.n_simulations == parallel.n_simulations


def test_trial_pool_reassembles_trials_in_order(ct09, twitch_trials):
    """The pool runs the longest trial first; every parameter set's forces come back in the given trial order."""
    long = synthetic_trial(ct09, "long", [0.02, 0.05], duration_s=0.6, seed=3)
    trials = [twitch_trials[0], long, twitch_trials[1]]
    problem = FitProblem(trials, ct09, ["C3", "C1"], options=OPTS)
    zs = [np.zeros(2), np.array([0.3, -0.2])]
    with TrialPool([twitch_trials[1], *trials], 2) as pool:
        got = pool.simulate([problem.parameters(z) for z in zs], trials, OPTS)
        half = pool.simulate([problem.parameters(zs[0])], trials, replace(OPTS, dt_ms=0.05))[0]
        each = pool.simulate([problem.parameters(zs[0])] * 2, trials, [OPTS, replace(OPTS, dt_ms=0.05)])
        with pytest.raises(ValueError, match="2 options for 1 parameter sets"):
            pool.simulate([ct09], trials, [OPTS, OPTS])
        res = pool.residuals(problem, zs)
        with pytest.raises(InputError, match="not in this pool"):
            pool.simulate([ct09], [synthetic_trial(ct09, "other", [0.02])], OPTS)
    for z, sims, r in zip(zs, got, res):
        want = problem.simulate_trials(z)
        assert [s.shape for s in sims] == [w.shape for w in want]
        for s, w in zip(sims, want):
            np.testing.assert_array_equal(s, w)
        np.testing.assert_array_equal(r, problem.residuals(z))
    for s, w in zip(half, problem.simulate_trials(zs[0], replace(OPTS, dt_ms=0.05))):
        np.testing.assert_array_equal(s, w)
    assert not np.array_equal(got[0][1], got[1][1])  # the candidates differ
    for s, w in zip(each[0] + each[1], got[0] + half):  # options per set: each set as if called alone
        np.testing.assert_array_equal(s, w)


def test_fits_share_a_pool(ct09, twitch_trials):
    """Two fits on one caller's pool give the fit of one process; a pool and workers > 1 are refused together."""
    problem = FitProblem(twitch_trials, ct09, ["C3", "C1"], start=far_start(ct09), options=OPTS)
    serial = fit(problem, progress=False, max_iterations=2)
    with TrialPool(twitch_trials, 2) as pool:
        a = fit(problem, progress=False, max_iterations=2, pool=pool)
        b = fit(FitProblem(twitch_trials[:1], ct09, ["C3"], options=OPTS), progress=False, max_iterations=1,
                pool=pool)
        with pytest.raises(InputError, match="not several"):
            fit(problem, progress=False, max_iterations=1, pool=pool, workers=2)
    assert a.estimates == serial.estimates and a.std_errors == serial.std_errors
    assert b.n_iterations == 1


def test_custom_map_is_used(ct09, twitch_trials):
    calls = []

    def my_map(fn, items):
        items = list(items)
        calls.append(len(items))
        return map(fn, items)

    problem = FitProblem(twitch_trials[:1], ct09, ["C3"], options=OPTS)
    fit(problem, progress=False, max_iterations=2, map_fn=my_map)
    assert 2 in calls  # one Jacobian (central differences, one parameter) = one map call of 2 candidates
