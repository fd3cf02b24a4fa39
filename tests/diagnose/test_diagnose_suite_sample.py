"""The CI's sample of ``neuromuscle bench diagnose --suite``: synth preparations of the suite's draws, made with
``neuromuscle synth`` (its extended protocol set, the suite's since stop 36) and diagnosed blind.  Its hidden
effect is here: an effect must be named with a held-out gain that passes every rule.  Its null is
test_diagnose_suite_false_alarm.py (a file of its own, so that the two test runners share the long cases).  The
rates over five seeds per cause are the benchmark's, in docs/diagnosis.md; the null and the fatigue-like effect of
tests/diagnose's own, smaller preparations are test_diagnose_verdicts.py.

The effect is relaxation_rate, the suite's weakest cause: ``--suite 5 --seed 1``'s seed 3, spread thin over many
trials.  Its reference leaves no held-out trial above 1.5 noise sd (the four largest at 1.38-1.42), so until stop
37 the rule "something to explain" stopped relaxation_rate, which removes 59 % of the held-out excess; since stop
38 a candidate that removes more than half of that excess has something to explain (neuromuscle.diagnose.verdict,
rule 0).  About 5 min in CI on 2 cores (stop 40).

Until stop 42 the sample also diagnosed seed 1's length-dependent activation (~4.5 min of CPU), a strong effect
named in every suite run since stop 27; it left the CI to bring the suite toward 15 min on the slower machine
(docs/diagnosis.md, stop 42).  Until stop 39 it also held the five-seed suite's fifth null, whose release decays a
third faster than CT09's; its mechanism stays tested in
test_diagnose_reference.py::test_the_reference_takes_up_a_faster_release_decay."""

from neuromuscle.bench.diagnose_suite import run_suite, score


def test_a_hidden_relaxation_effect_below_the_trial_threshold_is_named_when_the_extension_explains_most_of_it():
    res = run_suite(3, causes=["relaxation_rate"], seed=1, workers=2, first=3)
    assert len(res["cases"]) == 1
    case = res["cases"][0]
    assert case["verdict"] == "relaxation_rate", case
    assert case["gain_ok"] and case["heldout_gain"] > 0, case
    assert score(res["cases"])["hit_rate_pct"] == 100.0
