"""The sweep journal: draws round-trip, a last line cut short is dropped, a journal of other settings is refused."""

import pytest

from neuromuscle import InputError
from neuromuscle.bench.sweep_journal import append_draw, open_journal

SETTINGS = {"n_draws": 3, "seed": 1, "factor_range": (0.5, 2.0)}


def test_draws_round_trip_and_a_cut_line_is_dropped(tmp_path):
    path = tmp_path / "sweep.jsonl"
    assert open_journal(path, SETTINGS) == {}
    append_draw(path, 2, [{"draw": 2, "status": "ok"}], [{"draw": 2, "pct": float("nan")}])
    append_draw(path, 0, [{"draw": 0, "status": "budget_stop"}], [])
    with open(path, "a") as f:
        f.write('{"draw": 1, "runs": [')  # stopped while writing draw 1
    done = open_journal(path, SETTINGS)
    assert sorted(done) == [0, 2] and done[0]["runs"] == [{"draw": 0, "status": "budget_stop"}]
    assert done[2]["comparisons"][0]["pct"] != done[2]["comparisons"][0]["pct"]  # NaN survives
    append_draw(path, 1, [], [])
    assert sorted(open_journal(path, SETTINGS)) == [0, 1, 2]


def test_a_journal_of_other_settings_is_refused(tmp_path):
    path = tmp_path / "sweep.jsonl"
    open_journal(path, SETTINGS)
    with pytest.raises(InputError, match="written for other settings"):
        open_journal(path, {**SETTINGS, "seed": 2})


def test_a_journal_serves_a_sweep_of_another_size(tmp_path):
    """Draw i is the same in a sweep of any size: a stopped 1000-draw sweep gives the summary of its first N."""
    path = tmp_path / "sweep.jsonl"
    open_journal(path, SETTINGS)
    append_draw(path, 0, [], [])
    append_draw(path, 2, [], [])
    assert sorted(open_journal(path, {**SETTINGS, "n_draws": 1})) == [0, 2]  # the sweep keeps draws below n_draws
    assert sorted(open_journal(path, {**SETTINGS, "n_draws": 10})) == [0, 2]
