"""The package's example file: the shipped file is what its generator makes now (it cannot drift from the model),
it says how it was made, and ``neuromuscle data example`` copies it."""

import json

import numpy as np

from neuromuscle.cli import main
from neuromuscle.measured import example_path, read_measured, write_example
from neuromuscle.measured.example import PROTOCOLS, TRUE_VALUES

# The force is simulated by compiled mechanisms: another compiler or CPU may change its last bits, not more.
FORCE_ATOL_N = 1e-9


def test_shipped_example_equals_a_new_one(tmp_path):
    shipped = read_measured(example_path())
    new = read_measured(write_example(tmp_path / "new.h5"))
    assert list(shipped.trials) == list(new.trials) == [tid for tid, _, _ in PROTOCOLS]
    for tid, t in shipped.trials.items():
        n = new.trials[tid]
        np.testing.assert_allclose(t.force, n.force, rtol=0, atol=FORCE_ATOL_N, err_msg=tid)
        n.force = t.force
        assert t == n, tid
    assert shipped.attrs == new.attrs and shipped.extra_attrs == new.extra_attrs and not shipped.extra_datasets
    assert example_path().stat().st_size < 300_000


def test_example_states_how_it_was_made():
    data = read_measured(example_path())
    prov = data.extra_attrs["/provenance"]
    assert json.loads(prov["true_values"]) == TRUE_VALUES
    assert json.loads(prov["true_values_units"]) == {"C1": "1", "C2": "1", "C3": "ms", "alpha": "1"}
    assert (prov["base_parameters"], prov["seed"], prov["noise_sd_N"]) == ("CT09", 1, 0.02)
    assert all(tid in prov["protocols"] for tid, _, _ in PROTOCOLS)
    assert "C3 = 55" in data.attrs["preparation"]


def test_data_example_command_copies_it_and_keeps_an_existing_file(tmp_path, capsys):
    out = tmp_path / "cat_unit.h5"
    assert main(["data", "example", str(out)]) == 0
    assert read_measured(out) == read_measured(example_path())
    assert main(["data", "example", str(out)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main(["data", "example", str(out), "--overwrite"]) == 0
