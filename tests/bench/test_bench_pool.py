"""``neuromuscle bench pool`` on a tiny configuration: the JSON keys, and reports consistent with themselves and
across rank counts (no wall-time assertion)."""

import json

import pytest

from neuromuscle.bench.pool import RUN_KEYS, bench_pool, table_lines
from neuromuscle.cli import main
from neuromuscle.errors import InputError
from neuromuscle.pool.mpi import mpi_available
from neuromuscle.pool.discharge_stats import HUMAN_MEDIAN_RATES_HZ, HUMAN_PEAK_RATE_HZ


def test_bench_pool_json_keys_and_consistency(capsys):
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1,2", "--duration-ms", "60"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["duration_ms"] == 60.0 and res["dt_ms"] == pytest.approx(1 / 30) and res["secondorder"] == 2
    ranks = [r["ranks"] for r in res["runs"]]
    assert ranks == ([1, 2] if mpi_available() else [1])
    assert [s["ranks"] for s in res["skipped"]] == ([] if mpi_available() else [2])
    for r in res["runs"]:
        assert set(RUN_KEYS) <= set(r)
        assert r["n_units"] == 3 and r["spikes"] > 0
        assert 0 < r["sim_s"] <= r["wall_s"] and 0 <= r["build_s"] <= r["wall_s"]
        assert r["s_per_unit_s"] == pytest.approx(r["sim_s"] / (3 * 0.06))
        assert len(r["peak_rss_mib_per_rank"]) == r["ranks"]
        assert r["peak_rss_mib"] == max(r["peak_rss_mib_per_rank"]) and 50 < r["peak_rss_mib"] < 4096
        assert r["load_1min_before"] >= 0
        assert r["mean_rate_hz"] > 0 and 0 <= r["max_rate_hz"] < 60  # the synaptic drive: human rates
    assert len({r["spikes"] for r in res["runs"]}) == 1  # the same pool whatever the ranks
    # the machine's limit, timed before and after the runs, and each run's cost as a multiple of it
    assert len(res["machine_limit_ns"]) == 2 and all(x > 0 for x in res["machine_limit_ns"])
    for r in res["runs"]:
        limit = sum(res["machine_limit_ns"]) / 2
        assert r["times_machine_limit"] == pytest.approx(r["ns_per_cell_step_per_core"] / limit)
    lines = table_lines(res)
    assert len(lines) == 5 + len(res["runs"]) and "the machine's limit" in lines[1] and "x the limit" in lines[3]


@pytest.mark.parametrize("profile", ["human", "default"])
def test_bench_pool_fires_in_the_range_of_human_units(profile, capsys):
    """The benchmark's default drive recruits every unit of its 50-unit pool, each at a median rate within the
    recorded human range, with either motoneuron profile (its drive peak is the profile's)."""
    assert main(["bench", "pool", "--json", "--units", "50", "--ranks", "1", "--motoneurons", profile]) == 0
    res = json.loads(capsys.readouterr().out)
    (r,) = res["runs"]
    assert res["motoneurons"] == r["motoneurons"] == profile and r["recruited"] == 50
    assert r["medians_inside_human_range"] == 1.0 and r["max_rate_hz"] <= 1.5 * HUMAN_PEAK_RATE_HZ
    assert HUMAN_MEDIAN_RATES_HZ[0] <= r["median_rates_p5_p50_p95_hz"][0] < r["median_rates_p5_p50_p95_hz"][2]
    assert f"{profile} motoneurons" in table_lines(res)[0]


def test_bench_pool_fused_substeps_reach_the_pool(capsys):
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1", "--duration-ms", "60", "--muscle",
                 "fused", "--substeps", "2"]) == 0
    res = json.loads(capsys.readouterr().out)
    (r,) = res["runs"]
    assert (res["muscle"], res["substeps"]) == ("fused", 2) and (r["muscle"], r["substeps"]) == ("fused", 2)
    assert r["spikes"] > 0 and "muscle fused (substeps 2)" in table_lines(res)[0]


def test_bench_pool_muscle_keeps_its_cadence_at_a_longer_membrane_step(capsys):
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1", "--duration-ms", "60", "--dt-ms",
                 "0.05", "--drive", "ramp"]) == 0
    res = json.loads(capsys.readouterr().out)
    (r,) = res["runs"]
    assert (res["dt_ms"], res["substeps"], r["substeps"], res["drive"]) == (0.05, 4, 4, "ramp")
    assert r["ns_per_cell_step_per_core"] == pytest.approx(r["sim_s"] / (3 * 60 / 0.05) * 1e9)


def test_bench_pool_defaults_are_the_fast_path_and_the_reference_is_a_flag(capsys):
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1", "--duration-ms", "60"]) == 0
    fast = json.loads(capsys.readouterr().out)
    assert (fast["muscle"], fast["substeps"], fast["channels"], fast["pic_substeps"]) == ("fused_fixed", 6,
                                                                                          "fused_fixed", 6)
    assert fast["runs"][0]["pic_substeps"] == 6 and "PIC gate substeps 6" in table_lines(fast)[0]
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1", "--duration-ms", "60", "--muscle",
                 "modules", "--channels", "separate", "--dt-ms", "0.025", "--secondorder", "0"]) == 0
    ref = json.loads(capsys.readouterr().out)
    (r,) = ref["runs"]
    assert (r["muscle"], r["substeps"], r["channels"], r["pic_substeps"]) == ("modules", 1, "separate", 1)
    assert r["spikes"] > 0 and "backward Euler" in table_lines(ref)[0]
    with pytest.raises(InputError, match="pic_substeps = 6 needs channels='fused'"):
        bench_pool([3], [1], 60.0, channels="separate", pic_substeps=6)


@pytest.mark.parametrize("kw", [dict(units=[1], ranks=[2]), dict(units=[0]), dict(ranks=[]),
                                dict(units=[2], drive="sine"), dict(units=[2], muscle="hill"),
                                dict(units=[2], muscle="modules", substeps=2),
                                dict(units=[2], muscle="fused", substeps=0), dict(units=[2], nthread=0),
                                dict(units=[2], channels="hh"), dict(units=[2], cell_permute=2),
                                dict(units=[2], pic_substeps=0), dict(units=[2], motoneurons="cat")])
def test_bench_pool_refuses_bad_configurations(kw):
    with pytest.raises(InputError):
        bench_pool(**kw)


def test_bench_pool_runs_both_engines_and_compares_them(capsys):
    assert main(["bench", "pool", "--json", "--units", "3", "--ranks", "1", "--duration-ms", "60", "--engines",
                 "neuron,coreneuron"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert [r["engine"] for r in res["runs"]] == ["neuron", "coreneuron"]
    for r in res["runs"]:
        assert r["ns_per_cell_step_per_core"] == pytest.approx(r["sim_s"] / (3 * 60 / res["dt_ms"]) * 1e9)
    (a,) = res["agreement"]
    assert a["engines"] == ["neuron", "coreneuron"] and a["spikes"] == res["runs"][0]["spikes"] > 0
    assert a["spikes_identical"] and a["forces_identical"] and a["pool_force_max_diff_of_peak"] == 0.0
    lines = table_lines(res)
    assert len(lines) == 5 + 2 + 4 and "coreneuron" in lines[6] and "neuron vs coreneuron" in lines[-1]
    with pytest.raises(InputError, match="engines"):
        bench_pool(units=[2], engines=["neuron", "neuron"])
