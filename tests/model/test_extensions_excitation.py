"""The excitation-side catalogue extensions (staircase, doublet_potentiation, post_activation_potentiation,
relaxation_rate): found by name, neutral bit-identical to the baseline, fixed step and CVODE against the SciPy
twin of the same equations, the effect of the stated sign and size, bounds refused by parameter name."""

import numpy as np
import pytest

from neuromuscle import InputError, MuscleUnit, simulate
from neuromuscle.analysis.metrics import twitch_metrics
from neuromuscle.model.extensions import registry
from neuromuscle.protocols import constant_rate
from neuromuscle.reference import reference_simulate

pytestmark = pytest.mark.heavy(cost_s=85)

XM = -8.0  # mm, CT09's optimum
DT_REC = 0.5  # ms

#: a protocol that shows each effect: (parameters, spikes (ms), duration (ms), recorded exposed outputs)
CASES = {
    "staircase": ({"k": 0.5, "u": 0.1, "tau": 3000.0, "tau_f": 100.0},
                  np.concatenate([constant_rate(5, 1000.0, start_ms=50.0), constant_rate(40, 300.0, start_ms=1100.0),
                                  [1700.0, 1900.0]]), 2100.0, ("gain",)),
    "doublet_potentiation": ({"k": 1.5, "tau_f": 8.0, "tau_h": 25.0}, np.array([50.0, 58.0, 250.0]), 500.0,
                             ("gain",)),
    "post_activation_potentiation": ({"k_rel": 1.2, "k_tau": 0.5, "u": 0.05, "tau": 30000.0, "tau_f": 20.0},
                                     np.concatenate([constant_rate(100, 200.0, start_ms=50.0), [700.0, 1000.0]]),
                                     1300.0, ("gain", "tgain")),
    "relaxation_rate": ({"k": 0.5, "tau": 100.0, "d": 0.4}, np.array([50.0, 150.0, 160.0]), 500.0, ("gain",)),
}
TARGETS = {
    "staircase": {"ca.release_gain": "gain"},
    "doublet_potentiation": {"ca.release_gain": "gain"},
    "post_activation_potentiation": {"ca.release_gain": "gain", "act.tauA_gain": "tgain"},
    "relaxation_rate": {"ca.uptake_gain": "gain"},
}


def port_of(name, output):
    """The baseline port an extension's exposed output drives (TARGETS inverted)."""
    return next(port.split(".")[1] for port, o in TARGETS[name].items() if o == output)


def neutral(name):
    return {p.name: p.neutral for p in registry()[name].parameters if p.neutral is not None}


def peaks(result, spikes, window_ms):
    """Largest force (N) in [spike, spike + window_ms) after each spike."""
    return np.array([result.force_N[(result.t_ms >= s) & (result.t_ms < s + window_ms)].max() for s in spikes])


#: the cases run against their SciPy twin: every CASES entry, and relaxation_rate with d < 1 on a 100 Hz burst and
#: then a lone twitch (each spike raises X by 30 % of what is left);
#: id -> (extension, values, spikes, duration, outputs)
TWINS = {**{name: (name, *case) for name, case in CASES.items()},
         "relaxation_rate/partial": ("relaxation_rate", {"k": 0.6, "tau": 150.0, "d": 0.3},
                                     np.concatenate([constant_rate(100, 150.0, start_ms=50.0), [600.0]]), 900.0,
                                     ("gain",))}


@pytest.fixture(scope="module")
def twins(ct09):
    """The SciPy integration of every twin case, computed once (it is the slow part)."""
    out = {}
    for case, (name, values, spikes, dur, _) in TWINS.items():
        mod = registry()[name].reference_modulation(values, spikes)
        out[case] = (mod, reference_simulate(ct09, spikes, XM, dur, record_dt_ms=DT_REC, modulation=mod))
    return out


def test_the_four_are_found_by_name_with_their_ports():
    cat = registry()
    for name, targets in TARGETS.items():
        assert cat[name].targets == targets, name
        assert all(p.lower <= p.default <= p.upper for p in cat[name].parameters), name
        assert neutral(name), f"{name} declares no neutral value"


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_neutral_reproduces_the_baseline(ct09, name, method):
    """Fixed step: bit-identical.  CVODE: the extension's states join the error norm (as fatigue's)."""
    spikes = np.concatenate([[50.0, 58.0], constant_rate(20, 300.0, start_ms=200.0)])
    base = simulate(ct09, spikes, XM, 600.0, method=method, record=("force.F", "act.A"))
    off = simulate(ct09, spikes, XM, 600.0, method=method, extensions={name: neutral(name)},
                   record=("force.F", "act.A"))
    if method == "fixed":
        np.testing.assert_array_equal(base.force_N, off.force_N)
        np.testing.assert_array_equal(base["act.A"], off["act.A"])
    else:
        assert np.max(np.abs(base.force_N - off.force_N)) < 1e-4 * base.force_N.max()
    assert off.settings["extensions"] == [name]


@pytest.mark.parametrize("case", list(TWINS))
@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_matches_its_scipy_twin(ct09, twins, case, method):
    name, values, spikes, dur, outputs = TWINS[case]
    mod, ref = twins[case]
    sim = simulate(ct09, spikes, XM, dur, method=method, record_dt_ms=DT_REC, extensions={name: values},
                   record=("force.F", *(f"{name}.{o}" for o in outputs)))
    n = min(ref.t_ms.size, sim.t_ms.size)
    err = sim.force_N[:n] - ref.force_N[:n]
    # the tolerances of fatigue's test (the baseline's own against SciPy on random trains)
    assert np.sqrt(np.mean(err**2)) < 0.005 * ref.force_N.max(), method
    assert np.max(np.abs(err)) < 0.015 * ref.force_N.max(), method
    for o in outputs:
        expected = np.array([mod[port_of(name, o)](t) for t in sim.t_ms[:n]])
        np.testing.assert_allclose(sim[f"{name}.{o}"][:n], expected, atol=2e-3, err_msg=o)


def test_staircase_sign_and_size(ct09):
    spikes = constant_rate(5, 1900.0, start_ms=50.0)  # 10 twitches at 5 Hz
    base = peaks(simulate(ct09, spikes, XM, 2100.0), spikes, 200.0)
    up = peaks(simulate(ct09, spikes, XM, 2100.0, extensions={"staircase": {"k": 0.5, "u": 0.1, "tau": 3000.0}}),
               spikes, 200.0)
    down = peaks(simulate(ct09, spikes, XM, 2100.0,
                          extensions={"staircase": {"k": -0.4, "u": 0.1, "tau": 3000.0}}), spikes, 200.0)
    # S before the 10th spike's release is ~0.5, so release x1.25 / x0.8: the 10th twitch moves by > 10 %
    assert up[9] > 1.10 * base[9] and down[9] < 0.90 * base[9]
    # and it is a staircase: the change grows from twitch to twitch
    assert np.all(np.diff(up / base) > 0) and np.all(np.diff(down / base) < 0)


def test_staircase_is_built_by_low_rates(ct09):
    """The same 12 spikes, then a probe twitch 600 ms later.  A spike builds S by u (1 - F)^3, F = exp(-ISI/tau_f):
    at 5 Hz by 0.90 u (tau_f 60 ms) or 0.98 u (40 ms, the lower bound), at 50 Hz by 0.023 u or 0.06 u after the
    first: S is ~8x smaller after the 50 Hz train (its first spike alone builds a full u), and the probe grows about
    a quarter as much (twitch force grows faster than release near the threshold).  (The shallow gate of stops
    24-36, u (1 - F), built 0.28 u per 50 Hz spike at 60 ms.)"""
    grown = {}
    for rate in (5, 50):
        train = constant_rate(rate, 12 * 1000.0 / rate - 1.0, start_ms=50.0)
        assert train.size == 12
        probe = train[-1] + 600.0
        spikes = np.concatenate([train, [probe]])
        b = peaks(simulate(ct09, spikes, XM, probe + 300.0), [probe], 250.0)[0]
        for tau_f in (60.0, 40.0):
            values = {"k": 0.8, "u": 0.03, "tau": 5000.0, "tau_f": tau_f}
            e = peaks(simulate(ct09, spikes, XM, probe + 300.0, extensions={"staircase": values}), [probe], 250.0)[0]
            grown[tau_f, rate] = e / b - 1.0
    for tau_f in (60.0, 40.0):
        assert grown[tau_f, 5] > 0.15, grown  # measured 0.26, 0.27
        assert 0.0 < grown[tau_f, 50] < 0.35 * grown[tau_f, 5], grown  # measured 0.067, 0.079


@pytest.mark.parametrize("tau_f", [40.0, 200.0])
def test_a_tetanus_hardly_builds_the_staircase_at_any_admissible_interval_scale(ct09, tau_f):
    """What tells the staircase from a removal slowed by recent activity (synth's relaxation effect): at
    either tau_f bound, the 100 Hz tetanus of the post-tetanic trials (30 spikes) builds S as 1.2 or 0.9 lone spikes
    do, six twitches at 2 Hz as 4.2 or 3.5 (u 0.05, tau 5 s; S read from NEURON).  A shallow gate, u (1 - F) with
    tau_f at 2 ms, builds ~15 from the tetanus."""
    values = {"k": 0.5, "u": 0.05, "tau": 5000.0, "tau_f": tau_f}
    built = {}
    for label, spikes in (("tetanus", constant_rate(100, 299.0, start_ms=50.0)),
                          ("2 Hz", constant_rate(2, 2600.0, start_ms=50.0))):
        r = simulate(ct09, spikes, XM, spikes[-1] + 5.0, extensions={"staircase": values},
                     record=("staircase.gain",))
        built[label] = (r["staircase.gain"][-1] - 1.0) / values["k"] / values["u"]  # S in units of u, 5 ms after
    assert built["tetanus"] < 1.5 and built["2 Hz"] > 3.0, built


def test_staircase_interval_scale_below_its_bound_is_refused(ct09):
    """tau_f under 40 ms would let a tetanus build the staircase (a shallow gate with tau_f at 2 ms builds ~15 lone
    spikes' worth from one)."""
    with pytest.raises(InputError, match="tau_f"):
        simulate(ct09, [50.0], XM, 200.0, extensions={"staircase": {"k": 0.5, "tau_f": 2.0}})


def test_doublet_potentiates_short_intervals_only(ct09):
    values = {"k": 1.5, "tau_f": 8.0, "tau_h": 25.0}
    single = [50.0]
    alone = simulate(ct09, single, XM, 400.0, extensions={"doublet_potentiation": values})
    np.testing.assert_array_equal(simulate(ct09, single, XM, 400.0).force_N, alone.force_N)
    gain = {}
    for isi in (8.0, 30.0):
        spikes = [50.0, 50.0 + isi]
        b = simulate(ct09, spikes, XM, 450.0).force_N.max()
        e = simulate(ct09, spikes, XM, 450.0, extensions={"doublet_potentiation": values}).force_N.max()
        gain[isi] = e / b - 1.0
    assert gain[8.0] > 0.05, gain  # F = exp(-1) at the 2nd spike: release x ~1.5 while it lasts
    assert 0.0 <= gain[30.0] < 0.2 * gain[8.0], gain


def test_pap_after_a_tetanus_grows_and_slows_the_twitch(ct09):
    values = CASES["post_activation_potentiation"][0]
    spikes = np.concatenate([constant_rate(100, 200.0, start_ms=50.0), [800.0]])
    base = simulate(ct09, spikes, XM, 1200.0, record_dt_ms=0.25)
    pap = simulate(ct09, spikes, XM, 1200.0, record_dt_ms=0.25,
                   extensions={"post_activation_potentiation": values})
    late = base.t_ms >= 790.0
    tb = twitch_metrics(base.t_ms[late], base.force_N[late], 800.0)
    tp = twitch_metrics(pap.t_ms[late], pap.force_N[late], 800.0)
    # u F = 0.05 exp(-10/20) = 0.03 per spike: P ~ 0.43 after 20 spikes: release x1.5, tau_A x1.2
    assert tp.peak_N > 1.15 * tb.peak_N, (tb, tp)
    assert tp.half_relaxation_ms > 1.05 * tb.half_relaxation_ms, (tb, tp)


def test_pap_needs_short_intervals(ct09):
    """The same 20 spikes at 10 Hz (F = exp(-100/20) = 0.007 at each) leave the later twitch almost unchanged;
    a lone twitch is exactly unchanged (its spike finds F = 0)."""
    values = CASES["post_activation_potentiation"][0]
    spikes = np.concatenate([constant_rate(10, 2000.0, start_ms=50.0), [2600.0]])
    base = simulate(ct09, spikes, XM, 3000.0, record_dt_ms=0.25)
    pap = simulate(ct09, spikes, XM, 3000.0, record_dt_ms=0.25, extensions={"post_activation_potentiation": values})
    late = base.t_ms >= 2590.0
    tb = twitch_metrics(base.t_ms[late], base.force_N[late], 2600.0)
    tp = twitch_metrics(pap.t_ms[late], pap.force_N[late], 2600.0)
    assert tb.peak_N <= tp.peak_N < 1.02 * tb.peak_N, (tb, tp)
    lone = simulate(ct09, [50.0], XM, 400.0, extensions={"post_activation_potentiation": values})
    np.testing.assert_array_equal(lone.force_N, simulate(ct09, [50.0], XM, 400.0).force_N)


@pytest.mark.parametrize("k,peak,time_to_peak", [(-1.5, "lower", "earlier"), (0.5, "higher", "later")])
def test_relaxation_rate_effects(ct09, k, peak, time_to_peak):
    """d = 1, tau 30 ms: a pump sped up after the spike (k < 0) cuts the Ca2+ transient that outlasts release: a
    smaller, earlier twitch; one slowed (k > 0) a larger, later one.  The pump is changed from the spike on and back
    to the model's late in the relaxation (X = exp(-t/30 ms))."""
    base = simulate(ct09, [50.0], XM, 600.0, record_dt_ms=0.25)
    ext = simulate(ct09, [50.0], XM, 600.0, record_dt_ms=0.25,
                   extensions={"relaxation_rate": {"k": k, "tau": 30.0, "d": 1.0}},
                   record=("force.F", "relaxation_rate.gain"))
    tb = twitch_metrics(base.t_ms, base.force_N, 50.0)
    te = twitch_metrics(ext.t_ms, ext.force_N, 50.0)
    assert (te.peak_N < 0.7 * tb.peak_N) if peak == "lower" else (te.peak_N > 1.3 * tb.peak_N), (tb, te)
    # CT09: k = -1.5 -> peak 0.56x, 81.3 -> 78.1 ms; k = 0.5 -> peak 1.38x, 84.0 ms
    assert (te.time_to_peak_ms < 0.98 * tb.time_to_peak_ms) if time_to_peak == "earlier" else \
        (te.time_to_peak_ms > 1.02 * tb.time_to_peak_ms), (tb, te)
    gain = ext["relaxation_rate.gain"]
    assert gain[np.searchsorted(ext.t_ms, 50.5)] == pytest.approx(1.0 - k * np.exp(-0.5 / 30.0), abs=1e-3)
    assert np.all(np.abs(gain[ext.t_ms >= 350.0] - 1.0) < 1e-4)


def test_relaxation_rate_partial_depth_gain(twins):
    mod, _ = twins["relaxation_rate/partial"]
    # the burst drives X towards 1 (the pump towards 1 - k); the lone twitch raises X only to ~d (from 0.06)
    assert mod["uptake_gain"](195.0) < 0.6 and mod["uptake_gain"](600.01) > 0.75


def test_relaxation_rate_partial_depth_slows_relaxation_after_a_tetanus_unlike_a_constant_pump(ct09):
    """d = 0.1, k = 0.6, tau 300 ms: a twitch leaves the pump at 0.94x the base set's (X = 0.1 after its spike), a
    300 ms train at 100 Hz brings it to ~0.55x.  Against the base set with its pump a constant 0.94x (what a
    recalibrated Umax gives), the twitch is nearly the same and the train relaxes more slowly."""
    def half_relaxations(params, ext):
        out = []
        for spikes in ([50.0], constant_rate(100, 300.0, start_ms=50.0)):
            r = simulate(params, spikes, XM, 1200.0, record_dt_ms=0.25, extensions=ext)
            last = float(np.asarray(spikes)[-1])
            after = r.t_ms >= last
            f, t = r.force_N[after], r.t_ms[after]
            top = int(np.argmax(f))
            out.append(float(t[top + int(np.argmax(f[top:] < 0.5 * f[top]))] - last))
        return np.array(out)
    constant = half_relaxations(ct09.with_values({"Umax": 0.94 * ct09["Umax"]}), None)
    partial = half_relaxations(ct09, {"relaxation_rate": {"k": 0.6, "tau": 300.0, "d": 0.1}})
    assert abs(partial[0] / constant[0] - 1.0) < 0.05, (constant, partial)
    assert partial[1] > 1.05 * constant[1], (constant, partial)


@pytest.mark.parametrize("name", list(CASES))
def test_out_of_bounds_is_refused_naming_the_parameter(ct09, name):
    for p in registry()[name].parameters:
        for bad in (p.upper * 1.5 + 1.0, p.lower - 1.0):
            with pytest.raises(InputError, match=f"'{p.name}' = .* is outside its physiological range"):
                MuscleUnit(ct09, extensions={name: {p.name: bad}})


@pytest.mark.parametrize("name", list(CASES))
def test_selected_by_name_in_the_unit(ct09, name):
    values = CASES[name][0]
    with MuscleUnit(ct09, extensions={name: values}) as unit:
        assert unit.extension_names == (name,)
        for port in TARGETS[name]:
            slot, _, _ = port.partition(".")
            assert unit.components[slot].obj.use_ports == 1.0, port
        for k, v in values.items():
            assert getattr(unit.components[name].obj, k) == v
        assert (unit.components[name].obj in unit.spike_receivers()) == registry()[name].receives_spikes


@pytest.mark.parametrize("name", list(CASES))
def test_extension_from_the_command_line(ct09, tmp_path, name):
    from neuromuscle.cli import main
    from neuromuscle.sim.results import load_result

    values = CASES[name][0]
    arg = name + ":" + ",".join(f"{k}={v}" for k, v in values.items())
    out = tmp_path / "s.h5"
    assert main(["simulate", "--protocol", "train", "--rate-hz", "100", "--start-ms", "50", "--train-ms", "60",
                 "--duration-ms", "500", "--extension", arg, "--out", str(out)]) == 0
    got = load_result(out)
    assert got.settings["extensions"] == [name]
    # the values reached the mechanism: the same run from Python gives the same force, unlike the baseline
    train = constant_rate(100, 60.0, start_ms=50.0)  # 10 ms intervals: every effect shows
    same = simulate(ct09, train, XM, 500.0, record_dt_ms=0.5, extensions={name: values})
    np.testing.assert_allclose(got.force_N, same.force_N, rtol=1e-12)
    base = simulate(ct09, train, XM, 500.0, record_dt_ms=0.5)
    assert np.max(np.abs(got.force_N - base.force_N)) > 1e-3 * got.force_N.max()
    assert main(["simulate", "--extension", f"{name}:{next(iter(values))}=99", "--out",
                 str(tmp_path / "bad.h5")]) != 0
