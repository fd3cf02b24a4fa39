"""The bookkeeping of the forward selection: which step names which causes against which model, and when two
candidates are tried together (selection.py, step 6).  The fits themselves are exercised by the sample diagnoses."""

from types import SimpleNamespace

import numpy as np
import pytest

from conftest import evidence
from neuromuscle.diagnose import selection
from neuromuscle.diagnose.selection import (JOINT_IF_PASSES, Candidate, Joint, Step, at_base,
                                           fit_alone, joint, pair_for)
from neuromuscle.parameters import load_parameters


def model(name: str) -> SimpleNamespace:
    return SimpleNamespace(name=name)


def candidate(name: str, failed=(), score: float | None = 10.0, fitted: bool = True,
              chi2_gain: float = 90.0) -> Candidate:
    c = Candidate(name, ["cal"], ["held"])
    c.screen = None if score is None else SimpleNamespace(score=score)
    if fitted:
        c.model, c.evidence = model(f"M + {name}"), evidence(failed, chi2_gain)
    return c


def test_a_step_naming_one_cause_judges_it_against_the_model_before():
    s = Step(1, model("M"), {"a": candidate("a")}, named="a")
    assert s.named_causes == ["a"] and not s.named_jointly
    assert s.model_of("a").name == "M + a" and s.before_of("a").name == "M"
    assert s.after.name == "M + a" and s.evidence_of("a") is s.candidates["a"].evidence


def test_two_causes_named_together_are_each_judged_against_the_other_alone():
    a, b = candidate("a", ["R3"]), candidate("b", ["R2", "R4"])
    pair = Joint(("a", "b"), model("M + a + b"), {"a": a.model, "b": b.model}, {"a": evidence(), "b": evidence()})
    s = Step(1, model("M"), {"a": a, "b": b}, named="a", joint=pair)
    assert s.named_jointly and s.named_causes == ["a", "b"]
    assert s.model_of("a").name == s.model_of("b").name == "M + a + b" == s.after.name
    assert s.before_of("a").name == "M + b" and s.before_of("b").name == "M + a"
    assert s.evidence_of("b") is pair.evidence["b"]


def test_a_pair_that_fails_names_nothing():
    a, b = candidate("a", ["R3"]), candidate("b")
    pair = Joint(("a", "b"), model("M + a + b"), {"a": a.model, "b": b.model},
                 {"a": evidence(), "b": evidence(["R4"])})
    s = Step(1, model("M"), {"a": a, "b": b}, joint=pair)
    assert not pair.passed and s.named_causes == [] and s.after.name == "M"


def test_no_pair_is_tried_without_a_candidate_beyond_noise_and_material_alone():
    """joint() returns before fitting anything when every fitted candidate fails a rule of JOINT_IF_PASSES, or
    when no other candidate screens above its penalty (the context is never used)."""
    for rule in JOINT_IF_PASSES:
        s = Step(1, model("M"), {"a": candidate("a", [rule, "R3"]), "b": candidate("b", ["R2"])})
        assert joint(None, s) is None
    alone = Step(1, model("M"), {"a": candidate("a", ["R3"]), "b": candidate("b", score=-1.0, fitted=False),
                                 "c": candidate("c", score=None, fitted=False)})
    assert joint(None, alone) is None


def test_a_candidate_failing_only_for_size_is_not_paired():
    """A candidate that passes every rule but R4 (material) is not tried with another: on held-out two-effect files
    such a pair named a cause the file did not hold (docs/validation/diagnosis.md)."""
    small = candidate("a", ["R4"], score=50.0, chi2_gain=400.0)
    other = candidate("b", ["R4", "R7"], score=40.0, chi2_gain=300.0)
    assert pair_for(Step(1, model("M"), {"a": small, "b": other})) is None


def test_putting_p0_back_moves_the_force_valued_parameters_with_it():
    """A start or screen at the base force-length curve keeps the force-velocity curve's shape relative to P0:
    a fitted c0 below the base P0 would otherwise be refused by KimForce (eq 11's asymptote)."""
    p = load_parameters("CT09")
    fitted = p.with_values({"P0": 2 * p["P0"], "c0": -1.5 * p["P0"], "a0": 0.2 * p["P0"], "g1": -5.0})
    ctx = SimpleNamespace(base=p)
    back = at_base(ctx, fitted, ["P0", "g1", "g2"])
    assert (back["P0"], back["g1"], back["g2"]) == (p["P0"], p["g1"], p["g2"])
    assert back["c0"] == pytest.approx(-0.75 * p["P0"]) and back["a0"] == pytest.approx(0.1 * p["P0"])
    assert back["c0"] > -back["P0"]
    only = at_base(ctx, fitted, ["g1"])
    assert only["g1"] == p["g1"] and (only["P0"], only["c0"]) == (fitted["P0"], fitted["c0"])


def test_a_force_valued_parameter_scaled_past_its_range_stops_at_its_edge():
    """A fitted a0 near its upper bound (500 N), P0 put back 1.2x higher: the start stays admissible, a0 at 500 N,
    c0 scaled as usual."""
    p = load_parameters("CT09")
    fitted = p.with_values({"P0": 400.0, "a0": 480.0, "c0": -100.0})
    back = at_base(SimpleNamespace(base=p.with_values({"P0": 480.0})), fitted, ["P0"])
    assert back["P0"] == 480.0 and back["a0"] == 500.0 and back["c0"] == pytest.approx(-120.0)


def test_the_second_of_a_pair_is_the_best_measured_gain_then_the_best_screen():
    """A fitted held-out gain is a measurement, a screen a linearised ranking: the partner of the material
    candidate is the fitted one beyond noise (R2) with the best score, whatever the screens say."""
    a = candidate("a", ["R7"], score=50.0, chi2_gain=500.0)
    screened_first = candidate("b", ["R2", "R3", "R4", "R7"], score=40.0, chi2_gain=-900.0)
    measured = candidate("c", ["R7"], score=5.0, chi2_gain=300.0)
    unfitted = candidate("d", score=30.0, fitted=False)
    s = Step(1, model("M"), {c.name: c for c in (a, screened_first, measured, unfitted)})
    first, second = pair_for(s)
    assert (first.name, second.name) == ("a", "c")
    s = Step(1, model("M"), {c.name: c for c in (a, screened_first, unfitted)})
    assert [c.name for c in pair_for(s)] == ["a", "b"]


@pytest.mark.parametrize("first_cost, refitted", [(90.0, False), (120.0, True)])
def test_a_candidate_whose_fit_ends_above_the_model_it_contains_is_fitted_again_from_that_model(
        monkeypatch, first_cost, refitted):
    """The model before is the candidate's model with the extension neutral: a fit that ends above its
    calibration chi-square (100 here) is fitted again from it, the extension's effect parameters at their neutral
    values, and the better fit is kept."""
    fits: list[dict] = []

    def fake_fit(extensions, baseline_free, starts, *args, **kwargs):
        fits.append(dict(starts))
        return SimpleNamespace(cost=first_cost if len(fits) == 1 else 100.0)

    monkeypatch.setattr(selection, "fit_model", fake_fit)
    monkeypatch.setattr(selection, "calibration_chi2", lambda ctx, simulated: 100.0)
    before = SimpleNamespace(name="baseline", extensions=(), simulated={}, parameters=load_parameters("CT09"))
    ctx = SimpleNamespace(baseline=before, baseline_free=("P0",), calibration_trials=[], trials=[],
                          noise={}, pool=None, phases={}, base=load_parameters("CT09"), say=lambda text: None)
    got = selection.fit_candidate(ctx, "fatigue", before, None)
    assert len(fits) == (2 if refitted else 1)
    if refitted:
        (how, start), = fits[1].items()
        assert how == "model before, neutral" and start["fatigue.k"] == 0.0
        assert got.cost == 100.0
    else:
        assert got.cost == first_cost


def test_a_later_candidate_is_fitted_with_the_causes_named_before_it_free(monkeypatch):
    """Judged against the best model that contains it: at a later step the candidate's fit also frees the causes
    already named (none of their parameters in ``fixed_extensions``) and the baseline parameters any of them
    interacts with, so a named cause that took up part of the candidate's effect gives it back."""
    calls: list[dict] = []

    def fake_fit(extensions, baseline_free, starts, *args, **kwargs):
        calls.append(dict(extensions=tuple(extensions), free=tuple(baseline_free), **kwargs))
        return SimpleNamespace(cost=90.0)

    monkeypatch.setattr(selection, "fit_model", fake_fit)
    monkeypatch.setattr(selection, "calibration_chi2", lambda ctx, simulated: 100.0)
    before = SimpleNamespace(name="baseline + length_dependent_activation", extensions=("length_dependent_activation",),
                             simulated={}, parameters=load_parameters("CT09"))
    ctx = SimpleNamespace(baseline=before, baseline_free=("g1", "g2", "P0", "KSE"), calibration_trials=[], trials=[],
                          noise={}, pool=None, phases={}, base=load_parameters("CT09"), say=lambda text: None)
    selection.fit_candidate(ctx, "lengthening_below_optimum", before, None)
    (call,) = calls
    assert call["extensions"] == ("length_dependent_activation", "lengthening_below_optimum")
    assert not call.get("fixed_extensions")
    assert set(call["free"]) == {"g1", "g2", "P0", "KSE"}  # eq 18's Module 3 beside the candidate's KSE
    assert selection.refitted(ctx, "lengthening_below_optimum") == ("KSE",)


def test_a_candidate_whose_telling_trials_all_calibrate_is_judged_with_them_held_out(monkeypatch):
    """Cross-validation over trials: the model before is fitted again without the candidate's telling trials (once
    for every candidate with the same ones), the candidate is fitted from that refit, and both are judged with those
    trials on the held-out side; a candidate with a held-out telling trial is judged on the file's own split."""
    fits, judged = [], []

    def fake_fit(extensions, baseline_free, starts, calibration, *args, **kwargs):
        fits.append((tuple(extensions), tuple(calibration)))
        name = " + ".join(("baseline",) + tuple(extensions))
        return SimpleNamespace(name=name, start="model before", extensions=tuple(extensions), cost=1.0,
                               simulated={"of": f"{name} on {len(calibration)} trials"}, free=("P0",))

    def fake_judge(ctx, name, before, model, held):
        judged.append((name, tuple(ctx.calibration), tuple(ctx.heldout), before.name, tuple(held)))
        return evidence()

    def fake_calibration_side(ctx, name, before, model):
        identifying.append((name, tuple(ctx.calibration), before.name, model.name))
        return ["fatigue.k"], (500.0, 20.0)

    def fake_ranking(heldout, measured, before, after, noise, n_parameters):
        ranking.append((tuple(heldout), before["of"], after["of"], n_parameters))
        return 300.0, 7.0

    identifying, ranking = [], []
    monkeypatch.setattr(selection, "heldout_chi2_gain", fake_ranking)
    monkeypatch.setattr(selection.Context, "measured", property(lambda ctx: {}))
    monkeypatch.setattr(selection, "fit_model", fake_fit)
    monkeypatch.setattr(selection, "calibration_chi2", lambda ctx, simulated: 2.0)
    monkeypatch.setattr(selection, "judge", fake_judge)
    monkeypatch.setattr(selection, "calibration_side", fake_calibration_side)
    monkeypatch.setattr(selection, "_starts", lambda ctx, name, before, screened: {})
    baseline = SimpleNamespace(name="baseline", extensions=(), simulated={"of": "baseline on 3 trials"},
                               parameters=None, free=("P0",))
    data = SimpleNamespace(trials={i: i for i in ("twitch", "train", "long_train", "held_train")})
    ctx = selection.Context(data, {}, ("twitch", "train", "long_train"), ("held_train",), {}, None, ("P0",))
    ctx.baseline = baseline
    fatigue = Candidate("fatigue", ["long_train"], [])
    fit_alone(ctx, fatigue, baseline)
    assert fits == [(("fatigue",), ("twitch", "train", "long_train")),  # the candidate on the file's split
                    ((), ("twitch", "train")),                            # the baseline without its telling trial
                    (("fatigue",), ("twitch", "train"))]                  # the candidate from that refit
    assert judged == [("fatigue", ("twitch", "train"), ("held_train", "long_train"), "baseline", ("long_train",))]
    assert fatigue.evidence.crossed == ("long_train",) and fatigue.model.name == "baseline + fatigue"
    # whether the effect is identified: from the candidate's fit on every calibration trial, against the model before
    assert identifying == [("fatigue", ("twitch", "train", "long_train"), "baseline", "baseline + fatigue")]
    assert (fatigue.evidence.identified, fatigue.evidence.calibration_chi2_gain) == (["fatigue.k"], 500.0)
    # its score: that fit against the model before on the file's own held-out trials, as every other candidate's
    assert ranking == [(("held_train",), "baseline on 3 trials", "baseline + fatigue on 3 trials", 3)]
    assert fatigue.evidence.score == 300.0 - 7.0 + 500.0 - 20.0
    fit_alone(ctx, Candidate("relaxation_rate", ["long_train"], []), baseline)
    assert len(fits) == 5  # the refitted baseline is kept
    staircase = Candidate("staircase", ["train"], ["held_train"])
    fit_alone(ctx, staircase, baseline)
    assert len(fits) == 6 and judged[-1][1:3] == (("twitch", "train", "long_train"), ("held_train",))
    assert staircase.evidence.crossed == () and len(identifying) == 2  # judged on the file's split: as it was


def _pair_world(monkeypatch):
    """A fake four-trial file whose fits and judgements are recorded: (context, baseline, fits, judgements)."""
    fits, judged = [], []
    p = load_parameters("CT09").with_values({q: v for n in ("fatigue", "staircase", "doublet_potentiation")
                                             for q, v in selection.extension_defaults(n).items()})

    def fake_fit(extensions, baseline_free, starts, calibration, *args, **kwargs):
        fits.append((tuple(extensions), tuple(t for t in calibration)))
        return SimpleNamespace(name=" + ".join(("baseline",) + tuple(extensions)), start="model before",
                               extensions=tuple(extensions), cost=1.0, simulated={}, parameters=p, free=("P0",))

    def fake_judge(ctx, name, before, model, held):
        judged.append((name, tuple(ctx.calibration), before.name, model.name, tuple(held)))
        return evidence()

    monkeypatch.setattr(selection, "fit_model", fake_fit)
    monkeypatch.setattr(selection, "calibration_chi2", lambda ctx, simulated: 2.0)
    monkeypatch.setattr(selection, "judge", fake_judge)
    monkeypatch.setattr(selection, "calibration_side", lambda ctx, name, before, model: (
        [], (70.0 if len(ctx.calibration) == 3 else 0.0, 10.0)))  # the gain tells which split it was read on
    monkeypatch.setattr(selection, "_starts", lambda ctx, name, before, screened: {})
    monkeypatch.setattr(selection, "heldout_chi2_gain", lambda *args: (90.0, 10.0))  # as evidence()
    monkeypatch.setattr(selection.Context, "measured", property(lambda ctx: {}))
    baseline = SimpleNamespace(name="baseline", extensions=(), simulated={}, parameters=p, free=("P0",))
    data = SimpleNamespace(trials={i: i for i in ("twitch", "train", "long_train", "held_train")})
    ctx = selection.Context(data, {}, ("twitch", "train", "long_train"), ("held_train",), {}, None, ("P0",))
    ctx.baseline = baseline
    return ctx, baseline, fits, judged


def test_a_pair_with_a_cross_validated_candidate_is_judged_on_that_split(monkeypatch):
    """Two at once where one candidate was cross-validated alone: the pair is fitted on the file's split (the model
    named), and the model before, each candidate alone and the pair again without that candidate's telling trials;
    each is judged there against the other alone, its own telling trials held out, and says so."""
    ctx, baseline, fits, judged = _pair_world(monkeypatch)
    fatigue, staircase = Candidate("fatigue", ["long_train"], []), Candidate("staircase", ["train"], ["held_train"])
    for c in (fatigue, staircase):
        c.screen = SimpleNamespace(score=10.0)
        fit_alone(ctx, c, baseline)
    fatigue.evidence.failed = {"R7": "failed"}  # material alone, fails another rule: a pair is tried
    del fits[:], judged[:]
    j = joint(ctx, Step(1, baseline, {"fatigue": fatigue, "staircase": staircase}))
    both = ("fatigue", "staircase")
    assert fits == [(both, ("twitch", "train", "long_train")),   # the pair on the file's split: the model named
                    (("staircase",), ("twitch", "train")),       # staircase alone without fatigue's telling trial
                    (both, ("twitch", "train"))]                 # (the refitted baseline and fatigue alone: kept)
    assert judged == [("fatigue", ("twitch", "train"), "baseline + staircase", "baseline + fatigue + staircase",
                       ("long_train",)),
                      ("staircase", ("twitch", "train"), "baseline + fatigue", "baseline + fatigue + staircase",
                       ("held_train",))]
    assert j.model.name == "baseline + fatigue + staircase" and j.alone["staircase"] is staircase.model
    assert all(e.crossed == ("long_train",) for e in j.evidence.values())
    assert "long_train held out too" in j.evidence["staircase"].text()
    # rule R1 of each: the pair fitted on every calibration trial (three), not on the split without long_train
    assert all(e.calibration_chi2_gain == 70.0 for e in j.evidence.values())


def test_a_pair_of_candidates_cross_validated_on_different_trials_is_judged_with_both_held_out(monkeypatch):
    """Both of the pair cross-validated alone, on different trials: the split that holds out both sets gets its own
    refitted baseline and each candidate alone on it."""
    ctx, baseline, fits, judged = _pair_world(monkeypatch)
    fatigue, doublet = Candidate("fatigue", ["long_train"], []), Candidate("doublet_potentiation", ["train"], [])
    for c in (fatigue, doublet):
        c.screen = SimpleNamespace(score=10.0)
        fit_alone(ctx, c, baseline)
    fatigue.evidence.failed = {"R7": "failed"}
    del fits[:], judged[:]
    j = joint(ctx, Step(1, baseline, {"fatigue": fatigue, "doublet_potentiation": doublet}))
    both = ("fatigue", "doublet_potentiation")
    assert fits == [(both, ("twitch", "train", "long_train")), ((), ("twitch",)), (("fatigue",), ("twitch",)),
                    (("doublet_potentiation",), ("twitch",)), (both, ("twitch",))]
    sub = ctx.crossed[("long_train", "train")]
    assert sub.baseline is not None
    assert [(name, held) for name, _, _, _, held in judged] == [("fatigue", ("long_train",)),
                                                               ("doublet_potentiation", ("train",))]
    assert all(e.crossed == ("long_train", "train") for e in j.evidence.values())


def test_where_a_length_cause_is_defined_follows_the_candidates_own_optimum():
    """Rule R7's window of length-dependent activation (trials more than 2 mm from the optimum): a model before
    without it has bent g1 towards the long side; the trials at the true optimum are then off its optimum, but
    the cause is judged where the candidate, which refits g1, puts them."""
    from neuromuscle.diagnose.phases import describe_all
    from neuromuscle.synth import extended_protocols
    from neuromuscle.synth.dataset import _empty_trial

    held = ("twitch_opt", "train3_opt", "twitch_long", "train10_short")
    trials = {p.trial_id: _empty_trial(p) for p in extended_protocols(-8.0) if p.trial_id in held}
    phases = describe_all(trials)
    noise = {i: SimpleNamespace(sd_N=0.1) for i in held}
    ctx = selection.Context(SimpleNamespace(trials=trials), phases, (), held, noise, None, ())
    base = load_parameters("CT09")

    def fitted(g1: float) -> SimpleNamespace:
        return SimpleNamespace(parameters=base.with_values({"g1": g1}), extensions=(),
                               simulated={i: np.full(t.time_s.size, 5.0) for i, t in trials.items()})

    bent, own = fitted(-4.0), fitted(-8.0)
    window, quiet = selection._windows(ctx, "length_dependent_activation", bent, own, [])
    assert quiet is None and set(window) == {"twitch_long", "train10_short"}
    window, _ = selection._windows(ctx, "length_dependent_activation", own, bent, [])
    assert set(window) == {"twitch_opt", "train3_opt", "train10_short"}     # judged on the bent optimum
