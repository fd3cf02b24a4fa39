"""Noise estimate from differences, the split, and the decision rule on constructed residuals."""

import copy

import numpy as np
import pytest

from conftest import ar1
from diagnose_datasets import make_data
from neuromuscle.diagnose.residuals import noise_level, rest_mask, rest_trend_z
from neuromuscle.diagnose.split import automatic_split, given_split
from neuromuscle.diagnose.verdict import WindowSamples, choose, is_unexplained, judge, rest_left, rest_structured
from neuromuscle.measured import Trial
from neuromuscle.errors import InputError


@pytest.mark.parametrize("rho, rel", [(0.0, 0.1), (0.6, 0.15), (0.85, 0.5)])
def test_noise_level_under_a_smooth_misfit(rho, rel):
    """sd within rel (the differences carry little of strongly correlated noise: rho 0.85 is imprecise)."""
    rng = np.random.default_rng(5)
    t = np.arange(3000) * 1e-3
    misfit = 0.5 * np.sin(2 * np.pi * 1.5 * t)  # slow model error, 5x the noise
    nz = noise_level(misfit + ar1(rng, t.size, 0.1, rho))
    assert nz.sd_N == pytest.approx(0.1, rel=rel)
    assert nz.rho == pytest.approx(rho, abs=0.08)


def _case(rng, misfit_scale, effect, fix):
    """Held-out trials: measured = truth + AR(1) noise; baseline misses ``effect`` (and one trial has a misfit);
    the candidate removes ``fix`` of the effect."""
    n, sd, rho = 1000, 0.05, 0.6
    meas, before, after, noise = {}, {}, {}, {}
    for k in range(4):
        truth = np.sin(np.linspace(0, 3, n)) * 5
        m = truth + ar1(rng, n, sd, rho)
        eff = effect * np.linspace(0, 1, n)
        mis = misfit_scale * np.sin(np.linspace(0, 9, n)) if k == 0 else 0.0
        meas[k], before[k], after[k] = m, truth + eff + mis, truth + (1 - fix) * eff + mis
        noise[k] = noise_level(before[k] - m)
    return list(meas), meas, before, after, noise


def test_rule_passes_a_real_effect():
    ids, meas, before, after, noise = _case(np.random.default_rng(1), 0.0, 0.3, 0.8)
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"])
    assert ev.passed, ev.text()


def test_rule_refuses_a_small_change_of_a_calibration_misfit():
    """One held-out trial with a misfit 4x the noise; the candidate moves the prediction by 1 % of it."""
    rng = np.random.default_rng(2)
    ids, meas, before, _, noise = _case(rng, 0.2, 0.0, 0.0)
    after = dict(before)
    after[0] = before[0] - 0.01 * 0.2 * np.sin(np.linspace(0, 9, 1000))
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"])
    assert not ev.passed and any("above noise" in f for f in ev.failed), ev.text()


def test_rule_needs_a_reference_misfit():
    """A reference at its noise floor on every held-out trial leaves nothing to explain when a candidate takes up
    less than half of the excess (here all of a misfit smaller than the noise on one trial: 28 % of the held-out
    excess, the rest being the other trials' noise); one structured held-out trial is enough."""
    rng = np.random.default_rng(4)
    ids, meas, before, _, noise = _case(rng, 0.03, 0.0, 0.0)
    after = {k: b - (0.03 * np.sin(np.linspace(0, 9, 1000)) if k == 0 else 0.0) for k, b in before.items()}
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"])
    assert ev.excess_removed < 0.5
    assert any(f.startswith("nothing to explain") for f in ev.failed), ev.text()
    ids, meas, before, after, noise = _case(np.random.default_rng(1), 0.0, 0.3, 0.8)
    ev = judge(ids, meas, {**before, 1: meas[1], 2: meas[2], 3: meas[3]}, after, noise, 2, ["x.k"])
    assert not any(f.startswith("nothing to explain") for f in ev.failed), ev.text()


@pytest.mark.parametrize("fix, explains", [(0.9, True), (0.2, False)])
def test_a_diffuse_excess_is_something_to_explain_only_when_the_candidate_explains_most_of_it(fix, explains):
    """An effect spread over every held-out trial, each within 1.5 noise sd under the reference (1.15): a candidate
    that removes 90 % of its amplitude (99 % of its squared error) has something to explain; one that removes 20 %
    (36 %) does not, however far its gain is beyond noise (stop 38: suite seed 3's hidden relaxation effect)."""
    ids, meas, before, after, noise = _case(np.random.default_rng(6), 0.0, 0.05, fix)
    ratios = [np.sqrt(np.mean((before[k] - meas[k]) ** 2)) / noise[k].sd_N for k in ids]
    assert max(ratios) < 1.5
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"])
    assert ev.chi2_gain > ev.bic_penalty
    assert (ev.excess_removed > 0.5) is explains
    assert any(f.startswith("nothing to explain") for f in ev.failed) is not explains, ev.text()
    assert ev.passed is explains


def _history_case(shape, level=0.0, level_after=None):
    """Four held-out trials whose reference misses ``shape`` (N); the candidate removes 80 % of it; the window is
    each trial's second half (the hold), measured from the isometric ``level`` (N) of the reference and
    ``level_after`` (default: the same) of the candidate."""
    rng = np.random.default_rng(1)
    n = 1000
    hold = np.arange(n) >= 500
    ids, meas, before, after, noise = list(range(4)), {}, {}, {}, {}
    for k in ids:
        truth = np.sin(np.linspace(0, 3, n)) * 5
        meas[k] = truth + ar1(rng, n, 0.05, 0.6)
        before[k], after[k] = truth + shape, truth + 0.2 * shape
        noise[k] = noise_level(before[k] - meas[k])
    lv1 = level if level_after is None else level_after
    return ids, meas, before, after, noise, {k: WindowSamples(hold, ("iso",), level, lv1) for k in ids}


@pytest.mark.parametrize("in_window, passes", [(True, True), (False, False)])
def test_a_history_cause_must_gain_where_it_is_defined(in_window, passes):
    """Rule 7: an extension for a cause defined after a movement passes only when it gains beyond its penalty in
    the held-out samples where the cause is defined (the hold after the movement, here each trial's second half).
    The same gain before the hold (as on a ramp) passes every other rule but not this one (stop 39: two fresh
    nulls' force-history fits gained 444 and 628 held out, -92 and +15 in the holds)."""
    hold = np.arange(1000) >= 500
    ids, meas, before, after, noise, window = _history_case(-0.3 * (hold if in_window else ~hold))  # 6 noise sd
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"], window=window)
    assert not [f for f in ev.failed if not f.startswith("where the cause is defined")], ev.text()
    assert (ev.window_chi2_gain > ev.window_penalty and ev.window_p05 > 0) is passes
    assert ev.passed is passes, ev.text()
    assert ev.window_trials[0]["samples"] == 500 and ev.window_trials[0]["isometric_references"] == ["iso"]
    assert sum(w["chi2_gain"] for w in ev.to_json()["window_trials"].values()) == pytest.approx(ev.window_chi2_gain)
    assert "from the isometric force at that length" in ev.text()


def test_a_hold_misfit_the_isometric_trials_share_is_not_a_history_effect():
    """The reference falls short in the hold by as much as on the isometric trials at that length (a force-length
    misfit, stop 39's second null of --seed 2): measured from the isometric level, the candidate that adds force
    in the hold makes the window worse and fails rule 7; with no isometric misfit at that length it passes."""
    hold = np.arange(1000) >= 500
    shortfall = -0.3 * hold
    ids, meas, before, after, noise, window = _history_case(shortfall, level=-0.3)
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"], window=window)
    assert ev.window_chi2_gain < 0 and not ev.passed, ev.text()
    ids, meas, before, after, noise, window = _history_case(shortfall, level=0.0)
    assert judge(ids, meas, before, after, noise, 2, ["x.k"], window=window).passed
    # a candidate that only raises the isometric force at that length (its refit) is measured from its own level
    ids, meas, before, after, noise, window = _history_case(shortfall, level=-0.3, level_after=-0.06)
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"], window=window)
    assert abs(ev.window_chi2_gain) < ev.window_penalty and not ev.passed, ev.text()


def test_a_cause_with_no_held_out_trial_where_it_is_defined_is_not_named():
    ids, meas, before, after, noise = _case(np.random.default_rng(1), 0.0, 0.3, 0.8)
    ev = judge(ids, meas, before, after, noise, 2, ["x.k"],
               window={k: WindowSamples(np.zeros(1000, bool), (), 0.0, 0.0) for k in ids})
    assert ev.failed == ["no held-out trial where the cause is defined"]
    assert ev.window_p05 is None and "FAILS: no held-out trial where the cause is defined" in ev.text()
    assert judge(ids, meas, before, after, noise, 2, ["x.k"]).window_chi2_gain is None  # other causes: no rule 7


def test_rule_refuses_an_unidentified_extension():
    ids, meas, before, after, noise = _case(np.random.default_rng(3), 0.0, 0.3, 0.8)
    assert not judge(ids, meas, before, after, noise, 2, []).passed
    ev = judge(ids, meas, before, after, noise, 2, [], calibration=(12.0, 15.0))
    assert not ev.passed and "calibration chi2 gain 12.0 <= BIC penalty 15.0" in ev.failed[0], ev.text()


def test_a_calibration_likelihood_ratio_identifies_an_extension_without_a_clear_interval():
    """Rule 1's likelihood-ratio form: no interval excludes neutral, but the calibration fit gains more than its
    penalty over the reference."""
    ids, meas, before, after, noise = _case(np.random.default_rng(3), 0.0, 0.3, 0.8)
    ev = judge(ids, meas, before, after, noise, 2, [], calibration=(250.0, 15.0))
    assert ev.passed, ev.text()
    assert ev.to_json()["calibration_chi2_gain"] == 250.0


def test_the_verdict_among_passing_candidates_fits_the_whole_file_best():
    """Two candidates pass every rule: the one with the larger held-out gain is not named when the other fits the
    calibration trials better by more (suite seed 4's staircase case, stop 34: held out 916 against
    relaxation_rate's 1230, calibration 4500 against 2907); a failing candidate is never named, however large its
    gain; with no calibration gain the held-out gain less its penalty decides."""
    ids, meas, before, after, noise = _case(np.random.default_rng(1), 0.0, 0.3, 0.8)
    small = {k: b + 0.5 * (a - b) for (k, b), a in zip(before.items(), after.values())}
    strong_heldout = judge(ids, meas, before, after, noise, 3, ["x.k"], calibration=(100.0, 20.0))
    strong_calibration = judge(ids, meas, before, small, noise, 2, ["y.k"], calibration=(5000.0, 20.0))
    assert strong_heldout.passed and strong_calibration.passed
    assert strong_heldout.chi2_gain > strong_calibration.chi2_gain
    assert strong_calibration.whole_file_score > strong_heldout.whole_file_score
    assert choose({"x": strong_heldout, "y": strong_calibration}) == "y"
    assert strong_calibration.to_json()["whole_file_score"] == pytest.approx(
        strong_calibration.chi2_gain - strong_calibration.bic_penalty + 5000.0 - 20.0)
    failing = judge(ids, meas, before, after, noise, 3, [], calibration=(1e6, 1e7))
    assert not failing.passed and choose({"f": failing}) is None
    assert choose({"f": failing, "y": strong_calibration}) == "y"
    no_cal = judge(ids, meas, before, after, noise, 3, ["x.k"])
    assert no_cal.whole_file_score == pytest.approx(no_cal.chi2_gain - no_cal.bic_penalty)
    assert choose({"x": no_cal, "y": judge(ids, meas, before, small, noise, 3, ["y.k"])}) == "x"


def test_unexplained_needs_several_trials():
    assert not is_unexplained(["a"], 10) and not is_unexplained(["a", "b"], 10)
    assert is_unexplained(["a", "b", "c"], 10) and not is_unexplained(["a", "b", "c"], 25)


def _twitch_trial(rng, extra, moving=False):
    """A 1 s twitch (stimulus at 0.1 s, model force back at rest by ~0.5 s) at 1 kHz: the model's force, and the
    trial measured as model + ``extra`` + AR(1) noise (sd 0.35 N, rho 0.8)."""
    t = np.arange(1000) * 1e-3
    s = np.clip(t - 0.1, 0, None)
    sim = 0.5 + 4.0 * (s / 0.08) * np.exp(1 - s / 0.08)
    force = sim + extra(t) + ar1(rng, t.size, 0.35, 0.8)
    length = -8.0 + (2.0 * t if moving else 0.0 * t)
    return Trial(trial_id="tw", protocol="twitch", time_s=t, force=force, force_unit="N", length_unit="mm",
                 length=length, stimulus_times_s=np.array([0.1])), sim


@pytest.mark.parametrize("extra, structured", [
    (lambda t: 0.0 * t, False),                               # noise only
    (lambda t: 0.0 * t + 0.6, False),                         # a constant offset (passive force misfit)
    (lambda t: 0.9 * np.sin(2 * np.pi * t / 4.0 + 2.5), True),  # a transducer drift (synth's weakest), period 4 s
    (lambda t: 0.9 * np.sin(2 * np.pi * t / 4.0 - 0.5), True),
])
def test_rest_trend_sees_force_change_where_the_muscle_is_quiet(extra, structured):
    """Rest: before the stimulus and >= 250 ms after it, where the model's force is back at its level.  (A drift
    near its crest is flat over one trial and not seen in it: the verdict counts trials.)"""
    for seed in range(5):
        trial, sim = _twitch_trial(np.random.default_rng(seed), extra)
        nz = noise_level(trial.force - sim)
        m = rest_mask(trial, sim, nz.sd_N)
        assert m[:100].all() and not m[100:350].any() and m[-300:].all()
        z = rest_trend_z(trial, sim - trial.force, sim, nz)
        assert (abs(z) > 3.0) == structured, (seed, z)


def test_rest_trend_needs_an_isometric_trial_with_rest():
    trial, sim = _twitch_trial(np.random.default_rng(0), lambda t: 0.0 * t, moving=True)
    assert rest_trend_z(trial, sim - trial.force, sim, noise_level(trial.force - sim)) is None
    assert rest_structured({"a": None, "b": -3.5, "c": 2.9}) == (["b"], 2)


def test_a_model_that_leaves_trends_at_rest_cannot_be_named():
    """rest_left: enough trials (max(3, 20 %) of those with a rest window) trending at rest fail a candidate."""
    quiet = {f"t{k}": 0.5 * (-1) ** k for k in range(12)} | {"moving": None}
    assert rest_left(quiet) is None
    two = quiet | {"t0": 4.0, "t1": -3.2}
    assert rest_left(two) is None
    three = two | {"t2": 3.1}
    why = rest_left(three)
    assert why is not None and "3 of 12 trials" in why and "t0, t1, t2" in why and "moving" not in why
    assert rest_left({f"t{k}": 5.0 for k in range(3)} | {f"u{k}": 0.0 for k in range(13)}) is None  # 3 < 20 % of 16


def test_automatic_split_puts_each_protocol_on_both_sides():
    data = make_data(0)
    s = automatic_split(data)
    for proto in {t.protocol for t in data.trials.values()}:
        ids = {i for i, t in data.trials.items() if t.protocol == proto}
        assert ids & set(s.calibration) and ids & set(s.heldout)
    g = given_split(data, ["twitch_opt", "long50_opt"])
    assert g.heldout == ("twitch_opt", "long50_opt") and "twitch_opt" not in g.calibration
    with pytest.raises(InputError, match="nosuch"):
        given_split(data, ["nosuch"])


def test_automatic_split_holds_out_between_calibration_trials():
    """Doublets at 5, 10 and 15 ms (same length and stimulus count): the 10 ms one is held out, so the doublet
    extension is judged where it interpolates (ordered by id as text, 15 ms was held out)."""
    data = make_data(0)
    base = data.trials["train20_opt"]
    for isi in (5, 10, 15):
        t = copy.deepcopy(base)
        t.trial_id, t.protocol = f"doublet{isi}_opt", "doublet"
        stim = np.asarray(base.stimulus_times_s, dtype=float)
        t.stimulus_times_s = np.sort(np.append(stim[:-1], stim[0] + isi / 1000.0))  # same count, shortest ISI isi
        data.trials[t.trial_id] = t
    s = automatic_split(data)
    assert "doublet10_opt" in s.heldout and {"doublet5_opt", "doublet15_opt"} <= set(s.calibration)
