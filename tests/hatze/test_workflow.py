"""Seed 000 'from twitch to tetanus' workflow: ``neuromuscle twitch-to-tetanus`` / ``run_twitch_to_tetanus``."""

import json

import numpy as np
import pytest

from neuromuscle.cli import main
from neuromuscle.errors import InputError
from neuromuscle.model.hatze_parameters import THETA_NAMES, load_subject, load_theta, load_theta_intervals
from neuromuscle.hatze.data import read_twitch_csv, synthetic_twitch
from neuromuscle.hatze.report import FIGURES
from neuromuscle.hatze.workflow import run_twitch_to_tetanus


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The command end to end on the synthetic twitch (subject 3, noise 0.05 N m, seed 0), timed."""
    out = tmp_path_factory.mktemp("t2t") / "report_dir"
    rc = main(["twitch-to-tetanus", "--out", str(out), "--subject", "3", "--seed", "0"])
    return out, rc


@pytest.mark.slow  # the module's full workflow run (tens of seconds); test_overwrite_and_csv_input runs it too
def test_command_runs_end_to_end(run):
    out, rc = run
    assert rc == 0  # (its wall time is a benchmark's business, not a test's)
    for name in ("report.json", "report.md", *FIGURES):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    rep = json.loads((out / "report.json").read_text())
    assert rep["twitch"]["source"] == "synthetic" and rep["twitch"]["seed"] == 0
    prov = rep["provenance"]
    assert prov["inputs"]["seed"] == 0 and "numpy" in prov["versions"] and "matplotlib" in prov["versions"]
    md = (out / "report.md").read_text()
    assert "| quantity | ours | paper | note |" in md and "synthetic" in md


@pytest.mark.slow  # the module's full workflow run (tens of seconds); test_overwrite_and_csv_input runs it too
def test_fitted_theta_inside_seed_intervals(run):
    rep = json.loads((run[0] / "report.json").read_text())
    params = rep["fit"]["parameters"]
    intervals = load_theta_intervals()
    assert params["theta1"]["frozen"] and params["theta1"]["estimate"] == load_theta().theta1
    for name in THETA_NAMES[1:]:
        est = params[name]["estimate"]
        assert intervals[name].contains(est), (name, est)
        assert params[name]["inside_seed_interval"]
        assert params[name]["lower"] <= est <= params[name]["upper"]
    assert rep["fit"]["rms_residual_nm"] == pytest.approx(0.05, rel=0.1)       # fits down to the noise
    sv = rep["fit"]["singular_values_dM_dlntheta_nm"]
    assert len(sv) == 5 and sv[0] > 100 and sv[-1] < 1e-4                      # theta1 direction is empty


@pytest.mark.slow  # the module's full workflow run (tens of seconds); test_overwrite_and_csv_input runs it too
def test_trend_and_rise_times_reported_beside_seed(run):
    rep = json.loads((run[0] / "report.json").read_text())
    s3 = rep["trend"]["subjects"]["3"]
    assert s3["reproduction"] and s3["seed"]["m_per_s"] == 7.94
    assert s3["seed"]["m_ci"][0] <= round(s3["m_per_s"], 2) <= s3["seed"]["m_ci"][1]   # 5 s window: 7.93
    assert rep["trend"]["table2_theta_1s_window"]["m_per_s"] == pytest.approx(7.63, abs=0.01)
    assert not rep["trend"]["subjects"]["1"]["reproduction"]
    md = (run[0] / "report.md").read_text()
    row = next(line for line in md.splitlines() if line.startswith("| trend m, subject 3"))
    assert f"{s3['m_per_s']:.2f}" in row and "7.94" in row
    rise = rep["rise_times"]
    assert rise["moment_q1_mean_s"] == pytest.approx(0.201, abs=0.003) and rise["moment_q1_mean_seed_s"] == 0.2
    peaks = [r["peak_moment_nm"] for r in rep["trains"]["rows"]]
    assert [r["rate_hz"] for r in rep["trains"]["rows"]] == [4, 8, 12, 16, 24] and np.all(np.diff(peaks) > 0)


@pytest.mark.slow  # the module's full workflow run (tens of seconds); test_overwrite_and_csv_input runs it too
def test_rerun_without_overwrite_is_refused(run, capsys):
    out = run[0]
    before = (out / "report.json").read_text()
    assert main(["twitch-to-tetanus", "--out", str(out)]) == 2
    assert "overwrite" in capsys.readouterr().err
    with pytest.raises(InputError, match="already holds report.json"):
        run_twitch_to_tetanus(out)
    assert (out / "report.json").read_text() == before


def test_overwrite_and_csv_input(tmp_path):
    t, noisy, _ = synthetic_twitch(load_subject("3"), load_theta(), 0.02, 1)
    csv = tmp_path / "twitch.csv"
    csv.write_text("time_s,moment_nm,comment\n" + "".join(f"{a:.6f},{b:.9f},x\n" for a, b in zip(t, noisy)))
    tt, mm = read_twitch_csv(csv)
    np.testing.assert_allclose(mm, noisy, atol=1e-8)
    out = tmp_path / "csv_run"
    rep = run_twitch_to_tetanus(out, twitch_csv=csv, max_evaluations=5, figures=False)
    assert rep["twitch"]["source"] == "csv" and len(rep["twitch"]["sha256"]) == 64
    rep2 = run_twitch_to_tetanus(out, twitch_csv=csv, max_evaluations=3, figures=False, overwrite=True)
    assert rep2["fit"]["n_evaluations"] <= 3


def test_csv_missing_column_is_refused(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,moment\n0.0,0.1\n0.001,0.2\n")
    with pytest.raises(InputError, match="missing column.*'moment_nm'"):
        run_twitch_to_tetanus(tmp_path / "o", twitch_csv=bad)
    assert main(["twitch-to-tetanus", "--out", str(tmp_path / "o2"), "--twitch-csv", str(bad)]) == 2
    assert "moment_nm" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("content, culprit", [
    ("time_s,moment_nm\n" + "".join(f"{k * 1e-3},1.0\n" for k in range(7)) + "0.007,nan\n",
     r"row 9, column 'moment_nm': non-finite"),
    ("time_s,moment_nm\n0.0,1.0\n0.001,abc\n", r"row 3, column 'moment_nm': not a number"),
    ("time_s,moment_nm\n" + "".join(f"{(7 - k) * 1e-3},1.0\n" for k in range(8)), "'time_s' must increase"),
])
def test_bad_csv_values_are_refused(tmp_path, content, culprit):
    bad = tmp_path / "bad.csv"
    bad.write_text(content)
    with pytest.raises(InputError, match=culprit):
        run_twitch_to_tetanus(tmp_path / "o", twitch_csv=bad)


@pytest.mark.parametrize("kwargs, culprit", [
    (dict(subject="7"), "subject '7' is not in Table 1"),
    (dict(noise_nm=float("nan")), "noise_nm"),
    (dict(seed=-1), "seed"),
    (dict(twitch_csv="/nonexistent/twitch.csv"), "does not exist"),
    (dict(trend_window_s=0.0), "trend_window_s"),
])
def test_bad_arguments_are_refused(tmp_path, kwargs, culprit):
    with pytest.raises(InputError, match=culprit):
        run_twitch_to_tetanus(tmp_path / "o", **kwargs)


def test_options_are_one_checked_value_and_keywords_replace_fields(tmp_path):
    from dataclasses import replace

    from neuromuscle.hatze.workflow import TwitchToTetanusOptions

    opts = TwitchToTetanusOptions(noise_nm=0, seed=np.int64(3), start_factors=[1, 2, 0.5, 0.5, 2])
    assert (opts.noise_nm, opts.seed, opts.start_factors) == (0.0, 3, (1.0, 2.0, 0.5, 0.5, 2.0))
    with pytest.raises(InputError, match="start_factors"):
        replace(opts, start_factors=(1.0, 2.0))
    with pytest.raises(TypeError, match="noise"):
        run_twitch_to_tetanus(tmp_path / "o", opts, noise=0.1)        # a misspelt option is not ignored
    assert not (tmp_path / "o").exists()
