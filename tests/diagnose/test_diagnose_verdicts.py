"""Blind diagnoses of small preparations: a null with one calibration misfit -> nothing named; a hidden
fatigue-like effect (release weights by stimulus count, not the extension's depletion state) -> "fatigue" with a
held-out gain that passes every rule.  Slow: the default run's blind diagnoses are the sample of
test_diagnose_sample_*.py (a null and named causes of the synth worlds); these two add a generator of their own."""

import json

import pytest

from neuromuscle.parameters import load_parameters

pytestmark = [pytest.mark.slow, pytest.mark.heavy(cost_s=40)]


def test_null_with_calibration_misfit_names_nothing(null_files):
    _, out, doc = null_files
    assert doc["named"] == [] and doc["verdict"] == "none", json.dumps(doc["causes"], indent=1)
    assert "long50_short" in doc["split"]["calibration"]  # the misfit calibrates: the baseline takes it up
    assert all(not c["statistics"]["passed"] for c in doc["causes"] if c.get("fitted"))


def test_hidden_fatigue_is_named_with_heldout_gain(fatigue_files):
    _, out, doc = fatigue_files
    assert doc["named"][0] == "fatigue" and doc["verdict"] == "fatigue", json.dumps(doc["causes"], indent=1)
    best = doc["causes"][0]
    assert best["name"] == "fatigue" and best["named"] and best["statistics"]["passed"]
    assert best["nrmse_heldout_after"] < best["nrmse_heldout_before"]
    st = best["statistics"]
    assert st["gain_noise_variances"] > 0 and st["chi2_gain"] > st["bic_penalty"] and st["failed"] == {}
    detail = doc["named_detail"][0]
    assert detail["name"] == "fatigue" and detail["heldout_chi2_gain"] == st["chi2_gain"]
    params = load_parameters(out / "params.json")
    assert params["fatigue.k"] > 0.0
