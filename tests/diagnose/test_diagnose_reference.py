"""The reference every candidate is judged against (diagnose/extension_fit.py, ``fit_reference``): Module 2, the pump
rate Umax and the release decay tau2 refitted, so that a preparation whose Ca2+ release decays faster than CT09's
is calibration, not a relaxation_rate effect (suite seed 5's null, tau2 0.66 x CT09's, was named relaxation_rate
while the reference held tau2 at CT09's)."""

from dataclasses import replace

import numpy as np
import pytest

from diagnose_datasets import make_data
from neuromuscle.diagnose import extension_fit, screening
from neuromuscle.diagnose.baseline import OPTIONS, simulate_all
from neuromuscle.diagnose.extension_fit import fit_reference
from neuromuscle.diagnose.residuals import Noise
from neuromuscle.parameters import load_parameters

SD_N = 0.01  # white noise (N), ~0.3 % of the 40 Hz train's force
TRIALS = ("twitch_opt", "twitch_short", "train10_opt", "train20_opt", "train40_opt", "long50_opt")
TAU2_FACTOR = 0.66  # suite seed 5's null preparation


@pytest.fixture(scope="module")
def faster_release():
    """Six isometric trials of CT09 with tau2 times TAU2_FACTOR (everything else CT09's), white noise SD_N."""
    ct09 = load_parameters("CT09")
    truth = ct09.with_values(tau2=TAU2_FACTOR * ct09["tau2"])
    trials = [t for t in make_data(5).trials.values() if t.trial_id in TRIALS]
    clean = simulate_all(truth, trials, OPTIONS)
    rng = np.random.default_rng(7)
    trials = [replace(t, force=clean[t.trial_id] + rng.normal(0.0, SD_N, clean[t.trial_id].size)) for t in trials]
    noise = {t.trial_id: Noise(SD_N, 0.0, float(t.force.size)) for t in trials}
    return ct09, truth, trials, noise


def _relaxation_screen(ref, trials, noise):
    measured = {t.trial_id: t.force for t in trials}
    return screening.screen(["relaxation_rate"], ref.parameters, ref.simulated, trials, measured, noise,
                            OPTIONS)["relaxation_rate"]


def test_the_reference_takes_up_a_faster_release_decay(faster_release, monkeypatch):
    """The reference recovers tau2 and leaves noise; relaxation_rate's screen then gains almost nothing, against
    millions of noise variances at a reference that holds tau2 at CT09's (stop 24's: tau2 neither in the reference
    nor in what the candidates refit, so Module 2 and Umax alone absorb what they can)."""
    ct09, truth, trials, noise = faster_release
    ref = fit_reference(ct09, trials, trials, OPTIONS, noise=noise, workers=2)
    assert ref.parameters["tau2"] == pytest.approx(truth["tau2"], rel=0.1)
    chi2 = sum(float(np.sum((ref.simulated[t.trial_id] - t.force) ** 2)) for t in trials) / SD_N ** 2
    assert chi2 < 1.2 * sum(t.force.size for t in trials)  # the residual is the noise
    with_tau2 = _relaxation_screen(ref, trials, noise)

    for module, name in ((extension_fit, "REFERENCE_FREE"), (screening, "REFITTED")):
        monkeypatch.setattr(module, name, tuple(q for q in getattr(module, name) if q != "tau2"))
    held = fit_reference(ct09, trials, trials, OPTIONS, noise=noise, workers=2)
    assert held.parameters["tau2"] == ct09["tau2"]
    without_tau2 = _relaxation_screen(held, trials, noise)
    assert without_tau2.score > 1000.0 * without_tau2.penalty  # measured: gain 2.0e6 noise variances (Umax 9055)
    assert with_tau2.gain < 1e-3 * without_tau2.gain, (with_tau2, without_tau2)  # measured: 27
