"""Worlds: the base model (eq 18, eqs 19-20, CT09/CT95), protocol subsets, sampling, static points, and two hidden
effects at once."""

import numpy as np
import pytest

from neuromuscle.cli import main
from neuromuscle.errors import InputError
from neuromuscle.measured import read_measured
from neuromuscle.synth import make_dataset, truth
from neuromuscle.synth.protocols import protocol_set, total_duration_s
from neuromuscle.synth.worlds import WORLDS, world

TWITCHES = ("twitch_short", "twitch_opt", "twitch_long")


def test_the_measured_worlds_and_their_background():
    assert [w for w in WORLDS][:4] == ["B", "A", "B-reduced", "A-reduced"]
    assert world("A").background_causes == ("length_dependent_activation",) and world("B").background_causes == ()
    assert set(world("A-movement").allowed_causes) == {"movement_induced_depression", "lengthening_below_optimum"}
    with pytest.raises(InputError, match="unknown world 'Z'"):
        world("Z")


def test_reduced_and_ramps_sets():
    reduced = protocol_set("reduced", -8.0)
    assert len(reduced) == 26 and 50.0 < total_duration_s(reduced) < 60.0
    assert sum(p.protocol == "stretch_hold" for p in reduced) == 1 and not any(p.protocol == "step" for p in reduced)
    lengths = {p.length_mm for p in reduced if p.length_mm is not None}
    assert lengths == {-16.0, -8.0, 0.0}
    ramps = protocol_set("ramps", -8.0)
    assert len(ramps) == 8 and all(p.length_mm is None for p in ramps)
    assert {round(p.length_trace_mm[-1], 6) for p in ramps} == {-4.0}  # one final length
    fast = protocol_set("standard", -8.0, sample_rate_hz=5000.0, drop=("long_train", "potentiation"))
    assert not any(p.protocol in ("long_train", "potentiation") for p in fast)
    assert np.diff(fast[0].time_s)[0] == pytest.approx(0.0002)
    with pytest.raises(InputError, match="cannot drop"):
        protocol_set("standard", -8.0, drop=("nosuch",))
    with pytest.raises(InputError, match="sample_rate_hz"):
        protocol_set("standard", -8.0, sample_rate_hz=50.0)


def test_a_world_with_eq18_has_phi_one_at_the_optimum_and_weaker_twitches_away_from_it():
    a = make_dataset(None, 0.0, 4, world="A-reduced", trials=TWITCHES, noise_pct=0.0)
    b = make_dataset(None, 0.0, 4, world="B-reduced", trials=TWITCHES, noise_pct=0.0)
    p = truth(a)["parameters"]
    assert p["phi1"] * p["g1"] + p["phi2"] == pytest.approx(1.0)
    assert p["phi3"] * p["g1"] + p["phi4"] == pytest.approx(1.0)
    assert truth(a)["model"].endswith("eq 18 on, eqs 19-20 off") and truth(a)["background_causes"] == \
        ["length_dependent_activation"]
    assert not a.extra_datasets  # the reduced worlds carry no static points
    peak = {k: (a.trials[k].force.max(), b.trials[k].force.max()) for k in TWITCHES}
    assert peak["twitch_opt"][0] == pytest.approx(peak["twitch_opt"][1], rel=0.02)
    assert peak["twitch_short"][0] < 0.95 * peak["twitch_short"][1]  # K5 scaled down below the optimum


def test_two_hidden_effects_act_together():
    ids = ("post_tetanic_opt",)
    one = make_dataset("post_activation_potentiation", 0.8, 6, world="B-reduced", trials=ids, noise_pct=0.0)
    two = make_dataset("post_activation_potentiation", 0.8, 6, world="B-reduced", trials=ids, noise_pct=0.0,
                       also={"relaxation_rate": 0.8})
    null = make_dataset(None, 0.0, 6, world="B-reduced", trials=ids, noise_pct=0.0)
    f1, f2, f0 = (d.trials[ids[0]].force for d in (one, two, null))
    assert np.max(np.abs(f2 - f1)) > 0.01 * np.max(f0) and np.max(np.abs(f1 - f0)) > 0.01 * np.max(f0)
    assert [c["name"] for c in truth(two)["causes"]] == ["post_activation_potentiation", "relaxation_rate"]
    with pytest.raises(InputError, match="at most once"):
        make_dataset("fatigue", 0.5, 1, also={"fatigue": 0.5}, trials=ids, world="B-reduced")
    with pytest.raises(InputError, match="out-of-catalogue"):
        make_dataset("transducer_drift", 0.5, 1, also={"fatigue": 0.5}, trials=ids, world="B-reduced")


def test_digitised_world_has_few_uneven_samples(tmp_path):
    d = make_dataset("force_enhancement_after_stretch", 0.5, 2, world="ramps", trials=("stretch6mm_4mm_s",))
    t = d.trials["stretch6mm_4mm_s"]
    assert t.n_samples == 25 and len(set(np.round(np.diff(t.time_s), 6))) > 5
    assert t.length.size == 25
    out = tmp_path / "w.h5"
    assert main(["synth", "--cause", "none", "--seed", "3", "--world", "B-reduced", "--eq18", "on", "--drop",
                 "random_length,isokinetic,stretch_hold,shorten_hold,long_train,post_tetanic,doublet,low_rate_train",
                 "--also", "", "--out", str(out)]) == 0
    tr = truth(read_measured(out))
    assert tr["world"]["name"] == "B-reduced+" and tr["world"]["length_dependence"] is True
    assert main(["synth", "--cause", "fatigue", "--seed", "3", "--also", "fatigue", "--out",
                 str(tmp_path / "x.h5")]) == 2
