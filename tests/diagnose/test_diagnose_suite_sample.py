"""The CI's sample of ``neuromuscle bench diagnose --suite``: a synth preparation of the suite's draws (seed 1),
made with ``neuromuscle synth`` and diagnosed blind, must be named with a held-out gain that passes every rule.
One case (about 3 min on 2 cores); the rates over five seeds per cause are the benchmark's, in docs/diagnosis.md.
The null and the fatigue-like effect of tests/diagnose's own preparations are test_diagnose_verdicts.py."""

from neuromuscle.bench.diagnose_suite import run_suite, score


def test_hidden_length_dependent_activation_is_named_blind():
    res = run_suite(1, causes=["length_dependent_activation"], seed=1, workers=2)
    case = res["cases"][0]
    assert case["verdict"] == "length_dependent_activation", case
    assert case["gain_ok"] and case["heldout_gain"] > 0, case
    assert score(res["cases"])["hit_rate_pct"] == 100.0
