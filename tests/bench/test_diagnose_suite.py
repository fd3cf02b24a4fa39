"""``neuromuscle bench diagnose --suite``: the draws and the scoring (the diagnoses themselves are measured by the
command, about 5 min each, and by tests/diagnose)."""

import pytest

from neuromuscle.bench.diagnose_suite import score, suite_cases, table_lines
from neuromuscle.cli import main
from neuromuscle.errors import InputError
from neuromuscle.synth import CAUSES, OUTSIDE


def test_cases_cover_every_cause_the_outside_effect_and_none_reproducibly():
    cases = suite_cases(2)
    names = [c.cause for c in cases]
    assert sorted(set(names)) == sorted([*CAUSES, *OUTSIDE, "none"])
    assert all(names.count(n) == 2 for n in set(names))
    assert cases == suite_cases(2) and cases != suite_cases(2, seed=1)
    for c in cases:
        assert (c.strength == 0.0) == (c.cause == "none") and (c.cause == "none" or 0.25 <= c.strength <= 1.0)
        assert 1.0 <= c.noise_pct <= 2.0
        assert c.expected == ("unexplained" if c.cause in OUTSIDE else c.cause)


def test_a_subset_has_the_draws_of_the_whole_suite():
    whole = suite_cases(3, seed=1)
    sub = suite_cases(3, ["relaxation_rate", "none"], seed=1)
    assert sub == [c for c in whole if c.cause in ("relaxation_rate", "none")]
    assert suite_cases(1, seed=1) == whole[:len(whole) // 3]  # the first seed of three is a suite of one


def _row(cause, expected, verdict, gain_ok):
    return {"cause": cause, "expected": expected, "verdict": verdict, "gain_ok": gain_ok}


def test_score_counts_hits_false_alarms_and_wrong_names():
    rows = [_row("staircase", "staircase", "staircase", True),
            _row("staircase", "staircase", "staircase", False),      # named, but no held-out gain: no hit
            _row("fatigue", "fatigue", "staircase", True),           # wrong name
            _row("fatigue", "fatigue", "none", False),
            _row("transducer_drift", "unexplained", "unexplained", False),
            _row("none", "none", "none", False),
            _row("none", "none", "fatigue", True)]                   # false alarm
    s = score(rows)
    assert s["per_cause"]["staircase"]["hits"] == 1 and s["per_cause"]["fatigue"]["wrong_name"] == 1
    assert s["hit_rate_pct"] == pytest.approx(100 * 2 / 5, abs=0.1)
    assert s["false_alarm_rate_pct"] == 50.0 and s["wrong_name_rate_pct"] == 20.0
    assert "false alarms on nulls 50.0 %" in table_lines(s)[-1]
    s = score(rows + [_row("staircase", "staircase", "error", False)])  # a case whose diagnosis raised
    assert s["errors"] == 1 and s["per_cause"]["staircase"]["wrong_name"] == 0
    assert s["hit_rate_pct"] == pytest.approx(100 * 2 / 6, abs=0.1)


@pytest.mark.parametrize("argv, message", [(["--suite", "0"], "seeds"), (["--suite", "1", "--causes", "gout"],
                                                                        "unknown cause"),
                                           (["--causes", "fatigue"], "need --suite"),
                                           (["--journal", "j.jsonl"], "need --suite"),
                                           (["--first", "2"], "need --suite"),
                                           (["--separability"], "need --suite"),
                                           (["--suite", "1", "--separability", "--first", "12"],
                                            "nulls are skipped"),
                                           (["--suite", "1", "--first", "13"], "between 1 and 12"),
                                           (["--protocols", "long"], "unknown protocol set"),
                                           (["--suite", "1", "--protocols", "long"], "unknown protocol set")])
def test_bad_suite_arguments_are_refused_before_any_work(argv, message, capsys):
    assert main(["bench", "diagnose", *argv]) != 0
    assert message in capsys.readouterr().err
