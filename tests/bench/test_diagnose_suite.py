"""``neuromuscle bench diagnose --suite``: the draws per world, the two-effect files and the scoring from each case's
``named`` list (the diagnoses themselves are measured by the command and by tests/diagnose)."""

import gzip
import json
import re
from pathlib import Path

import pytest

from neuromuscle.bench.diagnose_suite import (NULL_ROW, SuiteCase, _evidence_row, judge_case, read_journals, score,
                                              score_journals, suite_cases, table_lines)
from neuromuscle.diagnose.evidence import Evidence
from neuromuscle.diagnose.rules import apply_rules
from neuromuscle.errors import InputError
from neuromuscle.cli import main
from neuromuscle.synth import CAUSES, OUTSIDE


def test_cases_cover_every_cause_the_outside_effect_and_none_in_every_world_reproducibly():
    cases = suite_cases(2, worlds=("B", "A-reduced"))
    for w in ("B", "A-reduced"):
        names = [c.label for c in cases if c.world == w]
        assert sorted(set(names)) == sorted([*CAUSES, *OUTSIDE, "none"])
        assert all(names.count(n) == 2 for n in set(names))
    assert cases == suite_cases(2, worlds=("B", "A-reduced"))
    assert cases != suite_cases(2, seed=1, worlds=("B", "A-reduced"))
    for c in cases:
        assert (c.effects == ()) == (c.label == "none")
        assert all(0.25 <= s <= 1.0 for _, s in c.effects) and 1.0 <= c.noise_pct <= 2.0
    a_null = next(c for c in cases if c.world == "A-reduced" and c.label == "none")
    assert a_null.expected()["required"] == ["length_dependent_activation"]  # eq 18 in the data


def test_a_world_and_a_subset_keep_their_draws():
    whole = suite_cases(3, seed=1, worlds=("B", "A"))
    assert suite_cases(3, seed=1, worlds=("A",)) == [c for c in whole if c.world == "A"]
    sub = suite_cases(3, ["relaxation_rate", "none"], seed=1, worlds=("B",))
    assert sub == [c for c in whole if c.world == "B" and c.label in ("relaxation_rate", "none")]


def test_two_effect_files_carry_two_different_causes():
    pairs = [c for c in suite_cases(0, seed=3, worlds=("B",), two_effect=6)]
    assert len(pairs) == 6 and all(len(c.effects) == 2 and c.effects[0][0] != c.effects[1][0] for c in pairs)
    assert all(n in CAUSES for c in pairs for n, _ in c.effects)


def _case(world, *names):
    return SuiteCase(world, tuple((n, 0.5) for n in names), 1.5, 1)


def test_judging_a_case_from_what_it_named():
    s = judge_case(_case("B", "staircase"), ["staircase"], ["staircase"])
    assert s["hits"] == {"staircase": True} and not s["wrong_names"]
    s = judge_case(_case("B", "fatigue"), ["staircase"], ["staircase"])
    assert s["hits"] == {"fatigue": False} and s["wrong_names"] == ["staircase"]
    s = judge_case(_case("A"), ["length_dependent_activation"], ["length_dependent_activation"])
    assert not s["false_alarm"] and s["background_named"] == {"length_dependent_activation": True}
    s = judge_case(_case("A"), ["length_dependent_activation", "fatigue"], ["length_dependent_activation", "fatigue"])
    assert s["false_alarm"] and s["wrong_names"] == ["fatigue"]
    s = judge_case(_case("B"), ["unexplained"], [])
    assert s["false_alarm"]
    s = judge_case(_case("B", "transducer_drift"), ["unexplained"], [])
    assert s["unexplained_hit"] and not s["wrong_names"]
    s = judge_case(_case("B", "staircase", "fatigue"), ["fatigue", "staircase"], ["fatigue", "staircase"])
    assert s["both_named"] is True
    s = judge_case(_case("A-movement", "staircase"), ["staircase", "movement_induced_depression"], ["staircase"])
    assert not s["wrong_names"]  # the data's own eqs 19-20 may be named


def test_score_counts_hits_false_alarms_wrong_names_and_pairs():
    def row(world, names, named, passed=None, error=None):
        c = _case(world, *names)
        r = {"world": world, "effects": [list(e) for e in c.effects], "named": named}
        if error:
            return {**r, "error": error}
        return {**r, "score": judge_case(c, named, named if passed is None else passed)}

    rows = [row("B", ["staircase"], ["staircase"]), row("B", ["staircase"], ["staircase"], passed=[]),
            row("B", ["fatigue"], ["staircase"]), row("B", [], []), row("B", [], ["fatigue"]),
            row("A", [], ["length_dependent_activation"]), row("B", ["staircase", "fatigue"], ["fatigue"]),
            row("B", ["fatigue"], [], error="boom")]
    s = score(rows)
    assert s["per_world"]["B"]["staircase"] == {"n": 3, "hits": 1, "hit_rate_pct": 33.3}
    assert s["false_alarms"] == 1 and s["nulls"] == 3 and s["files_with_a_wrong_name"] == 1
    assert s["two_effect_files"] == 1 and s["both_named"] == 0 and s["errors"] == 1
    assert s["per_world"]["A"]["length_dependent_activation (background)"]["hits"] == 1
    assert "false alarms 1 of 3 nulls" in table_lines(s)[-1]
    assert s["per_world"]["B"][NULL_ROW] == {"n": 2, "hits": 1, "hit_rate_pct": 50.0}
    assert s["per_world"]["A"][NULL_ROW]["hits"] == 1  # eq 18 alone is right in an eq-18 world
    assert s["worlds"]["B"] == {"hidden_causes": 5, "hidden_named": 2, "hit_rate_pct": 40.0,
                                "files_with_a_wrong_name": 1, "nulls": 2, "false_alarms": 1,
                                "two_effect_files": 1, "both_named": 0}
    assert s["worlds"]["A"]["nulls"] == 1 and s["worlds"]["A"]["false_alarms"] == 0
    assert s["causes"] == {"fatigue": {"n": 2, "hits": 1, "hit_rate_pct": 50.0},
                           "staircase": {"n": 3, "hits": 1, "hit_rate_pct": 33.3}}
    lines = table_lines(s)
    assert "| B | 2 of 5 | 40.0 | 1 | 1 / 2 | 0 / 1 |" in lines and "| staircase | 3 | 1 | 33.3 |" in lines


def _record(world, names, named, seed):
    c = SuiteCase(world, tuple((n, 0.5) for n in names), 1.5, seed)
    return {"world": world, "effects": [list(e) for e in c.effects], "seed": seed, "label": c.label,
            "named": named, "score": judge_case(c, named, named)}


def _write(path, rows):
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))
    return str(path)


def test_journals_of_several_runs_score_as_one_suite(tmp_path, capsys):
    first = [_record("A", [], ["length_dependent_activation"], 1), _record("B", ["fatigue"], ["fatigue"], 2)]
    second = [_record("B", [], ["staircase"], 3), _record("B", ["staircase"], [], 4)]
    a, b = _write(tmp_path / "a.jsonl", first), _write(tmp_path / "b.jsonl", second)
    res = score_journals([a, b])
    assert res["n_cases"] == 4 and res == {**score(first + second), "journals": [a, b], "n_cases": 4}
    assert res["nulls"] == 2 and res["false_alarms"] == 1 and res["hidden_named"] == 1
    assert main(["bench", "diagnose", "--score", a, b]) == 0
    out = capsys.readouterr().out
    assert "false alarms 1 of 2 nulls" in out and f"| B | {NULL_ROW} | 1 | 0 |" in out
    packed = tmp_path / "b.jsonl.gz"
    packed.write_bytes(gzip.compress(Path(b).read_bytes()))
    assert score_journals([a, str(packed)]) == {**res, "journals": [a, str(packed)]}


@pytest.mark.parametrize("text, message", [("{not json\n", "line 2: not a JSON line"),
                                           ('{"world": "B"}\n', "line 2: not a case record"),
                                           ("DUP", "line 2: the case (world A, none, seed 1) is already in")])
def test_a_bad_journal_is_refused_naming_its_file_and_line(tmp_path, text, message):
    good = json.dumps(_record("A", [], ["length_dependent_activation"], 1)) + "\n"
    path = tmp_path / "j.jsonl"
    path.write_text(good + (good if text == "DUP" else text))
    with pytest.raises(InputError, match=re.escape(f"j.jsonl, {message}")):
        read_journals([str(path)])
    with pytest.raises(InputError, match="cannot read"):
        read_journals([str(tmp_path / "missing.jsonl")])
    (tmp_path / "cut.jsonl.gz").write_bytes(gzip.compress(good.encode())[:-9])
    with pytest.raises(InputError, match="cut.jsonl.gz: cannot read"):
        read_journals([str(tmp_path / "cut.jsonl.gz")])
    bad = bytearray(gzip.compress(good.encode() * 20))
    bad[20] ^= 0xFF
    bad[30] ^= 0xFF
    (tmp_path / "bad.jsonl.gz").write_bytes(bytes(bad))
    with pytest.raises(InputError, match="bad.jsonl.gz: cannot read"):
        read_journals([str(tmp_path / "bad.jsonl.gz")])


@pytest.mark.parametrize("argv, message", [(["--suite", "-1"], "seeds"),
                                           (["--suite", "1", "--causes", "gout"], "unknown cause"),
                                           (["--suite", "1", "--worlds", "Z"], "unknown world"),
                                           (["--causes", "fatigue"], "need --suite"),
                                           (["--journal", "j.jsonl"], "need --suite"),
                                           (["--first", "2"], "need --suite"),
                                           (["--two-effect", "2"], "need --suite"),
                                           (["--separability"], "need --suite"),
                                           (["--reach"], "need --suite"),
                                           (["--score", "j.jsonl", "--suite", "1"], "takes no --suite"),
                                           (["--score", "j.jsonl", "--reach"], "takes no --reach"),
                                           (["--suite", "1", "--first", "13"], "between 1 and 12"),
                                           (["--world", "Z"], "unknown world"),
                                           (["--cause", "gout"], "gout"),
                                           (["--cause", "fatigue", "--strength", "2"], "strength")])
def test_bad_suite_arguments_are_refused_before_any_work(argv, message, capsys):
    assert main(["bench", "diagnose", *argv]) != 0
    assert message in capsys.readouterr().err


def test_a_candidates_row_says_which_rules_it_failed_and_why_with_the_windows_bootstrap():
    """A journal row tells a rule R7 failure by the window's bootstrap from one by its gain, without a re-run."""
    ev = Evidence(3, gain=900.0, chi2_gain=600.0, bic_penalty=20.0, bootstrap_p05=150.0, excess=1000.0,
                  nrmse_before=5.0, nrmse_after=4.0, structured_before=["a"], identified=["x.k"],
                  calibration_chi2_gain=400.0, calibration_penalty=25.0, window_how="defined",
                  window_chi2_gain=4904.94, window_penalty=19.2, window_p05=-1130.7,
                  window_trials={"a": {"chi2_gain": 4904.94}},
                  per_trial={"a": {"gain": 900.0, "excess": 1000.0, "nrmse_before": 5.0, "nrmse_after": 4.0}},
                  crossed=("a",))
    row = _evidence_row(apply_rules(ev))
    assert row["failed"] == ["R7"] and "bootstrap 5th percentile -1.13e+03" in row["why"]["R7"]
    assert row["window_chi2_gain"] == 4904.9 and row["window_p05"] == -1130.7
    assert row["quiet_chi2_gain"] is None and row["quiet_p05"] is None
    assert row["cross_validated_trials"] == ["a"] and row["trials"]["a"]["window_chi2_gain"] == 4904.9
    assert row["trials"]["a"]["nrmse"] == [5.0, 4.0]
    json.dumps(row)  # a journal line
