"""Recording inside a pool (Pool.record): a motoneuron's and a muscle unit's variables by the single unit's names,
through the single unit's Recorder; what they show agrees with the spikes and forces; HDF5 keeps them; bad names,
units and a second call are refused."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition, load_pool_result
from neuromuscle.pool.drives import Drive

VARIABLES = ["mn.v", "mn.i_pic", "act.A", "ca.CaSPT", "force.F"]


@pytest.fixture(scope="module")
def recorded(ct09):
    with Pool(PoolDefinition(3, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        Drive.rise("synaptic", 0.6, 300.0).apply(pool)
        pool.record(VARIABLES, units=[2, 0])
        return pool.run(300.0, record_dt_ms=0.1)


def test_recorded_variables_follow_the_spikes_and_forces(recorded):
    r = recorded
    assert sorted(r.recordings) == sorted(VARIABLES)
    for name in VARIABLES:
        rec = r.recordings[name]
        assert rec.units == [0, 2] and rec.values.shape == (2, r.t_ms.size) and np.isfinite(rec.values).all()
    assert r.recordings["mn.v"].unit == "mV" and r.recordings["act.A"].unit == "1"
    # the recorded force is the unit force of the result
    assert np.array_equal(r.recordings["force.F"].values, r.unit_force_N[[0, 2]])
    for k, unit in enumerate([0, 2]):
        spikes = r.spikes_ms[unit]
        assert spikes.size >= 2
        v = r.recordings["mn.v"].values[k]
        assert v[0] == pytest.approx(-70.0) and v.max() > 0.0   # rests, then overshoots in its spikes
        assert np.all(v[r.t_ms < spikes[0] - 2.0] < -40.0)         # no spike before the first one detected
        ca = r.recordings["ca.CaSPT"].values[k]
        a = r.recordings["act.A"].values[k]
        # calcium and activation rise only after the first spike has travelled down the axon
        arrival = spikes[0] + r.units[unit]["axon_delay_ms"]
        before = r.t_ms < arrival - 0.5
        assert np.ptp(ca[before]) < 1e-3 * ca.max() and a[~before].max() > 2.0 * a[before].max()
        # the PIC current is inward while the cell is driven
        assert r.recordings["mn.i_pic"].values[k].min() < 0.0


def test_recordings_survive_hdf5(recorded, tmp_path):
    path = recorded.save(tmp_path / "pool.h5")
    back = load_pool_result(path)
    assert sorted(back.recordings) == sorted(recorded.recordings)
    for name, rec in recorded.recordings.items():
        got = back.recordings[name]
        assert got.units == rec.units and got.unit == rec.unit and np.array_equal(got.values, rec.values)


def test_no_recording_leaves_the_result_as_before(ct09):
    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        Drive.rise("synaptic", 0.6, 200.0).apply(pool)
        plain = pool.run(200.0)
    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        Drive.rise("synaptic", 0.6, 200.0).apply(pool)
        pool.record(["mn.v", "act.A"], units=[1])
        traced = pool.run(200.0, progress=lambda t: None)
    assert plain.recordings == {}
    assert np.array_equal(plain.unit_force_N, traced.unit_force_N)    # recording and progress change nothing
    assert all(np.array_equal(a, b) for a, b in zip(plain.spikes_ms, traced.spikes_ms))


@pytest.mark.parametrize("names, units, message", [
    (["mn.w"], None, "cannot record ['mn.w']; recordable: "),
    (["act.A", "act.A"], None, "recorded names repeat"),
    ("mn.v", None, "non-empty list"),
    (["mn.v"], [0, 5], "distinct unit indices 0..1"),
    (["mn.v"], [1, 1], "distinct unit indices 0..1"),
])
def test_bad_recordings_are_refused(ct09, names, units, message):
    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]")):
            pool.record(names, units=units)


def test_a_second_record_call_and_motoneuron_variables_without_motoneurons_are_refused(ct09):
    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        pool.record(["act.A"])
        with pytest.raises(InputError, match="already records"):
            pool.record(["mn.v"])
    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0), motoneurons=False) as pool:
        with pytest.raises(InputError, match="cannot record \\['mn.v'\\]"):
            pool.record(["mn.v"])
        pool.record(["ca.CaSPT"], units=[1])
        pool.drive_discharges([[10.0, 60.0], [20.0, 70.0]], 150.0)
        r = pool.run(150.0)
    ca = r.recordings["ca.CaSPT"].values[0]
    assert ca[r.t_ms < 20.0].max() < 0.1 * ca.max()   # unit 1's calcium rises at its first discharge, 20 ms


@pytest.mark.parametrize("channels", ["fused", "separate"])
def test_coreneuron_records_what_neuron_records(ct09, channels):
    """CoreNEURON records every step (the Recorder's stepwise path, a membrane variable by its section): the
    samples are NEURON's, bit for bit, for either channel set."""
    runs = {}
    for engine in ("neuron", "coreneuron"):
        d = PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0, motoneuron_channels=channels)
        with Pool(d, engine=engine) as pool:
            Drive.rise("synaptic", 0.6, 200.0).apply(pool)
            pool.record(["mn.v", "mn.i_pic", "mn.cai", "act.A"], units=[0])
            runs[engine] = pool.run(200.0, record_dt_ms=0.5)
    a, b = runs["neuron"], runs["coreneuron"]
    assert a.spikes_ms[0].size > 2 and a.recordings["mn.i_pic"].values.min() < 0.0
    for name, rec in a.recordings.items():
        np.testing.assert_array_equal(b.recordings[name].values, rec.values)
