"""The CI's sample of ``neuromuscle bench diagnose --suite``: synth preparations of the suite's draws (seed 1), made
with ``neuromuscle synth`` (its extended protocol set, the suite's since stop 36) and diagnosed blind: an effect
must be named with a held-out gain that passes every rule, and the null that was the five-seed suite's false alarm
must come back none.  Two cases (about 3 and 2 min on 2 cores); the rates over five seeds per cause are the
benchmark's, in docs/diagnosis.md.  The null and the fatigue-like effect of tests/diagnose's own preparations are
test_diagnose_verdicts.py."""

from neuromuscle.bench.diagnose_suite import run_suite, score


def test_hidden_length_dependent_activation_is_named_blind():
    res = run_suite(1, causes=["length_dependent_activation"], seed=1, workers=2)
    case = res["cases"][0]
    assert case["verdict"] == "length_dependent_activation", case
    assert case["gain_ok"] and case["heldout_gain"] > 0, case
    assert score(res["cases"])["hit_rate_pct"] == 100.0


def test_the_null_whose_release_decays_faster_is_none():
    """Suite seed 5's null (the fifth null of ``--suite 5 --seed 1``): its preparation's release decays a third
    faster than CT09's (tau2 0.66 x), which relaxation_rate took up (gain 1749, every rule passed) until the
    reference refitted tau2."""
    res = run_suite(5, causes=["none"], seed=1, workers=2, first=5)
    assert len(res["cases"]) == 1
    case = res["cases"][0]
    assert case["verdict"] == "none", case
    assert score(res["cases"])["false_alarm_rate_pct"] == 0.0
