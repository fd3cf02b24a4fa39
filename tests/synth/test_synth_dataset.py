"""Synthetic files: valid layout, null = baseline + AR(1) noise at the stated level, seeds reproducible, the truth
kept apart, bad input refused."""

import numpy as np
import pytest

from neuromuscle import InputError
from neuromuscle.cli import main
from neuromuscle.fit import trial_simulation
from neuromuscle.measured import read_measured, validate_measured
from neuromuscle.model.kim import kim_excitation
from neuromuscle.synth import (TRUTH_PATH, extended_protocols, make_dataset, standard_protocols, truth, without_truth,
                               write_dataset)
from neuromuscle.synth.dataset import SETTLE_MS
from neuromuscle.synth.protocols import total_duration_s

from synth_cache import NOISE_PCT, SEED, dataset

NULL_TRIALS = ("twitch_opt", "train3_opt", "ramp_lengthen10")


def test_standard_protocol_set_is_about_25_trials_and_modest_in_time():
    plan = standard_protocols(-8.0)
    assert 24 <= len(plan) <= 28
    assert total_duration_s(plan) < 95.0  # 91 s: two 12 s long trains and two ~11 s potentiation trials
    # two of each, one for each side of a diagnosis's split (with one, the cause it tells is untestable)
    assert sum(p.protocol == "long_train" for p in plan) == 2
    assert sum(p.protocol == "potentiation" for p in plan) == 2
    kinds = {p.protocol for p in plan}
    assert {"twitch", "train", "doublet", "long_train", "potentiation", "isokinetic", "stretch_hold",
            "shorten_hold", "random_length", "step"} <= kinds
    assert len({p.trial_id for p in plan}) == len(plan)


def test_file_passes_the_validator_and_data_check(tmp_path, capsys):
    out = write_dataset(tmp_path / "s.h5", "staircase", 0.5, SEED, trials=["twitch_short", "train3_opt", "step100"],
                        dt_ms=0.05)
    data = read_measured(out)
    validate_measured(data)
    assert main(["data", "check", str(out)]) == 0
    assert "3 trial(s)" in capsys.readouterr().out
    assert data.trials["train3_opt"].attrs["rate_hz"] == 3
    assert data.trials["twitch_short"].attrs["length_label"] == "short"
    t = truth(data)
    assert t["cause"] == "staircase" and t["strength"] == 0.5 and t["seed"] == SEED
    assert t["noise_kind"] == "AR(1)" and t["neuromuscle_version"]
    assert TRUTH_PATH not in without_truth(data).extra_attrs
    assert "/calibration/force_length" in data.extra_datasets


def test_parameters_vary_inside_their_bounds():
    from neuromuscle.parameters import load_parameters, registry

    p = truth(dataset(None, 0.0, ("twitch_opt",)))["parameters"]
    base = load_parameters("CT09")
    reg = registry()
    ratios = [p[k] / base[k] for k in base if base[k] != 0]
    assert np.std(np.log(ratios)) > 0.08  # tens of percent
    assert sum(abs(r - 1.0) > 1e-12 for r in ratios) == len(ratios)  # every parameter moved
    for k in p:
        assert reg[k].lower <= p[k] <= reg[k].upper


def test_null_file_is_the_baseline_plus_ar1_noise_of_the_stated_level():
    data = dataset(None, 0.0, NULL_TRIALS)
    t = truth(data)
    params = t["parameters"]
    assert t["noise_sd_N"] == pytest.approx(NOISE_PCT / 100.0 * params["P0"])
    resid = []
    for tr in data.trials.values():
        base = trial_simulation(params, tr, 0.05, record_dt_ms=0.5, settle_ms=SETTLE_MS,
                                excitation=kim_excitation(False, False))
        resid.append(tr.force - base)
    r = np.concatenate(resid)
    assert abs(np.mean(r)) < 0.2 * t["noise_sd_N"]
    assert np.std(r) == pytest.approx(t["noise_sd_N"], rel=0.15)
    lag1 = np.mean([np.corrcoef(x[1:], x[:-1])[0, 1] for x in resid])
    assert lag1 == pytest.approx(np.exp(-1.0 / t["noise_tau_ms"]), abs=0.05)  # 1 kHz samples, tau 5 ms


def test_seeds_are_reproducible_and_distinct():
    a = make_dataset("fatigue", 0.3, 7, trials=["twitch_opt"], dt_ms=0.05)
    b = make_dataset("fatigue", 0.3, 7, trials=["twitch_opt"], dt_ms=0.05)
    c = make_dataset("fatigue", 0.3, 8, trials=["twitch_opt"], dt_ms=0.05)
    assert a.trials == b.trials and truth(a)["true_parameters"] == truth(b)["true_parameters"]
    assert not np.allclose(a.trials["twitch_opt"].force, c.trials["twitch_opt"].force)


@pytest.mark.parametrize("kwargs, match", [
    ({"cause": "stair_case"}, "unknown cause 'stair_case'"),
    ({"strength": 1.5}, r"strength must be a number in \[0, 1\]"),
    ({"strength": -0.1}, r"strength must be a number in \[0, 1\]"),
    ({"strength": float("nan")}, r"strength must be a number in \[0, 1\]"),
    ({"seed": -1}, "seed must be an integer >= 0"),
    ({"noise_pct": 50.0}, r"noise_pct must be a number in \[0, 20\]"),
    ({"variation": 3.0}, "variation must be a log-sd between 0 and 1"),
    ({"trials": ["twitch_middle"]}, r"trial\(s\) \['twitch_middle'\] are not in the extended protocol set"),
])
def test_bad_input_is_refused_with_a_clear_message(kwargs, match):
    args = {"cause": "staircase", "strength": 0.5, "seed": 1, **kwargs}
    with pytest.raises(InputError, match=match):
        make_dataset(**args)


def test_existing_file_is_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "x.h5"
    out.write_bytes(b"keep me")
    with pytest.raises(InputError, match="exists; refusing to overwrite"):
        write_dataset(out, None, 0.0, 1)
    assert main(["synth", "--cause", "none", "--seed", "1", "--out", str(out)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert out.read_bytes() == b"keep me"


def test_cli_lists_causes_and_refuses_unknown_ones(capsys, tmp_path):
    assert main(["synth", "--list"]) == 0
    text = capsys.readouterr().out
    for name in ("length_dependent_activation", "fatigue", "transducer_drift", "none"):
        assert name in text
    assert main(["synth", "--cause", "cramp", "--seed", "1", "--out", str(tmp_path / "c.h5")]) == 2
    assert "unknown cause 'cramp'" in capsys.readouterr().err
    assert main(["synth", "--cause", "none", "--out", str(tmp_path / "c.h5")]) == 2
    assert "synth needs --seed" in capsys.readouterr().err
    assert not (tmp_path / "c.h5").exists()


def test_cli_writes_a_full_file_of_the_default_extended_set_that_data_check_accepts(tmp_path, capsys):
    out = tmp_path / "prep.h5"
    assert main(["synth", "--cause", "none", "--strength", "0", "--seed", "2", "--noise", "1.5",
                 "--out", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out
    assert main(["data", "check", str(out)]) == 0
    data = read_measured(out)
    assert len(data.trials) == len(extended_protocols(-8.0))  # world B: the extended set
    assert truth(data)["cause"] == "none"
