"""SynthPlay: nothing played is the baseline bit for bit; a played series reaches the port under fixed step and
CVODE alike; the hidden forms are not the catalogue's."""

import numpy as np
import pytest

from neuromuscle import InputError, kim_excitation, simulate
from neuromuscle.protocols import constant_rate
from neuromuscle.synth.play import SynthPlay, played_models


def test_nothing_played_is_the_baseline(ct09):
    spikes = constant_rate(20, 500.0, start_ms=100.0)
    base = simulate(ct09, spikes, -8.0, 800.0, excitation=kim_excitation(False, False), record=("force.F",))
    exc, con = played_models({})
    assert set(con) == {"force"}
    same = simulate(ct09, spikes, -8.0, 800.0, excitation=exc, contraction=con, record=("force.F",))
    np.testing.assert_array_equal(base.force_N, same.force_N)
    exc, con = played_models({"release_gain": (np.array([0.0, 800.0]), np.ones(2))})
    neutral = simulate(ct09, spikes, -8.0, 800.0, excitation=exc, contraction=con, record=("force.F",))
    np.testing.assert_array_equal(base.force_N, neutral.force_N)  # use_ports on, gain exactly 1


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_played_series_reach_the_ports(ct09, method):
    spikes = constant_rate(20, 900.0, start_ms=100.0)
    t = np.array([0.0, 500.0, 500.2, 1100.0])
    series = {"release_gain": (t, np.array([1.0, 1.0, 0.5, 0.5])),
              "force_offset": (np.array([0.0, 1100.0]), np.array([0.0, 2.0]))}
    exc, con = played_models(series)
    r = simulate(ct09, spikes, -8.0, 1100.0, excitation=exc, contraction=con, method=method,
                 record=("force.F", "force.Fse", "synth.release_gain", "synth.force_offset"))
    i = np.searchsorted(r.t_ms, [250.0, 800.0])
    np.testing.assert_allclose(r["synth.release_gain"][i], [1.0, 0.5], atol=1e-9)
    np.testing.assert_allclose(r["force.F"] - r["force.Fse"], r["synth.force_offset"], atol=1e-9)
    base = simulate(ct09, spikes, -8.0, 1100.0, excitation=kim_excitation(False, False), method=method)
    before, after = slice(0, i[0]), slice(int(np.searchsorted(r.t_ms, 700.0)), i[1])
    np.testing.assert_allclose(r["force.Fse"][before], base.force_N[before], atol=2e-3 * base.force_N.max())
    assert r["force.Fse"][after].mean() < 0.95 * base.force_N[after].mean()


def test_bad_series_are_refused():
    with pytest.raises(InputError, match="unknown port"):
        SynthPlay({"gain": (np.zeros(2), np.ones(2))})
    with pytest.raises(InputError, match="non-decreasing"):
        SynthPlay({"release_gain": (np.array([1.0, 0.0]), np.ones(2))})


def test_hidden_fatigue_is_not_the_catalogue_fatigue():
    """The catalogue's fatigue scales release by 1 - D with D -> D + k (1 - D) per spike (an exponential in the
    spike count); the hidden form falls hyperbolically with a rate-weighted count: no (k, tau_rec) of the extension
    reproduces its release gain over a 40 Hz train.  (Both also lower the force, each in its own way.)"""
    from neuromuscle.model.extensions import registry
    from neuromuscle.synth.effects import TrialInput, modulation

    spikes = 300.0 + np.arange(480) * 25.0
    t = np.arange(0.0, 12_400.0, 1.0)
    inp = TrialInput(t, np.full(t.size, -8.0), np.zeros(t.size), spikes, -8.0, 21.4, 23.0)
    series = modulation("fatigue", inp, 1.0)
    assert set(series) == {"release_gain", "force_scale"}
    tg, g = series["release_gain"]
    at = spikes + 1.0
    hidden = np.interp(at, tg, g)
    ext = registry()["fatigue"]
    best = np.inf
    for k in np.linspace(0.0005, 0.05, 60):
        twin = ext.reference_modulation({"k": k, "tau_rec": 600_000.0, "kc": 0.0}, spikes)["release_gain"]
        best = min(best, np.max(np.abs(np.array([twin(x) for x in at]) - hidden)))
    assert best > 0.05


def test_hidden_relaxation_is_not_the_catalogue_relaxation():
    """The catalogue's relaxation_rate scales the pump by 1 - k X, X raised by d (1 - X) at each spike and decaying
    exponentially (an exponential saturation in the spike count); the hidden form divides the pump by 1 + a L, L a
    first-order Hill function of a leaky count (a hyperbolic saturation of a linear sum).  Over a twitch, a 10 Hz
    and a 100 Hz train, no (k, tau, d) of the extension within its bounds comes within 0.05 of the hidden pump
    gain (a = 1.5: the best of the grid is 0.10 off at its worst point, RMS 0.056)."""
    from neuromuscle.model.extensions import registry
    from neuromuscle.model.extensions.spike_trace import SpikeTrace
    from neuromuscle.synth.effects import TrialInput, modulation

    bounds = {p.name: (p.lower, p.upper) for p in registry()["relaxation_rate"].parameters}
    spikes = np.concatenate([[100.0], 600.0 + np.arange(10) * 100.0, 2600.0 + np.arange(50) * 10.0])
    t = np.arange(0.0, 4000.0, 1.0)
    inp = TrialInput(t, np.full(t.size, -8.0), np.zeros(t.size), spikes, -8.0, 21.4, 23.0)
    tg, g = modulation("relaxation_rate", inp, 1.5)["uptake_gain"]
    at = np.union1d(spikes + 1.0, np.arange(0.0, 4000.0, 5.0))
    hidden = np.interp(at, tg, g)
    last = np.searchsorted(spikes, at, side="right") - 1  # the latest spike at or before each time
    best = np.inf
    for tau in np.geomspace(*bounds["tau"], 25):
        for d in np.geomspace(*bounds["d"], 25):
            tr = SpikeTrace(spikes, d, tau)
            x = np.where(last >= 0, tr.after[last] * np.exp(-(at - spikes[last]) / tau), 0.0)
            k = float(x @ (1.0 - hidden) / max(x @ x, 1e-12))  # least squares for 1 - k x ~ hidden
            k = min(max(k, bounds["k"][0]), bounds["k"][1])
            best = min(best, float(np.max(np.abs(1.0 - k * x - hidden))))
    assert best > 0.05, best
