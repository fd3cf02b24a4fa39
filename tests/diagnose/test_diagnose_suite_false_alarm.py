"""The CI's sample of the suite, continued (a file of its own, so that the test runners share the long cases): its
null, one whose misfit looks like force enhancement in the held-out long stretch-hold must come back none.

The second null of ``--suite 10 --seed 2``: its reference falls short of the force at the long length, in the
isometric 40 Hz train as in the stretch-holds (-1.43 and -1.08 noise sd in the long hold).  The force-enhancement
extension adds that force after the stretch and gains 1154 noise variances held out, 318 in the held-out long
hold itself; with each model measured from its own misfit of the isometric force at the same length, as the cause
is defined, it gains -892 in the held-out holds, and rule 7 stops it (stop 39; without the isometric level it was
named).  About 5 min in CI on 2 cores."""

from neuromuscle.bench.diagnose_suite import run_suite, score


def test_a_null_short_of_the_isometric_force_at_the_long_length_is_not_force_enhancement():
    res = run_suite(2, causes=["none"], seed=2, workers=2, first=2)
    assert len(res["cases"]) == 1
    case = res["cases"][0]
    assert case["seed"] == 1271443486, case  # the draw: the second null of --seed 2
    assert case["verdict"] == "none", case
    assert "force_enhancement_after_stretch" in case["candidates_fitted"], case  # fitted, and stopped by rule 7
    assert any(f.startswith("where the cause is defined") for f in
               case["candidates_fitted"]["force_enhancement_after_stretch"]), case
    assert score(res["cases"])["false_alarm_rate_pct"] == 0.0
