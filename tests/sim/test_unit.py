"""The unit's Python API: spikes from any NetCon source, teardown, bad input, HDF5 with provenance."""

import json

import h5py
import numpy as np
import pytest

from neuromuscle import InputError, LengthTrace, MuscleUnit, mechanism_hash, simulate
from neuromuscle.protocols import constant_rate, twitch
from neuromuscle.sim import load_result
from neuromuscle.sim import MAX_DIFFERENCE_DT_MS, MAX_DT_MS
from neuromuscle import Simulator, kim_excitation


def _force_after_run(unit, duration_ms=300.0):
    from neuron import h

    f = h.Vector().record(unit.ref("force.F"), 0.1)
    Simulator(dt_ms=0.025).run(duration_ms, units=[unit])
    return np.array(f)


def test_spikes_from_a_hodgkin_huxley_soma_drive_the_unit(ct09):
    """A motoneuron-like HH soma fires; its voltage crossing drives KimCa through a NetCon."""
    from neuron import h

    soma = h.Section(name="soma")
    soma.L = soma.diam = 20.0
    soma.insert("hh")
    stim = h.IClamp(soma(0.5))
    stim.delay, stim.dur, stim.amp = 100.0, 2.0, 1.0
    with MuscleUnit(ct09, name="hh") as unit:
        unit.length.xm = -8.0
        nc = unit.connect_from(soma(0.5)._ref_v, section=soma, threshold_mV=0.0, delay_ms=2.0)
        f = _force_after_run(unit)
        assert unit.ca.nspike == 1
        assert f.max() == pytest.approx(simulate(ct09, [102.0], -8.0, 300.0).force_N.max(), rel=0.01)
        del nc


def test_netstim_drives_the_unit_like_the_same_times_given_directly(ct09):
    from neuron import h

    ns = h.NetStim()
    ns.start, ns.interval, ns.number, ns.noise = 50.0, 25.0, 8, 0.0
    with MuscleUnit(ct09, name="ns") as unit:
        unit.length.xm = -8.0
        nc = unit.connect_from(ns, delay_ms=0.0)
        f = _force_after_run(unit)
        del nc
    direct = simulate(ct09, 50.0 + 25.0 * np.arange(8), -8.0, 300.0, record_dt_ms=0.1).force_N
    n = min(f.size, direct.size)
    assert np.max(np.abs(f[:n] - direct[:n])) < 1e-3 * direct.max()


def test_destroy_removes_the_unit_from_neuron(ct09):
    from neuron import h

    unit = MuscleUnit(ct09)
    assert unit.ca.nspike == 0
    unit.destroy()
    assert not any(sec.name().startswith("unit_muscle") for sec in h.allsec())


def test_simulations_do_not_leak_neuron_state(ct09):
    from neuron import h

    from neuromuscle.model import hatze, kim
    from neuromuscle.model.mechanisms import load_mechanisms

    load_mechanisms()  # atolscale names the mechanisms' states: they must exist when the test runs alone
    h.load_file("stdrun.hoc")
    cv, pc = h.CVode(), h.ParallelContext()
    h.dt, h.steps_per_ms, h.secondorder = 0.1, 10.0, 2
    cv.atol(1e-4)
    cv.rtol(1e-5)
    cv.condition_order(2)
    states = [f"{c.suffix}.{st.name}" for c in (*kim.COMPONENTS, *hatze.COMPONENTS) for st in c.states]
    for name in states:
        cv.atolscale(name, 0.5)

    def settings():
        return (len(list(h.allsec())), h.List("KimCa").count(), h.List("NetCon").count(), h.dt, h.steps_per_ms,
                h.secondorder, cv.active(), cv.condition_order(), cv.atol(), cv.rtol(), pc.nthread(),
                tuple(cv.atolscale(n) for n in states))

    before = settings()
    a = simulate(ct09, twitch(100.0), -8.0, 300.0, method="cvode", atol=1e-3, rtol=1e-6)
    b = simulate(ct09, twitch(100.0), -8.0, 300.0)
    assert settings() == before  # dt, CVODE, atol, rtol, atolscale (14+ states), nthread all restored
    Simulator(method="cvode", nthread=2).run(10.0)
    assert settings() == before
    c = simulate(ct09, twitch(100.0), -8.0, 300.0)
    np.testing.assert_array_equal(b.force_N, c.force_N)  # a run after a CVODE run is unchanged
    assert a.force_N.max() > 0
    cv.condition_order(1)


@pytest.mark.parametrize("kwargs, match", [
    (dict(spikes_ms=[10.0, float("nan")]), "spike times contains non-finite"),
    (dict(spikes_ms=[30.0, 10.0]), "not sorted"),
    (dict(spikes_ms=[-1.0]), "negative time"),
    (dict(length=LengthTrace(np.array([0.0, 100.0]), np.array([-8.0, -8.0]))), "shorter than the run"),
    (dict(dt_ms=0.5), "dt_ms = 0.5 ms is too large"),
    (dict(dt_ms=float("inf")), "dt_ms must be finite"),
    (dict(duration_ms=-5.0), "duration_ms must be finite and > 0"),
    (dict(method="rk4"), "method must be"),
    (dict(length="long"), "length must be a LengthTrace"),
])
def test_bad_run_input_is_refused_before_neuron_runs(ct09, kwargs, match):
    args = dict(spikes_ms=[10.0], length=-8.0, duration_ms=200.0)
    args.update(kwargs)
    spikes, length, dur = args.pop("spikes_ms"), args.pop("length"), args.pop("duration_ms")
    with pytest.raises(InputError, match=match):
        simulate(ct09, spikes, length, dur, **args)


def test_a_run_that_is_only_differenced_may_take_a_coarser_step():
    """MAX_DT_MS bounds a result's step; a run whose forces are only differenced may take up to
    MAX_DIFFERENCE_DT_MS, and no more."""
    with pytest.raises(InputError, match="too large for the fixed-step scheme"):
        Simulator(method="fixed", dt_ms=MAX_DIFFERENCE_DT_MS)
    assert Simulator(method="fixed", dt_ms=MAX_DIFFERENCE_DT_MS, differenced=True).dt_ms == MAX_DIFFERENCE_DT_MS
    with pytest.raises(InputError, match="too large for runs that are only differenced"):
        Simulator(method="fixed", dt_ms=1.5 * MAX_DIFFERENCE_DT_MS, differenced=True)
    assert MAX_DT_MS < MAX_DIFFERENCE_DT_MS
    with pytest.raises(InputError, match="differenced must be True or False"):
        Simulator(method="fixed", dt_ms=0.1, differenced="yes")
    assert Simulator(method="fixed", dt_ms=0.1, differenced=True).settings()["differenced"] is True
    assert "differenced" not in Simulator(method="fixed", dt_ms=0.1).settings()


def test_bad_length_traces_are_refused():
    with pytest.raises(InputError, match="strictly increasing"):
        LengthTrace(np.array([0.0, 0.0, 1.0]), np.zeros(3))
    with pytest.raises(InputError, match="non-finite"):
        LengthTrace(np.array([0.0, 1.0]), np.array([0.0, np.inf]))


def test_result_hdf5_round_trip_with_provenance(ct09, tmp_path):
    r = simulate(ct09, twitch(50.0), -8.0, 200.0, provenance_extra={"seed": 42})
    path = tmp_path / "r.h5"
    r.save(str(path))
    with pytest.raises(InputError, match="refusing to overwrite"):
        r.save(str(path))
    back = load_result(path)
    np.testing.assert_array_equal(back.force_N, r.force_N)
    assert dict(back.params) == dict(ct09)
    assert back.provenance["mechanism_sha256"] == mechanism_hash()
    assert back.provenance["seed"] == 42 and back.provenance["spikes_ms"] == [50.0]
    assert back.provenance["versions"]["neuron"] != "not installed"
    with h5py.File(path, "r") as f:
        params = json.loads(f.attrs["parameters"])["parameters"]
        assert params["P0"] == {"value": 23.0, "unit": "N"}
    # replay from the file alone gives the same trace
    again = simulate(back.params, back.provenance["spikes_ms"], -8.0, 200.0)
    np.testing.assert_allclose(again.force_N, r.force_N, rtol=0, atol=1e-12)


def test_movement_compensation_lowers_force_while_lengthening_below_optimum(ct09):
    from neuromuscle.protocols import constant_rate, isokinetic_ramp

    spikes = constant_rate(20, 1200.0, start_ms=100.0)
    ramp = isokinetic_ramp(-14.0, -9.0, 5.0, 300.0, 1300.0)
    off = simulate(ct09, spikes, ramp, 1300.0)
    on = simulate(ct09, spikes, ramp, 1300.0, excitation=kim_excitation(movement_compensation=True))
    late = on.t_ms > 900.0
    assert on.force_N[late].mean() < 0.9 * off.force_N[late].mean()
    early = on.t_ms < 300.0
    np.testing.assert_allclose(on.force_N[early], off.force_N[early])


def test_length_compensation_switch(ct09):
    on = simulate(ct09, twitch(100.0), -16.0, 400.0).force_N.max()
    off = simulate(ct09, twitch(100.0), -16.0, 400.0,
                   excitation=kim_excitation(length_compensation=False)).force_N.max()
    assert on < off  # phi(-16) = 0.75 slows troponin binding


def test_fast_stretch_stays_on_the_eccentric_saturation_and_is_counted(ct09):
    """A fast stretch of an active muscle drives F to eq 11's asymptote: the CE yields, F stays below
    (2 + c0/P0) Fc (never a blow-up), and the steps spent there are counted as information."""
    from neuromuscle.protocols import constant_rate, isokinetic_ramp

    ramp = isokinetic_ramp(-10.0, 0.0, 2000.0, 400.0, 600.0)
    r = simulate(ct09, constant_rate(100, 500.0, start_ms=50.0), ramp, 600.0, record=("force.F", "force.Fc"))
    assert np.all(np.isfinite(r.force_N))
    assert r.settings["steps_on_eccentric_saturation"] > 0 and not r.warnings
    # bounds on F itself: tests/sim/test_robust.py


def test_units_spread_over_sections_run_on_two_threads_with_identical_results(ct09):
    """Four units on four sections: with 2 threads NEURON gives each thread two of them (both threads work);
    every unit's force, recorded every step, equals the one-thread run bit for bit."""
    from neuron import h

    spikes = [twitch(50.0), constant_rate(20, 200.0, start_ms=20.0), constant_rate(40, 150.0, start_ms=30.0),
              twitch(80.0)]

    pc = h.ParallelContext()

    def run(nthread):
        units = [MuscleUnit(ct09, name=f"thr{i}") for i in range(4)]
        try:
            vecs = []
            for u, s in zip(units, spikes):
                u.length.xm = -8.0
                u.add_spike_times(s)
                vecs.append(h.Vector().record(u.force, u.ref("force.F")))
            pc.nthread(nthread)
            Simulator(dt_ms=0.025, nthread=nthread).run(250.0, units=units)
            per_thread = [len(list(pc.get_partition(i))) for i in range(nthread)]
            return [np.array(v) for v in vecs], per_thread
        finally:
            pc.nthread(1)
            for u in units:
                u.destroy()

    one, _ = run(1)
    two, per_thread = run(2)
    assert per_thread == [2, 2]  # both threads integrate units
    for a, b in zip(one, two):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_a_unit_starts_at_rest_and_the_published_start_is_kept_on_request(ct09, method):
    """No creep before the first stimulus: force, Atil and the Ca states stay at their t = 0 values; the paper's
    published initial state (all SR calcium free) still gives the spec's unsettled twitch."""
    names = ("force.F", "act.atil", "ca.CaSR", "ca.CaSRCS", "ca.CaSPT")
    rest = simulate(ct09, [300.0], -8.0, 600.0, method=method, record=names)
    before = rest.t_ms < 300.0
    for n in names:
        assert np.ptp(rest[n][before]) <= 1e-9 * max(abs(rest[n][0]), 1e-12), n
    assert rest.force_N[0] == pytest.approx(ct09["P0"] * 0.0599 ** 2, rel=0.01)  # A at rest = Ainf(0)^2
    assert rest["ca.CaSR"][0] == pytest.approx(87.5e-6, rel=0.01)  # spec: the SR equilibrates to ~87.5 uM
    published = simulate(ct09, [10.0], -8.0, 300.0, method=method, initial_state="published")
    assert published.force_N[0] == 0.0 and published.settings["initial_state"] == "published"
    assert published.force_N.max() == pytest.approx(2.66, rel=0.01)  # spec: the unsettled twitch
    with pytest.raises(InputError, match="initial_state must be one of rest, published"):
        simulate(ct09, [10.0], -8.0, 300.0, initial_state="settled")
