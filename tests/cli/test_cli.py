"""The command line: simulate writes HDF5 + PNG with provenance; errors exit 2 with a message; bench runs."""

import json

import h5py

import math

import pytest

from neuromuscle.bench.unit import bench_unit
from neuromuscle.cli import main


def test_simulate_writes_hdf5_and_png(tmp_path, capsys):
    out = tmp_path / "sim.h5"
    rc = main(["simulate", "--params", "CT09", "--protocol", "train", "--rate-hz", "20", "--train-ms", "300",
               "--duration-ms", "900", "--out", str(out)])
    assert rc == 0
    assert out.is_file() and out.with_suffix(".png").stat().st_size > 1000
    with h5py.File(out, "r") as f:
        prov = json.loads(f.attrs["provenance"])
        assert prov["protocol"] == {"protocol": "train", "rate_hz": 20.0, "start_ms": 500.0, "train_ms": 300.0}
        assert f["traces/force.F"][()].max() > 5.0
    assert "peak force" in capsys.readouterr().out
    # an existing output is not overwritten
    assert main(["simulate", "--duration-ms", "600", "--out", str(out)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err


def test_simulate_random_length_is_seeded(tmp_path):
    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    for p in (a, b):
        assert main(["simulate", "--protocol", "random-train", "--length", "random", "--seed", "4",
                     "--duration-ms", "800", "--train-ms", "600", "--movement-compensation", "--out", str(p)]) == 0
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        assert (fa["traces/force.F"][()] == fb["traces/force.F"][()]).all()
        assert json.loads(fa.attrs["provenance"])["length_protocol"] == {"length": "random", "seed": 4}


def test_bad_parameter_set_exits_2(tmp_path, capsys):
    assert main(["simulate", "--params", "CT99", "--out", str(tmp_path / "x.h5")]) == 2
    assert "CT99" in capsys.readouterr().err


def test_bench_unit_reports_both_schemes_and_accuracy(ct09):
    res = bench_unit(ct09, duration_ms=300.0, repeats=1, pool_units=2, full=True)
    for key in ("single_ours_s_per_unit_s_1hz", "single_published_s_per_unit_s_100hz", "pool_speedup_100hz",
                "single_ours_100hz_over_1hz"):
        assert math.isfinite(res[key])  # timings are reported, never asserted
    assert res["ours_twitch_peak_error_pct"] < 0.5 and res["published_twitch_peak_error_pct"] < 0.5


def test_standard_synthetic_fit_set(ct09):
    from neuromuscle.bench.fit import synthetic_module2_set

    trials = synthetic_module2_set(ct09)
    assert [t.trial_id for t in trials] == ["twitch", "train10", "train20", "train40"]
    peaks = [t.force.max() for t in trials]
    assert peaks == sorted(peaks) and peaks[-1] > 0.8 * ct09["P0"]


def test_info_names_versions_mechanism_hash_and_cache(capsys):
    from neuromuscle.model.mechanisms import cache_root, mechanism_hash

    assert main(["info", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["mechanism_sha256"] == mechanism_hash() and doc["mechanism_cache"] == str(cache_root())
    assert doc["versions"]["neuron"] and isinstance(doc["mpi4py_installed"], bool)


@pytest.mark.slow  # a full nrnivmodl compile into a fresh cache (about a minute); every fresh run compiles once anyway
def test_first_use_compiles_with_a_message_and_progress(tmp_path):
    """A fresh cache: nrnivmodl runs, and stderr says so before and after (with elapsed-time lines while it
    takes longer than the progress interval)."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "NEUROMUSCLE_CACHE": str(tmp_path / "cache")}
    code = "from neuromuscle import load_mechanisms; load_mechanisms()"
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=600)
    assert out.returncode == 0, out.stderr
    assert "neuromuscle: compiling" in out.stderr and "neuromuscle: mechanisms compiled." in out.stderr


def test_discharges_command_refuses_a_bad_file_naming_the_field(tmp_path, capsys):
    import numpy as np
    import scipy.io

    pulses = np.empty((1, 1), dtype=object)
    pulses[0, 0] = np.array([[30, 20]])
    scipy.io.savemat(tmp_path / "Z_30.mat", {"MUPulses": pulses, "fsamp": np.array([[2048.0]]),
                                             "ref_signal": np.zeros((1, 100))})
    assert main(["discharges", str(tmp_path / "Z_30.mat"), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "Z_30.mat: field 'MUPulses' unit 0" in err and not (tmp_path / "out").exists()
