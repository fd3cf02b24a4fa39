"""The screening of candidates (diagnose/screening.py): the linearised gain of each extension at the current model
puts the effect that is in the data first, and gives nothing to an effect that is not."""

import numpy as np
import pytest

from diagnose_datasets import make_data
from neuromuscle.diagnose.models import OPTIONS, simulate_all
from neuromuscle.diagnose.residuals import Noise
from neuromuscle.diagnose.screening import screen
from neuromuscle.parameters import load_parameters

NAMES = ["staircase", "fatigue", "relaxation_rate", "doublet_potentiation"]
REFIT = ("C1", "C2", "C3", "alpha", "tau2")
SD_N = 0.01  # white noise (N), ~0.3 % of the 40 Hz trains' force


@pytest.fixture(scope="module")
def setting():
    """Ten short trials (twitches, 10-60 Hz trains, 1.5 s trains), CT09 as the reference, and its forces."""
    trials = list(make_data(5).trials.values())
    ref = load_parameters("CT09")
    return trials, ref, simulate_all(ref, trials)


def _measured(trials, clean, seed):
    rng = np.random.default_rng(seed)
    return {t.trial_id: clean[t.trial_id] + rng.normal(0.0, SD_N, clean[t.trial_id].size) for t in trials}


def _noise(trials, measured):
    return {t.trial_id: Noise(SD_N, 0.0, float(measured[t.trial_id].size)) for t in trials}


def test_the_effect_in_the_data_comes_first(setting):
    trials, ref, ref_sims = setting
    truth = ref.with_values({"staircase.k": 0.4, "staircase.u": 0.1, "staircase.tau": 3000.0})
    measured = _measured(trials, simulate_all(truth, trials, ("staircase",)), 1)
    s = screen(NAMES, ref, ref_sims, trials, measured, _noise(trials, measured), OPTIONS, refitted=REFIT)
    order = sorted(NAMES, key=lambda n: -s[n].score)
    assert order[0] == "staircase", {n: s[n].score for n in NAMES}
    assert s["staircase"].score > 100.0 * s["staircase"].penalty
    assert s["staircase"].moves["staircase.k"] > 0.0  # the sign of the hidden staircase


def test_no_effect_no_gain_beyond_the_penalty(setting):
    trials, ref, ref_sims = setting
    measured = _measured(trials, ref_sims, 2)
    s = screen(NAMES, ref, ref_sims, trials, measured, _noise(trials, measured), OPTIONS, refitted=REFIT)
    assert all(s[n].score <= 0.0 for n in NAMES), {n: (s[n].gain, s[n].penalty) for n in NAMES}


def test_a_reference_on_a_bound_is_screened(setting):
    """Module 2 is moved downwards where upwards would leave its range (a fit can end on alpha's bound 8: this
    would otherwise raise)."""
    trials, ref, _ = setting
    at_bound = ref.with_values({"alpha": 8.0})
    sims = simulate_all(at_bound, trials[:3])
    measured = _measured(trials[:3], sims, 3)
    s = screen(["staircase"], at_bound, sims, trials[:3], measured, _noise(trials[:3], measured), OPTIONS,
               refitted=REFIT)
    assert s["staircase"].score <= 0.0


def test_one_pool_call_screens_as_the_serial_runs(setting):
    """On a worker pool every move of every candidate is simulated in one call (each run with its own extension):
    the screens are those of the serial runs, exactly."""
    from neuromuscle.fit.evaluate import TrialPool

    trials, ref, ref_sims = setting
    trials = trials[:4]
    truth = ref.with_values({"staircase.k": 0.4, "staircase.u": 0.1, "staircase.tau": 3000.0})
    measured = _measured(trials, simulate_all(truth, trials, ("staircase",)), 4)
    noise = _noise(trials, measured)
    names = ["staircase", "doublet_potentiation"]
    serial = screen(names, ref, ref_sims, trials, measured, noise, OPTIONS, refitted=REFIT)
    with TrialPool(trials, 2) as pool:
        pooled = screen(names, ref, ref_sims, trials, measured, noise, OPTIONS, pool=pool, refitted=REFIT)
    assert {n: pooled[n].to_json() for n in names} == {n: serial[n].to_json() for n in names}
    assert serial["staircase"].gain > 0.0


def test_time_constants_are_tried_at_their_defaults_then_at_every_combination_of_two_quantiles():
    from neuromuscle.diagnose.screening import GRID_QUANTILES, time_constant_settings
    from neuromuscle.model.extensions import registry

    known = registry()
    doublet = time_constant_settings(known["doublet_potentiation"])
    assert doublet[0] == {} and len(doublet) == 1 + len(GRID_QUANTILES) ** 2
    spec = {known["doublet_potentiation"].qualified(p.name): p for p in known["doublet_potentiation"].parameters}
    assert all(spec[q].lower < v < spec[q].upper for s in doublet[1:] for q, v in s.items())
    assert min(s["doublet_potentiation.tau_f"] for s in doublet[1:]) < 4.0
    assert time_constant_settings(known["length_dependent_activation"]) == [{}]  # no time constant: defaults only


def test_an_effect_far_from_its_default_time_constants_is_found_on_the_grid(setting):
    """A doublet potentiation with a fast facilitation and a slow hold (tau_f 3.8, tau_h 300 ms; defaults 8 and
    25 ms) gains far more at a grid setting than at the defaults, and the screen says which setting it was."""
    from neuromuscle.diagnose.screening import screen_settings

    trials, ref, ref_sims = setting
    truth = ref.with_values({"doublet_potentiation.k": 2.0, "doublet_potentiation.tau_f": 3.8,
                             "doublet_potentiation.tau_h": 300.0})
    measured = _measured(trials, simulate_all(truth, trials, ("doublet_potentiation",)), 5)
    noise = _noise(trials, measured)
    every = screen_settings(["doublet_potentiation"], ref, ref_sims, trials, measured, noise, OPTIONS, refitted=REFIT)
    at_defaults = next(s for s in every if not s.time_constants)
    best = screen(["doublet_potentiation"], ref, ref_sims, trials, measured, noise, OPTIONS,
                  refitted=REFIT)["doublet_potentiation"]
    assert best.time_constants, (at_defaults.gain, best.gain)
    assert best.time_constants["doublet_potentiation.tau_h"] > 100.0
    assert best.gain > 2.0 * at_defaults.gain and best.score > 0.0


def test_a_candidate_refits_only_its_subset():
    """``subsets``: a candidate whose fit refits fewer of the model's parameters gains what those cannot absorb:
    at least as much as with all of them."""

    trials = list(make_data(5).trials.values())[:5]
    ref = load_parameters("CT09")
    ref_sims = simulate_all(ref, trials)
    truth = ref.with_values({"staircase.k": 0.4, "staircase.u": 0.1, "staircase.tau": 3000.0})
    measured = _measured(trials, simulate_all(truth, trials, ("staircase",)), 6)
    noise = _noise(trials, measured)
    full = screen(["staircase"], ref, ref_sims, trials, measured, noise, OPTIONS, refitted=REFIT)["staircase"]
    part = screen(["staircase"], ref, ref_sims, trials, measured, noise, OPTIONS, refitted=REFIT,
                  subsets={"staircase": ("C1",)})["staircase"]
    assert part.gain >= full.gain > 0.0


def test_a_movement_candidate_is_screened_on_the_moving_trials_alone_with_the_same_result(monkeypatch):
    """A candidate that needs movement is not simulated on trials held at a constant length, whose force is the
    model's exactly (tests/model/test_extensions.py): its screen is the one every trial simulated gives, to the bit."""
    from neuromuscle.diagnose import screening
    from neuromuscle.model.extensions import Extension
    from neuromuscle.synth import make_dataset

    data = make_dataset("force_enhancement_after_stretch", 0.8, 3, world="B", noise_pct=1.0,
                        trials=["twitch_opt", "train20_opt", "stretch_hold40", "ramp_shorten40"])
    trials = list(data.trials.values())
    assert sum(screening.constant_length(t) is None for t in trials) == 2
    ref = load_parameters("CT09")
    ref_sims = simulate_all(ref, trials, options=OPTIONS)
    measured = {t.trial_id: np.asarray(t.force, dtype=float) for t in trials}
    noise = {t.trial_id: Noise(0.02, 0.0, float(t.force.size)) for t in trials}
    names = ["force_enhancement_after_stretch", "lengthening_below_optimum", "staircase"]
    args = (names, ref, ref_sims, trials, measured, noise, OPTIONS)
    calls = []
    real = screening.simulate_runs
    monkeypatch.setattr(screening, "simulate_runs", lambda runs, tr, *a: calls.append(len(tr)) or real(runs, tr, *a))
    skipped = [s.to_json() for s in screening.screen_settings(*args, refitted=("P0", "KSE"))]
    assert calls == [4, 2]  # every trial for the model, the refitted and the staircase; the moving ones for the rest
    monkeypatch.setattr(Extension, "needs_movement", classmethod(lambda cls: False))
    every = [s.to_json() for s in screening.screen_settings(*args, refitted=("P0", "KSE"))]
    assert skipped == every
    assert max(s["linearised_chi2_gain"] for s in every if "force_enhancement" in str(s)) > 0.0
