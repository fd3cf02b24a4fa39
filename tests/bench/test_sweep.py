"""``neuromuscle bench sweep`` on a small sample (6 draws around CT09, short protocols, fixed step and CVODE):
no hang, no exception, no non-finite value, no negative force, fixed step within 1 % of peak of CVODE."""

import json

import pytest

from neuromuscle.cli import main


ARGS = ["bench", "sweep", "--draws", "6", "--short", "--quiet", "--json"]

pytestmark = pytest.mark.slow  # 6 draws x 14 runs; the sweep's parts have fast tests of their own (test_sweep_*.py)


@pytest.fixture(scope="module")
def sweep_folder(tmp_path_factory):
    return tmp_path_factory.mktemp("sweep")


@pytest.fixture(scope="module")
def sweep_report(sweep_folder):
    out = sweep_folder / "sweep.json"
    code = main([*ARGS, "--out", str(out), "--journal", str(sweep_folder / "journal.jsonl")])
    report = json.loads(out.read_text())
    assert code == (1 if report["summary"]["failures"] else 0)
    return report


def test_a_finished_journal_gives_the_same_summary_without_running(sweep_report, sweep_folder, capsys):
    capsys.readouterr()
    main([*ARGS, "--journal", str(sweep_folder / "journal.jsonl")])
    again = json.loads(capsys.readouterr().out)
    drop = ("total_wall_s",)
    assert {k: v for k, v in again.items() if k not in drop} == \
        {k: v for k, v in sweep_report["summary"].items() if k not in drop}


def test_every_run_is_recorded_and_timed(sweep_report):
    s = sweep_report["summary"]
    assert s["n_draws"] == 6 and s["n_runs"] == s["n_runs_expected"] == 6 * 7 * 2 == len(sweep_report["runs"])
    assert len(sweep_report["comparisons"]) == 6 * 7
    assert (s["settings"]["steps_per_ms"], s["settings"]["run_budget_s"]) == (1000, 60.0)
    assert set(s["per_protocol"]) >= {"twitch", "train10", "train40", "train100", "random_length",
                                                     "random_length_mc", "ramp50", "ramp200_mc"}


def test_no_hang_exception_nonfinite_value_or_negative_force(sweep_report):
    s = sweep_report["summary"]
    assert (s["hangs"], s["exceptions"], s["nonfinite"], s["negative_force"]) == (0, 0, 0, 0), s["examples"]


def test_fixed_step_within_one_percent_of_cvode(sweep_report):
    worst = sweep_report["summary"]["worst_fixed_vs_cvode_pct"]
    assert worst["pct"] <= 1.0, worst
