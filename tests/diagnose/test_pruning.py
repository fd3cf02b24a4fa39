"""The backward check (pruning.py): which named causes are judged again, against which model, and which are
dropped.  The fits are faked; the sample diagnoses exercise them."""

from types import SimpleNamespace

from conftest import evidence
from neuromuscle.diagnose import pruning, selection
from neuromuscle.diagnose.pruning import prune
from neuromuscle.diagnose.selection import Candidate, Step


def fitted(extensions) -> SimpleNamespace:
    exts = tuple(extensions)
    return SimpleNamespace(name=" + ".join(("baseline",) + exts), extensions=exts, simulated={}, parameters=None,
                           wall_s=0.0)


def world(monkeypatch, fails: dict[str, tuple[str, ...]], named: list[list[str]], crossed: dict | None = None):
    """A file whose forward selection named ``named`` (one list a step) and whose backward judgements fail the
    rules ``fails[(cause, model before)]``; returns (context, steps, fits, judgements)."""
    fits, judged = [], []

    def fake_fit(extensions, baseline_free, starts, calibration, *args, **kwargs):
        fits.append((tuple(extensions), tuple(calibration)))
        return fitted(extensions)

    def fake_judge(ctx, name, before, model, held):
        judged.append((name, before.name, model.name, tuple(ctx.heldout)))
        return evidence(fails.get((name, before.name), ()), chi2_gain=90.0 - len(judged))

    for module in (pruning, selection):
        monkeypatch.setattr(module, "fit_model", fake_fit)
    monkeypatch.setattr(pruning, "judge", fake_judge)
    monkeypatch.setattr(pruning, "noise_under", lambda ctx, model: {})
    data = SimpleNamespace(trials={i: i for i in ("twitch", "train", "long_train", "held_train")})
    ctx = selection.Context(data, {}, ("twitch", "train", "long_train"), ("held_train",), {}, None, ("P0",))
    ctx.baseline = fitted(())
    steps, have = [], []
    for k, names in enumerate(named + [[]], start=1):
        before = fitted(have)
        cands = {n: Candidate(n, ["train"], ["held_train"]) for n in names}
        for n, c in cands.items():
            c.model, c.evidence = fitted(have + [n]), evidence()
            c.evidence.crossed = (crossed or {}).get(n, ())
        s = Step(k, before, cands, named=names[0] if names else None)
        if len(names) == 2:
            s.joint = selection.Joint(tuple(names), fitted(have + names), {n: fitted(have + [n]) for n in names},
                                      {n: cands[n].evidence for n in names})
        have = have + names
        if names:
            s.consolidated = fitted(have)
        steps.append(s)
    return ctx, steps, fits, judged


def test_a_cause_the_later_one_explains_is_dropped(monkeypatch):
    ctx, steps, fits, judged = world(monkeypatch, {("a", "baseline + b"): ("R2", "R4")}, [["a"], ["b"]])
    p = prune(ctx, steps)
    assert judged == [("a", "baseline + b", "baseline + a + b", ("held_train",))]   # b was judged at the last step
    assert fits == [(("b",), ("twitch", "train", "long_train"))]
    assert p.named == ["b"] and p.dropped == ["a"] and p.final.name == "baseline + b"
    assert p.checks[0].round == 1 and p.checks[0].evidence.failed == {"R2": "failed", "R4": "failed"}


def test_only_a_rule_of_redundancy_drops_a_cause(monkeypatch):
    # failing how much it explains (R4) or where it acts (R5, R7) against a related later cause keeps it
    for rules in (("R7",), ("R4", "R5"), ("R6",), ("R4", "R5", "R6", "R7")):
        ctx, steps, fits, judged = world(monkeypatch, {("a", "baseline + b"): rules}, [["a"], ["b"]])
        p = prune(ctx, steps)
        assert p.named == ["a", "b"] and p.dropped == [] and p.final is steps[-1].after
        assert set(p.checks[0].evidence.failed) == set(rules) and not p.checks[0].dropped
    # any one of R0-R3 drops it, whatever else it fails
    for rules in (("R0",), ("R1",), ("R2",), ("R3", "R7"), ("R2", "R3", "R4")):
        ctx, steps, fits, judged = world(monkeypatch, {("a", "baseline + b"): rules}, [["a"], ["b"]])
        assert prune(ctx, steps).dropped == ["a"]


def test_causes_that_pass_against_the_others_are_kept(monkeypatch):
    ctx, steps, fits, judged = world(monkeypatch, {}, [["a"], ["b"]])
    p = prune(ctx, steps)
    assert p.named == ["a", "b"] and p.dropped == [] and p.final is steps[-1].after and len(p.checks) == 1


def test_one_cause_or_one_step_is_not_judged_again(monkeypatch):
    for named in ([["a"]], [["a", "b"]], []):
        ctx, steps, fits, judged = world(monkeypatch, {}, named)
        p = prune(ctx, steps)
        assert not judged and not fits and p.checks == [] and p.named == [n for s in named for n in s]


def test_after_a_drop_every_cause_left_is_judged_against_the_new_final_model(monkeypatch):
    fails = {("a", "baseline + b + c"): ("R3",), ("b", "baseline + a + c"): ("R2", "R3")}
    ctx, steps, fits, judged = world(monkeypatch, fails, [["a"], ["b"], ["c"]])
    p = prune(ctx, steps)
    # round 1: a and b (c was named last); both fail, b (judged second: the lower gain here) is the worst
    assert [j[:2] for j in judged[:2]] == [("a", "baseline + b + c"), ("b", "baseline + a + c")]
    # round 2: a and c against baseline + a + c without each, both pass
    assert [j[:2] for j in judged[2:]] == [("a", "baseline + c"), ("c", "baseline + a")]
    assert p.named == ["a", "c"] and p.dropped == ["b"] and p.final.name == "baseline + a + c"
    assert [(c.name, c.round, c.dropped) for c in p.checks] == [("b", 1, True), ("a", 2, False), ("c", 2, False)]


def test_a_cause_named_by_cross_validation_is_judged_on_that_split_again(monkeypatch):
    ctx, steps, fits, judged = world(monkeypatch, {}, [["fatigue"], ["b"]], crossed={"fatigue": ("long_train",)})
    candidates, identified = [], []

    def fake_candidate_on(sub, c, before_cv):
        candidates.append((c.name, before_cv.name, tuple(sub.calibration)))
        return fitted(before_cv.extensions + (c.name,))

    def fake_identified(ev, ctx_, name, before, model):
        identified.append((name, before.name, model.name, tuple(ctx_.calibration)))
        return ev

    monkeypatch.setattr(pruning, "candidate_on", fake_candidate_on)
    monkeypatch.setattr(pruning, "scored_on_every_calibration_trial", fake_identified)
    p = prune(ctx, steps)
    assert judged == [("fatigue", "baseline + b", "baseline + b + fatigue", ("held_train", "long_train"))]
    assert fits == [(("b",), ("twitch", "train", "long_train")),   # the final model without fatigue
                    ((), ("twitch", "train")),                     # the baseline without its trial (its excess there)
                    (("b",), ("twitch", "train"))]                 # the model before, again without it
    # the cause fitted on the split from its own starts, as when it was named, not the final model refitted there
    assert candidates == [("fatigue", "baseline + b", ("twitch", "train"))]
    # and whether it is identified asked of every calibration trial, against the final model without it
    assert identified == [("fatigue", "baseline + b", "baseline + fatigue + b", ("twitch", "train", "long_train"))]
    assert p.checks[0].evidence.crossed == ("long_train",) and p.named == ["fatigue", "b"]
