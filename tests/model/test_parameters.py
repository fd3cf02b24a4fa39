"""Parameter sets: shipped files with units, validation of names, values and units."""

import json

import pytest

from neuromuscle import InputError, load_parameters
from neuromuscle.parameters import SPECS, builtin_sets, kim_parameter_names


def test_builtin_sets_are_table_1(ct09, ct95):
    assert builtin_sets() == ["CT09", "CT95"]
    assert (ct09["P0"], ct09["KSE"], ct09["C3"], ct09["c0"]) == (23.0, 0.4, 61.206, -7.4)
    assert (ct95["P0"], ct95["g1"], ct95["a0"], ct95["phi1"]) == (28.9, -5.0, 0.18, 0.006)
    assert {SPECS.alias(k) for k in ct09} == set(kim_parameter_names())  # complete for Modules 1-3


def test_round_trip_through_a_file(ct09, tmp_path):
    path = tmp_path / "p.json"
    ct09.with_values(P0=30.0).save(path)
    assert load_parameters(path)["P0"] == 30.0


@pytest.mark.parametrize("change, match", [
    ({"Kx": 1.0}, "unknown parameter 'Kx'"),
    ({"P0": -1.0}, "'P0' = -1 N is outside its physiological range"),
    ({"tau1": float("nan")}, "'tau1' is not finite"),
    ({"K2": "fast"}, "'K2' must be a number"),
    ({"C3": 5000.0}, "'C3' = 5000 ms is outside its physiological range \\[2, 1000\\] ms"),
])
def test_bad_overrides_name_the_parameter(ct09, change, match):
    with pytest.raises(InputError, match=match):
        ct09.with_values(**change)


def test_file_with_wrong_unit_or_missing_parameter(ct09, tmp_path):
    doc = ct09.to_json()
    doc["parameters"]["tau2"]["unit"] = "s"
    (tmp_path / "u.json").write_text(json.dumps(doc))
    with pytest.raises(InputError, match="'tau2' has unit 's'"):
        load_parameters(tmp_path / "u.json")
    doc = ct09.to_json()
    del doc["parameters"]["b0"]
    (tmp_path / "m.json").write_text(json.dumps(doc))
    with pytest.raises(InputError, match="lacks b0"):
        load_parameters(tmp_path / "m.json")
    with pytest.raises(InputError, match="neither a built-in set"):
        load_parameters(tmp_path / "absent.json")
