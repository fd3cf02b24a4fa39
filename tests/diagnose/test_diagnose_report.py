"""diagnosis.json schema, report.md, figures, params.json, and the refusal to overwrite."""

import json

import pytest

from neuromuscle.cli import main
from neuromuscle.diagnose import REPORT_FILES, SCHEMA, run_diagnosis
from neuromuscle.diagnose.candidates import CAUSES
from neuromuscle.diagnose.report import markdown
from neuromuscle.errors import InputError
from neuromuscle.parameters import load_parameters


def test_diagnosis_json_schema(null_files):
    path, out, _ = null_files
    doc = json.loads((out / "diagnosis.json").read_text())
    assert doc["schema"] == SCHEMA
    assert doc["verdict"] in {c.name for c in CAUSES} | {"none", "unexplained"}
    assert set(doc["split"]) >= {"calibration", "heldout"}
    assert set(doc["split"]["calibration"]) | set(doc["split"]["heldout"]) == set(doc["baseline"]["nrmse"])
    assert not set(doc["split"]["calibration"]) & set(doc["split"]["heldout"])
    assert all(isinstance(v, float) for v in doc["baseline"]["nrmse"].values())
    ref = doc["reference"]  # what the candidates are judged against: Module 2, the pump and tau2 refitted
    assert set(ref["module2"]) == {"C1", "C2", "C3", "alpha"}
    assert 200.0 <= ref["Umax_M_per_ms"] <= 20000.0
    assert 2.5 <= ref["tau2_ms"] <= 250.0
    for c in doc["causes"]:
        assert {"name", "evidence", "parameters", "nrmse_heldout_before", "nrmse_heldout_after"} <= set(c)
        assert isinstance(c["nrmse_heldout_before"], float) and isinstance(c["nrmse_heldout_after"], float)
        for p in c["parameters"].values():
            assert p["ci95"][0] <= p["value"] <= p["ci95"][1]
    screened = [r["screening"] for r in doc["ranking"] if "screening" in r]
    assert screened  # where on the time-constant grid each screen was best ({}: the defaults)
    assert all(isinstance(v, float) for s in screened for v in s["time_constants"].values())
    names = [c["name"] for c in doc["causes"]] + [u["name"] for u in doc["untestable"]]
    assert sorted(names) == sorted(c.name for c in CAUSES)
    assert "staircase" in [u["name"] for u in doc["untestable"]]  # no train of >= 5 stimuli at <= 15 Hz


def test_report_md_verdict_first_and_figures(null_files):
    _, out, doc = null_files
    text = (out / "report.md").read_text()
    assert text.splitlines()[2].startswith("**Verdict: none.**")
    assert "| trial | side |" in text
    assert doc["figures"] and all((out / p).is_file() for p in doc["figures"].values())
    assert "residual" in doc["figures"]
    load_parameters(out / "params.json")


def test_report_md_names_the_other_passing_candidates(null_files):
    """When a second candidate passes every rule, report.md says so and gives both whole-file scores (the verdict
    is the larger, verdict.choose)."""
    _, _, doc = null_files
    doc = json.loads(json.dumps(doc))

    def cause(name, passed, score):
        return {"name": name, "fitted": True, "evidence": "...", "parameters": {}, "nrmse_heldout_before": 3.0,
                "nrmse_heldout_after": 2.0, "statistics": {"passed": passed, "whole_file_score": score}}

    doc["verdict"] = "staircase"
    doc["causes"] = [cause("staircase", True, 5371.5), cause("relaxation_rate", True, 4091.2),
                     cause("fatigue", False, 9999.0)]
    text = markdown(doc)
    assert "**Verdict: staircase.**" in text
    assert "Also passing every rule: relaxation_rate." in text and "staircase 5371.5; relaxation_rate 4091.2" in text
    assert "fatigue 9999" not in text
    doc["causes"] = doc["causes"][:1]
    assert "Also passing" not in markdown(doc)


def test_refuses_to_overwrite(null_files):
    path, out, _ = null_files
    before = {n: (out / n).read_bytes() for n in REPORT_FILES}
    with pytest.raises(InputError, match="refusing to overwrite"):
        run_diagnosis(path, out)
    assert main(["diagnose", str(path), "--out", str(out), "--quiet"]) == 2
    assert {n: (out / n).read_bytes() for n in REPORT_FILES} == before
