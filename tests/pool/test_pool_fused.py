"""Pools of fused muscle units (PoolDefinition(muscle_model="fused"), KimUnit): the same spikes and forces, bit for
bit, as pools of the three Kim mechanisms, with extensions too; the muscle every k membrane steps stays within a
stated error of the every-step pool; the fixed-step forms (muscle_model and motoneuron_channels "fused_fixed")
give the fused pool bit for bit under backward Euler and are refused under CVODE; impossible combinations are
refused. (Two MPI ranks: tests/pool/test_mpi.py.)"""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition


def _ramp_pool(ct09, **kw):
    d = PoolDefinition(6, ct09, smallest_p0_N=0.2, p0_range=20.0, **kw)
    with Pool(d) as pool:
        pool.drive_current_ramp([0.0, 500.0], [0.0, 15.0])
        return pool.run(500.0)


@pytest.fixture(scope="module")
def modules_run(ct09):
    return _ramp_pool(ct09)


def test_fused_pool_is_bit_identical_to_the_modules_pool(ct09, modules_run):
    fused = _ramp_pool(ct09, muscle_model="fused")
    assert sum(s.size for s in modules_run.spikes_ms) > 20 and modules_run.pool_force_N.max() > 0.5
    assert all(np.array_equal(a, b) for a, b in zip(modules_run.spikes_ms, fused.spikes_ms))
    assert np.array_equal(modules_run.unit_force_N, fused.unit_force_N)


def test_fused_pool_with_extensions_is_bit_identical_to_the_modules_pool(ct09, modules_run):
    extensions = {"all": {"fatigue": {"k": 0.05}}, 0: {"staircase": {}}}
    modules = _ramp_pool(ct09, extensions=extensions)
    fused = _ramp_pool(ct09, muscle_model="fused", extensions=extensions)
    assert not np.array_equal(modules.unit_force_N, modules_run.unit_force_N)   # the extensions act
    assert np.array_equal(modules.unit_force_N, fused.unit_force_N)


def test_the_fixed_step_forms_give_the_fused_pool_bit_for_bit(ct09):
    from neuromuscle.sim import Simulator

    fused = _ramp_pool(ct09, muscle_model="fused", muscle_substeps=8, pic_substeps=8)
    fixed = _ramp_pool(ct09, muscle_model="fused_fixed", muscle_substeps=8, pic_substeps=8,
                       motoneuron_channels="fused_fixed")
    assert sum(s.size for s in fused.spikes_ms) > 20
    assert all(np.array_equal(a, b) for a, b in zip(fused.spikes_ms, fixed.spikes_ms))
    np.testing.assert_array_equal(fixed.unit_force_N, fused.unit_force_N)
    assert fixed.provenance["motoneuron_channels"] == "fused_fixed"
    with Pool(PoolDefinition(2, ct09, motoneuron_channels="fused_fixed")) as pool:
        pool.drive_current_ramp([0.0, 50.0], [0.0, 15.0])
        with pytest.raises(InputError, match="mn_soma_fixed.*fixed step only"):
            pool.run(50.0, Simulator(method="cvode"))


def test_substeps_error_is_small_and_grows_with_k(ct09, modules_run):
    peak = modules_run.pool_force_N.max()
    errs = [np.max(np.abs(_ramp_pool(ct09, muscle_model="fused", muscle_substeps=k).pool_force_N
                          - modules_run.pool_force_N)) / peak for k in (2, 8)]
    assert 0 < errs[0] < errs[1] < 0.01  # measured: see README, "Motoneuron pools", speed


@pytest.mark.parametrize("bad, message", [(dict(muscle_model="hill"), "muscle_model"),
                                          (dict(muscle_substeps=4), "needs muscle_model='fused'"),
                                          (dict(muscle_model="fused", muscle_substeps=0), "muscle_substeps"),
                                          (dict(motoneuron_channels="hh"), "motoneuron_channels"),
                                          (dict(pic_substeps=0), "pic_substeps"),
                                          (dict(motoneuron_channels="separate", pic_substeps=6),
                                           "needs motoneuron_channels='fused'")])
def test_impossible_fused_definitions_are_refused(ct09, bad, message):
    with pytest.raises(InputError, match=message):
        PoolDefinition(3, ct09, **bad)
