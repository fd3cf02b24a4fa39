"""Pools: size-principle recruitment under a common ramp, recorded discharges, Poisson drive, per-unit extensions,
HDF5 with provenance, summary figure, bad input refused with nothing written."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.model.extensions import registry
from neuromuscle.pool import Pool, PoolDefinition, load_pool_result, p0_spread_N, unit_muscle_parameters
from neuromuscle.pool.motoneuron import FUSED_CHANNELS


def test_p0_spread_and_twitch_speed(ct09):
    p0 = p0_spread_N(5, 0.1, 100.0)
    assert p0[0] == pytest.approx(0.1) and p0[-1] == pytest.approx(10.0)
    assert np.allclose(np.diff(np.log(p0)), np.log(100.0) / 4)
    fast = unit_muscle_parameters(ct09, 1.0, 2.0)
    assert fast["P0"] == 1.0 and fast["tau1"] == ct09["tau1"] / 2 and fast["K1"] == ct09["K1"] * 2
    assert fast["a0"] / fast["P0"] == pytest.approx(ct09["a0"] / ct09["P0"])


def _ramp_run(ct09):
    with Pool(PoolDefinition(4, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        pool.drive_current_ramp([0.0, 150.0, 300.0], [0.0, 40.0, 20.0])
        r = pool.run(300.0)
        return r, pool._clamp_kind


def test_common_clamp_and_per_soma_iclamps_give_the_same_pool(ct09):
    import weakref

    from neuromuscle.pool import pool as pool_module

    common, kind = _ramp_run(ct09)
    assert kind == "common"

    class OtherPool:
        pass

    other = OtherPool()
    pool_module.Pool._common_owner = weakref.ref(other)  # as if another live pool held the shared amplitude
    try:
        own, kind = _ramp_run(ct09)
    finally:
        pool_module.Pool._common_owner = pool_module._nobody
    assert kind == "iclamp"
    assert sum(s.size for s in common.spikes_ms) > 20
    assert all(np.array_equal(a, b) for a, b in zip(common.spikes_ms, own.spikes_ms))
    assert np.array_equal(common.unit_force_N, own.unit_force_N)


def _synaptic_run(ct09, channels="fused"):
    from neuron import h

    soma, pic = FUSED_CHANNELS[channels]
    with Pool(PoolDefinition(4, ct09, smallest_p0_N=0.2, p0_range=20.0, motoneuron_channels=channels)) as pool:
        pool.drive_synaptic([0.0, 200.0, 400.0], [0.0, 0.5, 0.3])
        r = pool.run(400.0)
        kind = pool._synaptic_kind
        shares = [getattr(c.soma(0.5), soma).fcommon for c in pool.cells.values()]
        own = [getattr(seg, pic).gsyn for c in pool.cells.values() for seg in c.dend]   # S/cm2 at the end
        syn = any(sec.has_membrane("mn_syn") for c in pool.cells.values() for sec in c.sections)
    return r, kind, shares, own, syn, getattr(h, f"gcommon_{soma}")


@pytest.mark.parametrize("channels", ["fused", "fused_fixed"])
def test_the_shared_synaptic_drive_and_per_segment_plays_give_the_same_pool(ct09, channels):
    """One play into the fused mechanisms' shared gcommon, each compartment's fcommon its share of the cell's
    conductance, is the pool of one play a segment into the fused mechanisms' own gsyn, to the bit; a pool gives
    the shared value back when it is destroyed; neither inserts mn_syn.  Either fused channel set."""
    import weakref

    from neuromuscle.pool import pool as pool_module

    shared, kind, shares, own, syn, after = _synaptic_run(ct09, channels)
    assert kind == "common" and all(x > 0 for x in shares) and not any(own) and not syn
    assert after == 0.0 and pool_module.Pool._synaptic_owner() is None

    class OtherPool:
        pass

    other = OtherPool()
    pool_module.Pool._synaptic_owner = weakref.ref(other)  # as if another live pool held the shared drive
    try:
        cells, kind, shares, own, syn, _ = _synaptic_run(ct09, channels)
    finally:
        pool_module.Pool._synaptic_owner = pool_module._nobody
    assert kind == "cells" and all(x == 0 for x in shares) and all(x > 0 for x in own) and not syn
    assert sum(s.size for s in shared.spikes_ms) > 20
    assert all(np.array_equal(a, b) for a, b in zip(shared.spikes_ms, cells.spikes_ms))
    assert np.array_equal(shared.unit_force_N, cells.unit_force_N)


def test_ramp_recruits_in_size_order_and_saves(ct09, tmp_path):
    d = PoolDefinition(6, ct09, smallest_p0_N=0.2, p0_range=20.0)
    with Pool(d) as pool:
        pool.drive_current_ramp([0.0, 600.0], [0.0, 40.0])
        r = pool.run(600.0)
    first = [s[0] for s in r.spikes_ms if s.size]
    assert len(first) >= 4 and np.all(np.diff(first) > 0)  # smaller cells first (Henneman)
    assert np.allclose(r.pool_force_N, r.unit_force_N.sum(axis=0))
    assert r.pool_force_N[-1] > 0.05 and r.unit_force_N.shape == (6, 601)
    assert [u["type"] for u in r.units][0] == "S" and r.units[-1]["type"] == "FF"
    path = r.save(tmp_path / "pool.h5")
    back = load_pool_result(path)
    assert np.array_equal(back.unit_force_N, r.unit_force_N)
    assert all(np.array_equal(a, b) for a, b in zip(back.spikes_ms, r.spikes_ms))
    assert back.provenance["mechanism_sha256"] and back.provenance["drive"] == "current"
    with pytest.raises(InputError):
        r.save(path)  # no silent overwrite
    assert r.figure(tmp_path / "pool.png").stat().st_size > 10_000


def test_recorded_discharges_drive_muscle_units(ct09):
    trains = [np.arange(50.0, 400.0, 100.0), np.arange(100.0, 400.0, 50.0), []]
    with Pool(PoolDefinition(3, ct09), motoneurons=False) as pool:
        pool.drive_discharges(trains, 500.0)
        r = pool.run(500.0)
    assert all(np.array_equal(a, np.asarray(b, float)) for a, b in zip(r.spikes_ms, trains))
    f = r.unit_force_N
    assert np.ptp(f[0]) > 0.2 * r.units[0]["P0_N"] and np.ptp(f[2]) < 1e-9  # a silent unit keeps its resting force


def test_poisson_drive_is_reproducible(ct09):
    out = []
    for _ in range(2):
        with Pool(PoolDefinition(3, ct09)) as pool:
            pool.drive_poisson(400.0, 0.15, seed=3)
            out.append(pool.run(300.0))
    assert sum(s.size for s in out[0].spikes_ms) > 0
    assert all(np.array_equal(a, b) for a, b in zip(out[0].spikes_ms, out[1].spikes_ms))


def test_extension_switched_on_per_unit(ct09):
    name = sorted(registry())[0]
    with Pool(PoolDefinition(2, ct09, extensions={1: {name: {}}}), motoneurons=False) as pool:
        assert name in pool.muscle[1].extension_names and not pool.muscle[0].extension_names


@pytest.mark.parametrize("bad", [dict(n_units=0), dict(p0_range=0.5), dict(smallest_p0_N=-1.0),
                                 dict(type_fractions=(0.5, 0.5, 0.5)), dict(extensions={7: {}}),
                                 dict(twitch_speed={"S": 1.0}), dict(smallest_p0_N=1e4)])
def test_impossible_definitions_are_refused(ct09, bad):
    kw = {"n_units": 3, "muscle": ct09, **bad}
    with pytest.raises(InputError):
        PoolDefinition(**kw).units()


@pytest.mark.parametrize("trains, message", [([[10.0, 5.0], [], []], "not sorted"),
                                             ([[10.0, 900.0], [], []], "beyond the run"),
                                             ([[10.0]], "discharge trains for 3 units")])
def test_bad_discharges_refused_nothing_written(ct09, tmp_path, trains, message):
    out = tmp_path / "never.h5"
    with Pool(PoolDefinition(3, ct09), motoneurons=False) as pool:
        with pytest.raises(InputError, match=message):
            pool.drive_discharges(trains, 500.0)
            pool.run(500.0).save(out)
    assert not out.exists()


def test_more_ranks_than_units_is_refused(ct09, monkeypatch):
    import neuromuscle.pool.pool as mod

    class TwoRanks:
        def id(self):
            return 0

        def nhost(self):
            return 2

    monkeypatch.setattr(mod, "parallel_context", lambda: TwoRanks())
    with pytest.raises(InputError, match="2 MPI ranks for 1 units"):
        Pool(PoolDefinition(1, ct09))


def test_size_spacing_and_explicit_p0(ct09):
    from neuromuscle.pool.definition import size_index

    assert size_index(0.5, 1.0) == 0.5 and size_index(1.0, 20.0) == pytest.approx(1.0)
    assert size_index(0.25, 20.0) == pytest.approx(np.log(5.75) / np.log(20.0))   # the low end spread out
    d = PoolDefinition(3, ct09, size_spacing=20.0, p0_N=(1.0, 2.0, 5.0), motoneuron_scales={"ca_decay_ms": 1.5})
    assert [u.muscle["P0"] for u in d.units()] == [1.0, 2.0, 5.0]
    assert d.units()[1].motoneuron.size == pytest.approx(size_index(0.5, 20.0))
    for bad in (dict(p0_N=(1.0, 2.0)), dict(size_spacing=0.5), dict(motoneuron_scales={"nonsense": 2.0}),
                dict(neuromodulation=-1.0)):
        with pytest.raises(InputError):
            PoolDefinition(3, ct09, **bad)


def test_the_pic_gate_step_reaches_every_cell(ct09):
    with Pool(PoolDefinition(3, ct09, pic_substeps=6)) as pool:
        assert {seg.mn_pic.substeps for c in pool.cells.values() for seg in c.dend} == {6.0}
