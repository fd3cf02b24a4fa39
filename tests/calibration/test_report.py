"""``neuromuscle fit``: report directory, params.json accepted by ``simulate``, clear errors on bad input."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "calibration"))

from calibration_synthetic import synthetic_data  # noqa: E402

from neuromuscle.cli import main  # noqa: E402
from neuromuscle.measured import write_measured  # noqa: E402
from neuromuscle.parameters import load_parameters  # noqa: E402


@pytest.fixture(scope="module")
def small_file(tmp_path_factory, ct09):
    path = tmp_path_factory.mktemp("fitdata") / "small.h5"
    data = synthetic_data(ct09.with_values(C3=70.0), full=True)
    data.trials = {k: v for k, v in data.trials.items() if k in ("twitch_opt", "train20")}
    data.extra_datasets.clear()
    return write_measured(path, data)


def test_fit_writes_report_and_simulate_accepts_params(small_file, tmp_path, capsys):
    out = tmp_path / "report"
    rc = main(["fit", str(small_file), "--out", str(out), "--free", "C3", "--dt-ms", "0.1",
               "--max-iterations", "10", "--quiet"])
    assert rc == 0
    for name in ("params.json", "fit.json", "summary.md", "figures/twitch_opt.png", "figures/train20.png"):
        assert (out / name).is_file(), name
    doc = json.loads((out / "fit.json").read_text())
    assert doc["fit"]["estimates"]["C3"] == pytest.approx(70.0, rel=0.02)
    lo, hi = doc["fit"]["ci95"]["C3"]
    assert lo < doc["fit"]["estimates"]["C3"] < hi
    assert set(doc["nrmse_percent"]) == {"twitch_opt", "train20"} and max(doc["nrmse_percent"].values()) < 2.0
    assert "95 % interval" in (out / "summary.md").read_text()
    p = load_parameters(out / "params.json")
    assert p["C3"] == pytest.approx(doc["fit"]["estimates"]["C3"])
    h5 = tmp_path / "sim.h5"
    rc = main(["simulate", "--params", str(out / "params.json"), "--duration-ms", "700", "--dt-ms", "0.1",
               "--out", str(h5)])
    assert rc == 0 and h5.is_file()


def test_fit_staged_mode(small_file, tmp_path):
    out = tmp_path / "staged"
    rc = main(["fit", str(small_file), "--out", str(out), "--free", "C3", "--dt-ms", "0.1", "--staged",
               "--max-iterations", "5", "--quiet"])
    assert rc == 0
    doc = json.loads((out / "fit.json").read_text())
    stages = {s["stage"]: s for s in doc["stages"]}
    assert "force_length" in stages["force-length"]["skipped"] and "step" in stages["KSE"]["skipped"]
    assert stages["module2"]["skipped"] is None and stages["module2"]["values"]["C3"] == pytest.approx(70, rel=0.02)
    assert "Stages" in (out / "summary.md").read_text()
    load_parameters(out / "params.json")


def test_fit_bad_file_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not an hdf5 file")
    assert main(["fit", str(bad), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "neuromuscle: error:" in err and "bad.h5" in err
    assert main(["fit", str(tmp_path / "missing.h5"), "--out", str(tmp_path / "o")]) == 2


def test_fit_unknown_free_and_trial(small_file, tmp_path, capsys):
    assert main(["fit", str(small_file), "--out", str(tmp_path / "o"), "--free", "C9"]) == 2
    assert "C9" in capsys.readouterr().err
    assert main(["fit", str(small_file), "--out", str(tmp_path / "o"), "--trials", "nope"]) == 2
    assert "nope" in capsys.readouterr().err


def test_staged_refuses_the_default_fits_trials_and_intervals(small_file, tmp_path, capsys):
    assert main(["fit", str(small_file), "--out", str(tmp_path / "o"), "--staged", "--trials", "twitch_opt"]) == 2
    assert "--trials" in capsys.readouterr().err
    assert main(["fit", str(small_file), "--out", str(tmp_path / "o"), "--staged", "--intervals", "iid"]) == 2
    assert "--intervals" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_existing_report_is_not_overwritten(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fit.json").write_text("{}")
    from neuromuscle.errors import InputError
    from neuromuscle.calibration.report import run_fit

    with pytest.raises(InputError, match="refusing to overwrite"):
        run_fit(tmp_path / "absent.h5", out)
    assert (out / "fit.json").read_text() == "{}"
