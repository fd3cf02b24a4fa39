"""The diagnosis's baseline (diagnose/baseline.py): the parameters a file identifies, the step's KSE, no settling,
and a baseline that fits data of its own model family to their noise."""

from dataclasses import asdict

import numpy as np
import pytest

from neuromuscle.diagnose.baseline import calibrate_baseline, free_parameters
from neuromuscle.diagnose.models import OPTIONS
from neuromuscle.diagnose.phases import describe_all
from neuromuscle.diagnose.split import automatic_split
from neuromuscle.fit import trial_simulation
from neuromuscle.model.extensions import registry
from neuromuscle.parameters import load_parameters
from neuromuscle.synth import make_dataset, truth, without_truth
from neuromuscle.synth.dataset import _empty_trial
from neuromuscle.synth.protocols import protocol_set, standard_protocols
from neuromuscle.synth.variation import draw_preparation
from neuromuscle.measured import MeasuredData

pytestmark = pytest.mark.heavy(cost_s=45)

ISOMETRIC = ("twitch_short", "twitch_opt", "twitch_long", "train4_opt", "train10_short", "train20_short",
             "train40_short", "train10_opt", "train20_opt", "train40_opt", "train10_long", "train20_long",
             "train40_long", "low_rate3_opt", "low_rate6_opt")


def _plan(name, **kw):
    trials = {p.trial_id: _empty_trial(p) for p in protocol_set(name, -8.0)}
    return MeasuredData(trials=trials, attrs={}, extra_datasets=kw.get("extra", {}))


@pytest.mark.parametrize("protocols, static, free, held", [
    ("extended", True, {"C1", "C2", "C3", "alpha", "Umax", "tau2", "P0", "g1", "g2", "KSE", "a0", "b0", "c0", "d0"},
     set()),
    ("reduced", False, {"C1", "C2", "C3", "alpha", "Umax", "tau2", "P0", "g1", "g2", "KSE", "a0", "b0", "c0", "d0"},
     set()),
    ("ramps", False, {"C3", "alpha", "Umax", "tau2", "P0", "g1", "g2", "KSE", "a0", "b0", "c0", "d0"}, {"C1", "C2"}),
])
def test_the_baseline_frees_what_the_file_identifies(protocols, static, free, held):
    """Force-length and force-velocity points and a step only start what the trials refine; a file of tetani at one
    rate holds C1 and C2; with movement, KSE and the force-velocity coefficients are free."""
    extra = {"/calibration/force_length": np.zeros((3, 2)), "/calibration/force_velocity": np.zeros((4, 2))} \
        if static else {}
    data = _plan(protocols, extra=extra)
    f, h = free_parameters(data, describe_all(data.trials), list(data.trials))
    assert set(f) == free and set(h) >= held and not set(f) & set(h)


def test_isometric_trials_at_one_length_hold_the_optimum_and_width():
    data = _plan("reduced")
    ids = [i for i in ISOMETRIC if i.endswith("_opt")]
    f, h = free_parameters(data, describe_all(data.trials), ids)
    assert "g1" not in f and "g2" not in f and "KSE" not in f and "a0" not in f
    assert "one length" in h["g2"]


def test_the_diagnosis_runs_need_no_settling():
    """The runs start at the trial's first sample (settle_ms 0): every mechanism, each extension's included, starts
    at rest, so settling for 300 ms first changes the force by less than 1e-6 P0 (on a twitch and a shortening
    hold; a 0.5 ms step sampled at 0.2 ms steps is as sensitive to the last bit of the clock as to the state)."""
    assert OPTIONS.settle_ms == 0.0
    params, _ = draw_preparation(load_parameters("CT09"), 0.2, np.random.default_rng(7))
    plans = standard_protocols(round(float(params["g1"]), 1))
    trials = [_empty_trial(p) for p in plans if p.trial_id in ("twitch_opt", "shorten_hold40")]
    for name in [None, *sorted(registry())]:
        ext = () if name is None else (name,)
        p = params if name is None else params.with_values(
            {registry()[name].qualified(x.name): x.default for x in registry()[name].parameters})
        for tr in trials:
            now = trial_simulation(p, tr, **{**asdict(OPTIONS), "extensions": ext})
            settled = trial_simulation(p, tr, **{**asdict(OPTIONS), "settle_ms": 300.0, "extensions": ext})
            assert np.max(np.abs(now)) > 0.01 * p["P0"], (name, tr.trial_id)
            assert np.max(np.abs(now - settled)) < 1e-6 * p["P0"], (name, tr.trial_id)


def test_a_baseline_fits_data_of_its_own_model_to_their_noise():
    """Twitches and trains at three lengths of a preparation whose every Module 1-3 parameter is ~20 % off CT09
    (no static points): every held-out trial of the calibrated baseline within 1.25 x its noise sd."""
    data = make_dataset(None, 0.0, 11, noise_pct=1.5, world="B-reduced", trials=ISOMETRIC, workers=2)
    sd = float(truth(data)["noise_sd_N"])
    data = without_truth(data)
    split = automatic_split(data)
    from neuromuscle.fit.evaluate import TrialPool
    with TrialPool(list(data.trials.values()), 2) as pool:
        b = calibrate_baseline(data, describe_all(data.trials), split.calibration, load_parameters("CT09"),
                               pool=pool)
    assert b.model.converged, b.model.message
    rms = {i: float(np.sqrt(np.mean((b.simulated[i] - data.trials[i].force) ** 2))) / sd for i in split.heldout}
    assert max(rms.values()) < 1.25, rms
    assert b.free == ("C1", "C2", "C3", "alpha", "Umax", "tau2", "P0", "g2", "g1")


#: A world-B draw whose seven force-length points, spanning 0.8-1 P0, put g2 25 % off its true value.
LENGTH_TRIALS = ("twitch_short", "twitch_opt", "twitch_long", "train10_short", "train10_opt", "train10_long",
                 "train40_short", "train40_opt", "train40_long", "stretch_hold40", "stretch_hold40_4s")


def test_force_length_points_start_g1_and_g2_and_the_trials_refine_them():
    """Force-length points near the optimum say little of the Gaussian's width: held at their estimate, g2 would
    miss the long-length trains; refined by the trials, every held-out trial is within 1.25 x its noise sd."""
    data = make_dataset(None, 0.0, 433681461, noise_pct=1.8, world="B", trials=LENGTH_TRIALS, workers=2)
    t = truth(data)
    sd, g2 = float(t["noise_sd_N"]), float(t["parameters"]["g2"])
    data = without_truth(data)
    split = automatic_split(data)
    from neuromuscle.fit.evaluate import TrialPool
    with TrialPool(list(data.trials.values()), 2) as pool:
        b = calibrate_baseline(data, describe_all(data.trials), split.calibration, load_parameters("CT09"),
                               pool=pool)
    assert abs(b.staged["g2"] / g2 - 1) > 0.15  # the points alone: the draw this test is about
    assert "g1" in b.free and "g2" in b.free
    assert abs(b.parameters["g2"] / g2 - 1) < 0.05
    rms = {i: float(np.sqrt(np.mean((b.simulated[i] - data.trials[i].force) ** 2))) / sd for i in split.heldout}
    assert max(rms.values()) < 1.25, rms
