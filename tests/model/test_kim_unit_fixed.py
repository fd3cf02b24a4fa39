"""KimUnitFixed (mod/kim_unit_fixed.mod), KimUnit for the fixed step alone: KimUnit's traces bit for bit under
backward Euler and Crank-Nicolson, every step and every few steps, isometric and under random length with
movement compensation, with catalogue extensions on its ports and in a pool; refused under CVODE."""

import numpy as np
import pytest

from neuromuscle import InputError, simulate
from neuromuscle.model import kim_fused
from neuromuscle.model.mechanisms import fixed_step_only_mechanisms
from neuromuscle.pool import PoolDefinition
from neuromuscle.pool.pool import Pool
from neuromuscle.protocols.lengths import random_length
from neuromuscle.sim import Simulator

VARIABLES = ["muscle.F", "muscle.A", "muscle.atil", "muscle.CaSPT", "muscle.CaSR", "muscle.Fc", "muscle.xce"]


def _pair(params, spikes, length, duration, movement=False, substeps=1, extensions=None, secondorder=0):
    out = []
    for fixed in (False, True):
        out.append(simulate(params, spikes, length, duration, excitation=kim_fused(True, movement, substeps,
                                                                                 fixed_step=fixed),
                            extensions=extensions, record=VARIABLES, simulator=Simulator(secondorder=secondorder)))
    return out


def _assert_identical(unit, fixed):
    for name in VARIABLES:
        assert np.array_equal(unit[name], fixed[name]), (name, np.max(np.abs(unit[name] - fixed[name])))


@pytest.mark.parametrize("secondorder", [0, 2])
@pytest.mark.parametrize("substeps", [1, 4])
def test_a_tetanus_is_kimunits_bit_for_bit(ct09, secondorder, substeps):
    spikes = list(20.0 + 10.0 * np.arange(40))
    unit, fixed = _pair(ct09, spikes, -8.0, 700.0, substeps=substeps, secondorder=secondorder)
    assert unit["muscle.F"].max() > 0.5
    _assert_identical(unit, fixed)


@pytest.mark.parametrize("secondorder", [0, 2])
def test_random_length_with_movement_and_extensions_is_kimunits_bit_for_bit(ct09, secondorder):
    trace = random_length(1200.0, seed=7)
    spikes = list(30.0 + 25.0 * np.arange(45))
    extensions = {"fatigue": {"k": 0.05}, "staircase": {}, "force_enhancement_after_stretch": {}}
    unit, fixed = _pair(ct09, spikes, trace, 1200.0, movement=True, substeps=3, extensions=extensions,
                        secondorder=secondorder)
    plain = simulate(ct09, spikes, trace, 1200.0, excitation=kim_fused(True, True, 3, fixed_step=True),
                     record=["muscle.F"], simulator=Simulator(secondorder=secondorder))
    assert np.max(np.abs(fixed["muscle.F"] - plain["muscle.F"])) > 1e-3   # the extensions act on its ports
    _assert_identical(unit, fixed)


def test_cvode_is_refused_with_the_mechanism_named(ct09):
    assert fixed_step_only_mechanisms() == ("KimUnitFixed",)
    with pytest.raises(InputError, match="KimUnitFixed.*fixed step only"):
        simulate(ct09, [10.0], -8.0, 100.0, excitation=kim_fused(fixed_step=True), method="cvode")
    # KimUnit itself runs under CVODE
    assert simulate(ct09, [10.0], -8.0, 100.0, excitation=kim_fused(), method="cvode").force_N.max() > 0.01


def test_a_pool_of_kimunitfixed_is_a_pool_of_kimunit(ct09):
    forces, spikes = [], []
    for model in ("fused", "fused_fixed"):
        d = PoolDefinition(5, ct09, muscle_model=model, muscle_substeps=6, pic_substeps=6)   # mn_soma, mn_pic
        with Pool(d, length=-8.0) as pool:
            pool.drive_current_ramp([0.0, 300.0], [0.0, 20.0])
            r = pool.run(300.0, Simulator(dt_ms=1 / 30, secondorder=2))
        forces.append(r.unit_force_N)
        spikes.append(r.spikes_ms)
        assert r.provenance["muscle_model"] == model
    assert sum(s.size for s in spikes[0]) > 10 and forces[0].max() > 0.1
    assert all(np.array_equal(a, b) for a, b in zip(*spikes))
    np.testing.assert_array_equal(forces[0], forces[1])
    with Pool(PoolDefinition(2, ct09, muscle_model="fused_fixed"), length=-8.0) as pool:
        pool.drive_current_ramp([0.0, 100.0], [0.0, 20.0])
        with pytest.raises(InputError, match="KimUnitFixed"):
            pool.run(100.0, Simulator(method="cvode"))


def test_from_hoc_a_cvode_initialisation_marks_the_unit_refused(ct09):
    from neuron import h

    from neuromuscle import MuscleUnit

    unit = MuscleUnit(ct09, excitation=kim_fused(fixed_step=True))
    obj = unit.components["muscle"].obj
    cv = h.CVode()
    was = cv.active()
    try:
        for on in (1, 0):
            cv.active(on)
            h.finitialize()
            assert obj.refused == on
    finally:
        cv.active(was)
        h.finitialize()
        unit.destroy()
