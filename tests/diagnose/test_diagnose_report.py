"""diagnosis.json schema, report.md, figures, params.json, and the refusal to overwrite."""

import json

import pytest

from neuromuscle.cli import main
from neuromuscle.diagnose import REPORT_FILES, SCHEMA, run_diagnosis
from neuromuscle.diagnose.causes import causes
from neuromuscle.diagnose.report import markdown
from neuromuscle.diagnose.rules import RULES
from neuromuscle.errors import InputError
from neuromuscle.parameters import load_parameters


def test_diagnosis_json_schema(null_files):
    path, out, _ = null_files
    doc = json.loads((out / "diagnosis.json").read_text())
    assert doc["schema"] == SCHEMA
    assert doc["verdict"] in set(causes()) | {"none", "unexplained"}
    assert isinstance(doc["named"], list) and all(n in set(causes()) | {"unexplained"} for n in doc["named"])
    assert set(doc["split"]) >= {"calibration", "heldout"}
    assert set(doc["split"]["calibration"]) | set(doc["split"]["heldout"]) == set(doc["baseline"]["nrmse"])
    assert not set(doc["split"]["calibration"]) & set(doc["split"]["heldout"])
    assert all(isinstance(v, float) for v in doc["baseline"]["nrmse"].values())
    b = doc["baseline"]
    assert {"C1", "C2", "C3", "alpha", "Umax", "tau2", "P0"} <= set(b["free"]) and isinstance(b["converged"], bool)
    assert b["start"] in b["start_costs"]
    for c in doc["causes"]:
        assert {"name", "evidence", "parameters", "nrmse_heldout_before", "nrmse_heldout_after"} <= set(c)
        for p in c["parameters"].values():
            assert p["ci95"][0] <= p["value"] <= p["ci95"][1]
    assert doc["steps"] and doc["steps"][0]["model_before"]["extensions"] == []
    cands = doc["steps"][0]["candidates"]
    assert sorted(c["name"] for c in cands) == sorted(causes())
    assert any(c["screening"] is not None for c in cands)
    assert [r["id"] for r in doc["rules"]] == [r.id for r in RULES]
    assert "staircase" in [u["name"] for u in doc["untestable"]]  # no isometric train of >= 5 stimuli at <= 15 Hz
    assert doc["backward_check"] == []   # nothing named: nothing judged again


def test_report_md_named_first_rules_and_figures(null_files):
    _, out, doc = null_files
    text = (out / "report.md").read_text()
    assert text.splitlines()[2].startswith("**Named: none.**")
    assert "| trial | side |" in text and "## Decision rules" in text
    assert all(f"| {r.id} | {r.name} |" in text for r in RULES)
    assert doc["figures"] and all((out / p).is_file() for p in doc["figures"].values())
    assert "baseline residual" in doc["figures"]
    load_parameters(out / "params.json")


def test_report_md_lists_each_named_cause_with_its_gain(null_files):
    _, _, doc = null_files
    doc = json.loads(json.dumps(doc))
    doc["named"] = ["length_dependent_activation", "fatigue", "unexplained"]
    doc["named_detail"] = [{"name": "length_dependent_activation", "step": 1, "heldout_chi2_gain": 12188.3,
                            "bic_penalty": 29.4, "excess_removed": 0.96, "nrmse_heldout_before": 14.5,
                            "nrmse_heldout_after": 3.9},
                           {"name": "fatigue", "step": 2, "heldout_chi2_gain": 812.0, "bic_penalty": 20.1,
                            "excess_removed": 0.6, "nrmse_heldout_before": 3.9, "nrmse_heldout_after": 3.1}]
    text = markdown(doc)
    assert "**Named: length_dependent_activation, fatigue, unexplained.**" in text
    assert "1. **length_dependent_activation**" in text and "2. **fatigue**" in text
    assert "Then **unexplained**" in text


def test_report_md_shows_two_causes_named_together(null_files):
    """A step that names two causes together lists both, the pair's evidence (each beside the other) and each
    cause's parameters."""
    _, _, doc = null_files
    doc = json.loads(json.dumps(doc))
    pair = ["length_dependent_activation", "lengthening_below_optimum"]
    step = doc["steps"][0]
    step["named"] = pair
    step["together"] = {"names": pair, "passed": True, "model": {},
                        "evidence": {a: {"beside": b, "evidence": f"{a} gains", "statistics": {}}
                                     for a, b in (pair, pair[::-1])}}
    doc["causes"] = [{"name": n, "named": True, "step": step["step"],
                      "parameters": {f"{n}.k": {"value": 0.5, "unit": "1", "ci95": [0.4, 0.6], "neutral": 0.0}}}
                     for n in pair] + doc["causes"]
    text = markdown(doc)
    assert f"Named: **{pair[0]}, {pair[1]}** (together)." in text
    assert f"| {pair[0]} | {pair[1]} | {pair[0]} gains |" in text
    assert f"| {pair[1]} | {pair[0]} | {pair[1]} gains |" in text
    assert all(f"| {n}: parameter |" in text and f"| {n}.k | 0.5 |" in text for n in pair)


def test_report_md_shows_the_backward_check(null_files):
    """A cause dropped by the backward check: the table of its judgement, and its parameters still shown at the
    step that named it."""
    _, _, doc = null_files
    doc = json.loads(json.dumps(doc))
    doc["steps"][0]["named"] = ["movement_induced_depression"]
    doc["backward_check"] = [{"name": "movement_induced_depression", "round": 1, "dropped": True,
                              "against": ["force_depression_after_shortening"], "evidence": "fails R4", "model": {},
                              "statistics": {}}]
    doc["causes"] = [{"name": "movement_induced_depression", "named": False, "dropped": True, "step": 1,
                      "parameters": {"mid.k": {"value": 0.5, "unit": "1", "ci95": [0.4, 0.6], "neutral": 0.0}}}]
    text = markdown(doc)
    assert "## Backward check" in text
    assert ("| 1 | movement_induced_depression | baseline + force_depression_after_shortening | dropped | fails R4 |"
            in text)
    assert "| movement_induced_depression: parameter |" in text


def test_refuses_to_overwrite(null_files):
    path, out, _ = null_files
    before = {n: (out / n).read_bytes() for n in REPORT_FILES}
    with pytest.raises(InputError, match="refusing to overwrite"):
        run_diagnosis(path, out)
    assert main(["diagnose", str(path), "--out", str(out), "--quiet"]) == 2
    assert {n: (out / n).read_bytes() for n in REPORT_FILES} == before


def test_the_report_states_the_rules_from_the_rules_table(null_files):
    """diagnosis.json and report.md give the decision rules as rules.RULES states them, thresholds in force."""
    _, out, _ = null_files
    doc = json.loads((out / "diagnosis.json").read_text())
    assert doc["rules"] == [r.to_json() for r in RULES]
    section = (out / "report.md").read_text().split("## Decision rules", 1)[1]
    assert all(r.statement in section for r in RULES)
    assert "above 1.5 noise sd" in section
