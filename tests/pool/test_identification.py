"""Which units a decomposition identifies: larger units are identified preferentially, shallower ones too, the
recording's count is respected, a seed fixes the choice, bad input is refused; the comparison of the identified
units with recorded ones."""

from dataclasses import replace

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import discharge_stats as ds
from neuromuscle.pool.discharges import DischargeTrial
from neuromuscle.pool.identification import (
    IdentificationModel,
    copies_per_unit,
    estimate_depth_attenuation,
    identified_ks,
    identify,
    muap_energy,
)
from neuromuscle.pool.recorded_comparison import compare_discharges, discharging_s

P0 = 1.0 + 49.0 * np.linspace(0.0, 1.0, 40) ** 3          # N: most units small, the last ones large
ACTIVE = np.ones(40, bool)


def test_copies_cover_the_muscle():
    c = copies_per_unit(40, 400)
    assert c.sum() == 400 and set(c) == {10}
    c = copies_per_unit(30, 400)
    assert c.sum() == 400 and c.max() - c.min() <= 1


def test_energy_grows_with_size_and_falls_with_depth():
    e = muap_energy(np.array([1.0, 2.0, 2.0]), np.array([0.0, 0.0, 1.0]), size_exponent=2.0,
                    depth_attenuation=3.0)
    assert e[1] == pytest.approx(4.0 * e[0]) and e[2] == pytest.approx(e[1] * np.exp(-3.0))


def test_larger_units_are_identified_preferentially():
    ident = identify(P0, ACTIVE, 40, motor_units=400, model=IdentificationModel(depth_attenuation=4.0, seed=3))
    per_unit = ident.identified_copies / copies_per_unit(40, 400)
    small, large = per_unit[:20].mean(), per_unit[20:].mean()
    assert large > 3.0 * small
    assert np.mean(ident.units) > 25                                # the sample leans to the late, large units


def test_without_depth_the_largest_active_units_are_the_sample():
    active = np.arange(40) < 30                                     # the last ten units silent
    ident = identify(P0, active, 25, motor_units=400, model=IdentificationModel(depth_attenuation=0.0))
    assert ident.identified_copies[29] == 10 and ident.identified_copies[28] == 10
    assert ident.identified_copies[27] == 5 and ident.identified_copies[:27].sum() == 0
    assert ident.identified_copies[30:].sum() == 0                  # silent units are never identified


def test_strong_depth_attenuation_samples_every_size():
    ident = identify(P0, ACTIVE, 100, motor_units=400, model=IdentificationModel(depth_attenuation=200.0, seed=1))
    assert ident.units.size > 30                                    # shallowness dominates: all sizes appear


def test_count_is_respected_and_the_seed_fixes_the_choice():
    for count in (1, 17, 84, 400):
        ident = identify(P0, ACTIVE, count, motor_units=400, model=IdentificationModel(seed=5))
        assert ident.weights.sum() == count == ident.count
        assert np.all(ident.identified_copies <= ident.copies)
    a = identify(P0, ACTIVE, 30, motor_units=400, model=IdentificationModel(seed=7))
    b = identify(P0, ACTIVE, 30, motor_units=400, model=IdentificationModel(seed=7))
    c = identify(P0, ACTIVE, 30, motor_units=400, model=IdentificationModel(seed=8))
    assert np.array_equal(a.identified_copies, b.identified_copies)
    assert not np.array_equal(a.identified_copies, c.identified_copies)
    assert a.summary()["model"]["seed"] == 7 and "depth_attenuation" in a.summary()["model"]


def test_units_discharging_longer_are_identified_first():
    """Equal units: the ones discharging longest are the sample; an exponent of 0 leaves the time out; a large unit
    discharging briefly loses to a smaller one discharging throughout when the energies times the times say so."""
    p0 = np.full(40, 5.0)
    time_s = np.linspace(30.0, 5.0, 40)                             # early units discharge longest
    flat = IdentificationModel(depth_attenuation=0.0, activity_exponent=1.0)
    ident = identify(p0, ACTIVE, 50, motor_units=400, model=flat, active_s=time_s)
    assert np.array_equal(ident.units, np.arange(5)) and ident.weights.sum() == 50
    ignored = identify(p0, ACTIVE, 50, motor_units=400, model=replace(flat, activity_exponent=0.0), active_s=time_s)
    assert np.array_equal(ignored.identified_copies, identify(p0, ACTIVE, 50, motor_units=400, model=flat)
                          .identified_copies)
    two = identify([1.0, 1.5], np.array([True, True]), 10, motor_units=20, model=flat, active_s=[30.0, 10.0])
    assert np.array_equal(two.units, [0])                           # 1 * 30 > 1.5 ** 2 * 10
    assert identify([1.0, 1.5], np.array([True, True]), 10, motor_units=20, model=flat,
                    active_s=[30.0, 20.0]).units.tolist() == [1]    # 2.25 * 20 > 30


def test_sampled_units_are_drawn_in_proportion_to_their_weights():
    """Sampled: one unit of two drawn with the probability of its share of the energy (3:1 here), over many seeds;
    the depths are those of the ranked choice with the same seed; a large sample reaches smaller units than the
    ranked one."""
    flat = IdentificationModel(depth_attenuation=0.0, selection="sampled")
    first = [identify([1.0, 3.0 ** 0.5], np.array([True, True]), 1, motor_units=2,
                      model=replace(flat, seed=s)).units[0] for s in range(4000)]
    assert np.mean(first) == pytest.approx(0.75, abs=0.03)         # 3 / (1 + 3), 4000 draws: sd 0.007
    ranked = identify(P0, ACTIVE, 60, motor_units=400, model=IdentificationModel(depth_attenuation=0.0))
    sampled = identify(P0, ACTIVE, 60, motor_units=400, model=replace(flat, seed=2))
    assert sampled.weights.sum() == 60 and sampled.units.min() < ranked.units.min()
    assert np.mean(sampled.units) > 20                             # still leaning to the large units
    with pytest.raises(InputError, match="selection"):
        IdentificationModel(selection="largest")


@pytest.mark.parametrize("active_s", [[1.0], [1.0, -1.0], [1.0, float("nan")], ["a", "b"]])
def test_bad_times_discharging_are_refused(active_s):
    with pytest.raises(InputError, match="active_s"):
        identify([1.0, 2.0], np.array([True, True]), 2, motor_units=10, active_s=active_s)


@pytest.mark.parametrize("kwargs, match", [
    (dict(p0_N=[1.0, -2.0], active=[True, True], count=3, motor_units=10), "P0 > 0"),
    (dict(p0_N=[1.0, 2.0], active=[True], count=3, motor_units=10), "boolean array"),
    (dict(p0_N=[1.0, 2.0], active=[1, 1], count=3, motor_units=10), "boolean array"),
    (dict(p0_N=[1.0, 2.0], active=[True, True], count=0, motor_units=10), "positive integer"),
    (dict(p0_N=[1.0, 2.0], active=[True, False], count=6, motor_units=10), "stand for only 5"),
    (dict(p0_N=[1.0, 2.0], active=[True, True], count=1, motor_units=1), "motor_units must be"),
])
def test_bad_input_is_refused(kwargs, match):
    with pytest.raises(InputError, match=match):
        identify(**kwargs)


@pytest.mark.parametrize("kwargs", [dict(depth_attenuation=-1.0), dict(size_exponent=float("nan")),
                                    dict(seed=-1), dict(seed=1.5), dict(activity_exponent=-0.5)])
def test_bad_parameters_are_refused(kwargs):
    with pytest.raises(InputError):
        IdentificationModel(**kwargs)


def test_the_estimate_finds_the_attenuation_that_made_a_sample():
    thr = np.linspace(0.5, 60.0, 40)                                # thresholds rising with size, % MVC
    truth = identify(P0, ACTIVE, 60, motor_units=400, model=IdentificationModel(depth_attenuation=6.0, seed=99))
    recorded = np.repeat(thr[truth.units], truth.weights)
    best, cost = estimate_depth_attenuation(P0, ACTIVE, thr, recorded, motor_units=400,
                                            grid=[0.0, 2.0, 6.0, 30.0, 200.0], seeds=range(10))
    assert best == 6.0 and cost[2] < cost[0] and cost[2] < cost[4]


def test_the_identified_distance_averages_the_seeds_of_the_depths():
    thr = np.linspace(0.5, 60.0, 40)
    recorded = thr[25:]
    model = IdentificationModel(depth_attenuation=3.0)
    one = []
    for seed in (4, 5):
        found = identify(P0, ACTIVE, recorded.size, motor_units=400, model=IdentificationModel(3.0, seed=seed))
        one.append(identified_ks(P0, ACTIVE, thr, recorded, motor_units=400, model=model, seeds=[seed]))
        assert one[-1] == pytest.approx(ds.ks_distance(thr[found.units], recorded, found.weights))
    both = identified_ks(P0, ACTIVE, thr, recorded, motor_units=400, model=model, seeds=[4, 5])
    assert both == pytest.approx(np.mean(one))
    with pytest.raises(InputError, match="one model threshold per unit"):
        identified_ks(P0, ACTIVE, thr[:5], recorded, motor_units=400, model=model)


T = np.arange(0.0, 20001.0, 1.0)
FORCE = np.interp(T, [0, 4000, 16000, 20000], [0, 30, 30, 0])


def test_time_discharging_is_first_to_last_discharge():
    assert discharging_s([100.0, 350.0, 2100.0]) == pytest.approx(2.0)
    assert discharging_s([5.0]) == 0.0 and discharging_s([]) == 0.0


def _trains(rates_hz, starts_ms):
    return [np.arange(s, 19000.0 - s / 4, 1000.0 / r) for r, s in zip(rates_hz, starts_ms)]


def test_the_comparison_holds_the_identified_units_beside_the_pool():
    pool = _trains(np.linspace(20.0, 12.0, 20), np.linspace(100.0, 3800.0, 20))
    rec = pool[-6:]                                                 # a sample of the late-recruited, large units
    trial = DischargeTrial("made up", 0.0, 20000.0, rec, np.arange(6), T, FORCE)
    p0 = 1.0 + 29.0 * np.linspace(0.0, 1.0, 20) ** 4
    c = compare_discharges(trial, pool, T, FORCE, p0_N=p0, motor_units=20,
                           identification=IdentificationModel(depth_attenuation=0.0, seed=0))
    s = c.summary()
    assert s["identified"]["identification"]["count"] == 6
    assert sum(s["identified"]["identification"]["weights"]) == 6
    spread = s["identified"]["over_seeds"]["thresholds_ks_median_p5_p95"]
    assert spread == [0.0, 0.0, 0.0]                                # without depth the random seed does not matter
    expected = s["identified"]["over_seeds"]["thresholds_ks_expected"]
    assert expected["value"] == 0.0 and expected["pass"] and expected["recorded_units"] == 6
    p50, p95 = expected["by_chance_p50_p95"]                       # six units drawn from six: chance shows
    assert 0.0 < p50 <= p95 < 1.0
    whole, found = c.criteria(), c.identified_criteria()
    assert np.array_equal(c.identified.identification.units, np.arange(14, 20))
    assert found["thresholds_ks"]["value"] == 0.0 and not whole["thresholds_ks"]["pass"]
    assert found["medians_inside"]["fraction"] > whole["medians_inside"]["fraction"]
    assert c.identified.active_s == pytest.approx([(t[-1] - t[0]) / 1000.0 for t in pool])
    with pytest.raises(InputError, match="both p0_N and motor_units"):
        compare_discharges(trial, pool, T, FORCE, p0_N=p0)


def test_the_command_estimates_from_a_run_file_and_names_a_bad_one(tmp_path, capsys):
    """``python -m neuromuscle.pool.identification FILE.json``: an estimate from a per-file JSON; a file without
    the per-unit table is refused naming the file and the field."""
    import json

    from neuromuscle.pool import identification

    p0 = np.linspace(1.0, 10.0, 20)
    thresholds = np.linspace(1.0, 30.0, 20)
    row = {"file": "X.mat", "units": {"p0_N": p0.tolist(), "threshold_percent_mvc": thresholds.tolist(),
                                      "active": [True] * 20, "discharging_s": [10.0] * 20},
           "recorded_thresholds_percent_mvc": thresholds[-6:].tolist(), "identification": {"motor_units": 100}}
    good = tmp_path / "X.json"
    good.write_text(json.dumps(row))
    out = identification.main([str(good)])
    assert out["file"] == "X.mat" and out["depth_attenuation"] in identification.DEPTH_GRID
    assert json.loads(capsys.readouterr().out)["mean_ks"] == out["mean_ks"]
    del row["units"]["discharging_s"]                               # a run file written before the times were
    older = tmp_path / "older.json"
    older.write_text(json.dumps(row))
    assert identification.main([str(older)])["mean_ks"] == out["mean_ks"]   # the default model does not use them
    del row["units"]["active"]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(row))
    with pytest.raises(InputError, match=r"bad\.json: field 'active'"):
        identification.main([str(bad)])
    with pytest.raises(InputError, match="missing.json"):
        identification.main([str(tmp_path / "missing.json")])
