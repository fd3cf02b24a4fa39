"""Blind diagnoses: a null preparation with one calibration misfit -> "none"; a hidden fatigue-like effect (release
weights by stimulus count, not the extension's depletion state) -> "fatigue" with a positive held-out gain."""

import json

from neuromuscle.parameters import load_parameters


def test_null_with_calibration_misfit_is_none(null_files):
    _, out, doc = null_files
    assert doc["verdict"] == "none", json.dumps(doc["causes"], indent=1)
    assert doc["baseline"]["nrmse"]["long50_short"] > 3.0  # the misfit is there
    assert all(not c["statistics"]["passed"] for c in doc["causes"] if c.get("fitted"))


def test_hidden_fatigue_is_found_with_heldout_gain(fatigue_files):
    _, out, doc = fatigue_files
    assert doc["verdict"] == "fatigue", json.dumps(doc["causes"], indent=1)
    best = doc["causes"][0]
    assert best["name"] == "fatigue" and best["statistics"]["passed"]
    assert best["nrmse_heldout_after"] < best["nrmse_heldout_before"]
    assert best["statistics"]["gain_noise_units"] > 0 and best["statistics"]["chi2_gain"] > best["statistics"]["bic_penalty"]
    k = best["parameters"]["fatigue.k"]
    assert k["ci95"][0] > k["neutral"]
    params = load_parameters(out / "params.json")
    assert params["fatigue.k"] == k["value"]
