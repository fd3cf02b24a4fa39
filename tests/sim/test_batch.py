"""One protocol under several parameter sets in one NEURON run (neuromuscle.sim.simulate_batch): each unit's force
is bit for bit the one ``simulate`` gives it alone, under movement and for every extension."""

import numpy as np
import pytest

import neuromuscle.sim.run as run_module
from neuromuscle import InputError, kim_excitation, simulate
from neuromuscle.model.extensions import registry
from neuromuscle.protocols import constant_rate, random_length
from neuromuscle.sim import simulate_batch, simulate_protocols
from neuromuscle.sim.recordings import Recorder


def _runs(ct09):
    """The reference twice (two parameter sets) and every catalogue extension at its defaults."""
    moved = ct09.with_values({"kim_m2.C1": ct09["kim_m2.C1"] * 1.01, "kim_m1.Umax": ct09["kim_m1.Umax"] * 0.9})
    return [(ct09, None), (moved, None), *((ct09, {name: {}}) for name in sorted(registry()))]


@pytest.mark.parametrize("dt_ms", [0.1, 0.2])
def test_batch_is_each_run_bit_for_bit_under_movement(ct09, dt_ms):
    """A 20 Hz train through a random length (stretch and shortening at up to ~100 mm/s): every unit of the batch,
    the reference and each extension, is the lone run's force exactly (not to a tolerance)."""
    spikes, trace = constant_rate(20, 500.0, start_ms=50.0), random_length(600.0, seed=2)
    runs = _runs(ct09)
    exc = kim_excitation(True, False)
    batch = simulate_batch(runs, spikes, trace, 600.0, excitation=exc, record=("force.F",), dt_ms=dt_ms,
                           record_dt_ms=dt_ms)
    assert len(batch) == len(runs)
    for (params, ext), got in zip(runs, batch):
        alone = simulate(params, spikes, trace, 600.0, excitation=exc, extensions=ext, record=("force.F",),
                         dt_ms=dt_ms, record_dt_ms=dt_ms)
        assert got is not None and np.array_equal(got.force_N, alone.force_N), ext
        assert got.settings["extensions"] == alone.settings["extensions"]
    forces = [r.force_N for r in batch]
    assert not np.array_equal(forces[0], forces[1])  # the units are not one unit recorded twice
    assert all(f.max() > 1.0 for f in forces)


def test_batch_of_one_and_isometric(ct09):
    """A batch of one, isometric, with a spike after the end (dropped and counted as simulate does)."""
    got = simulate_batch([(ct09, None)], [10.0, 400.0], -6.0, 300.0, dt_ms=0.1)[0]
    alone = simulate(ct09, [10.0, 400.0], -6.0, 300.0, dt_ms=0.1)
    assert np.array_equal(got.force_N, alone.force_N)
    assert got.settings["n_spikes_not_delivered"] == alone.settings["n_spikes_not_delivered"] == 1
    assert got.warnings == alone.warnings and "not delivered" in got.warnings[0]
    assert simulate_batch([], [10.0], -6.0, 300.0) == []


def test_a_failing_unit_is_none_and_the_others_are_untouched(ct09, monkeypatch):
    """No valid parameter set makes a unit fail (every value is range-checked), so the second unit's recording is
    corrupted after the run: that unit comes back None, the others exactly as alone."""
    made = []

    class Corrupting(Recorder):
        def arrays(self, duration_ms):
            t, traces = super().arrays(duration_ms)
            if self is made[1]:
                traces["force.F"][5] = np.nan
            return t, traces

        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            made.append(self)

    monkeypatch.setattr(run_module, "Recorder", Corrupting)
    runs = _runs(ct09)[:3]
    got = simulate_batch(runs, [10.0], -6.0, 200.0, record=("force.F",), dt_ms=0.1)
    monkeypatch.undo()
    assert got[1] is None
    for k in (0, 2):
        alone = simulate(ct09, [10.0], -6.0, 200.0, extensions=runs[k][1], record=("force.F",), dt_ms=0.1)
        assert np.array_equal(got[k].force_N, alone.force_N)


def test_batch_refuses_bad_steps(ct09):
    with pytest.raises(InputError, match="record_dt_ms = 0.05 ms is below the fixed step dt_ms = 0.1 ms"):
        simulate_batch([(ct09, None)], [10.0], -6.0, 100.0, dt_ms=0.1, record_dt_ms=0.05)
    with pytest.raises(InputError, match="duration_ms"):
        simulate_batch([(ct09, None)], [10.0], -6.0, float("nan"))


@pytest.mark.parametrize("bad", ["ct09", "ct09-ext-extra", "dict-params", "ext-not-mapping"])
def test_batch_refuses_a_run_that_is_not_a_parameter_set_and_extensions(ct09, bad):
    """A malformed run is named by its index before NEURON builds anything (not Python's unpacking error)."""
    run = {"ct09": ct09, "ct09-ext-extra": (ct09, None, None), "dict-params": (dict(ct09), None),
           "ext-not-mapping": (ct09, "fatigue")}[bad]
    with pytest.raises(InputError, match=r"simulate_batch: run 1 must be a \(ParameterSet, extensions or None\) pair"):
        simulate_batch([(ct09, None), run], [10.0], -6.0, 100.0)


def test_protocols_of_different_lengths_in_one_run_are_each_alone(ct09):
    """simulate_protocols: a moving 600 ms protocol and an isometric 250.3 ms one (ending off the step grid) in one
    run, each with its own length input; every unit is its lone run bit for bit over its own duration."""
    protocols = [(constant_rate(20, 500.0, start_ms=50.0), random_length(600.0, seed=2), 600.0),
                 ([10.0, 120.0], -6.0, 250.3)]
    runs = [(ct09, None, 1), (ct09, {"fatigue": {}}, 0), (ct09, None, 0), (ct09, None, 1)]
    got = simulate_protocols(runs, protocols, record=("force.F",), dt_ms=0.2, record_dt_ms=0.5)
    for (params, ext, j), res in zip(runs, got):
        spikes, length, duration = protocols[j]
        alone = simulate(params, spikes, length, duration, extensions=ext, record=("force.F",), dt_ms=0.2,
                         record_dt_ms=0.5)
        assert np.array_equal(res.t_ms, alone.t_ms) and np.array_equal(res.force_N, alone.force_N), (ext, j)
    with pytest.raises(InputError, match=r"simulate_protocols: run 0 must be a \(ParameterSet, extensions or None, "
                                         r"protocol index < 2\) triple"):
        simulate_protocols([(ct09, None, 2)], protocols)
