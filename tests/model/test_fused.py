"""The fused Kim unit (mod/kim_unit.mod, KimUnit) against the three-mechanism unit (KimCa, KimAct, KimForce):
bit-identical under the fixed step and, for one unit, under CVODE (the same right-hand side), for a twitch,
trains, and random length with and without movement compensation, and with every catalogue extension driving its
modulation ports (three on one port through PortCombine too; under CVODE as well); the muscle-every-k-steps option
converges to it; a contraction beside it is refused."""

import numpy as np
import pytest

from neuromuscle import InputError, MuscleUnit, simulate
from neuromuscle.model import kim_excitation, kim_fused
from neuromuscle.model.extensions import registry
from neuromuscle.protocols.lengths import random_length

THREE = ["force.F", "act.A", "act.atil", "ca.CaSPT", "ca.CaSR", "force.Fc"]
FUSED = ["muscle.F", "muscle.A", "muscle.atil", "muscle.CaSPT", "muscle.CaSR", "muscle.Fc"]

TRAINS = {
    "twitch": ([50.0], 400.0),
    "train_20hz": (list(50.0 + 50.0 * np.arange(10)), 800.0),
    "tetanus_100hz": (list(20.0 + 10.0 * np.arange(40)), 700.0),
}


def _pair(params, spikes, length, duration, movement=False, substeps=1, **sim):
    three = simulate(params, spikes, length, duration, excitation=kim_excitation(True, movement),
                     record=THREE, **sim)
    fused = simulate(params, spikes, length, duration, excitation=kim_fused(True, movement, substeps),
                     record=FUSED, **sim)
    return three, fused


def _assert_identical(three, fused):
    for a, b in zip(THREE, FUSED):
        assert np.array_equal(three[a], fused[b]), (a, np.max(np.abs(three[a] - fused[b])))


@pytest.mark.parametrize("name", list(TRAINS))
def test_fixed_step_is_bit_identical_isometric(ct09, name):
    spikes, duration = TRAINS[name]
    three, fused = _pair(ct09, spikes, -8.0, duration)
    assert three["force.F"].max() > 0.5
    _assert_identical(three, fused)


@pytest.mark.parametrize("movement", [False, True], ids=["static", "movement_compensation"])
def test_fixed_step_is_bit_identical_random_length(ct09, movement):
    trace = random_length(1500.0, seed=3)
    spikes = list(30.0 + 25.0 * np.arange(55))
    three, fused = _pair(ct09, spikes, trace, 1500.0, movement=movement)
    assert three["force.F"].max() > 1.0
    _assert_identical(three, fused)


@pytest.mark.parametrize("movement", [False, True], ids=["static", "movement_compensation"])
def test_cvode_is_bit_identical_for_one_unit(ct09, movement):
    trace = random_length(800.0, seed=5)
    spikes = list(30.0 + 30.0 * np.arange(25))
    three, fused = _pair(ct09, spikes, trace, 800.0, movement=movement, method="cvode", atol=1e-3, rtol=1e-6)
    assert three["force.F"].max() > 1.0
    # one unit: the same states in the same order, the same right-hand side and diagonal Jacobian, so CVODE takes
    # the same steps
    _assert_identical(three, fused)


def test_substeps_converge_to_the_every_step_update(ct09):
    spikes = list(20.0 + 40.0 * np.arange(12))
    ref = simulate(ct09, spikes, -8.0, 600.0, excitation=kim_fused(), record=["muscle.F"])["muscle.F"]
    peak = ref.max()
    errs = []
    for k in (2, 4, 8):
        f = simulate(ct09, spikes, -8.0, 600.0, excitation=kim_fused(substeps=k), record=["muscle.F"])["muscle.F"]
        errs.append(np.max(np.abs(f - ref)) / peak)
    assert 0 < errs[0] < errs[1] < errs[2]      # the error grows with k (and k > 1 is not the k = 1 run)
    assert errs[2] < 0.01                        # k = 8 (0.2 ms muscle step; measured 0.23 %): under 1 % of peak


#: every catalogue extension alone, and three gains on one port (KimCa's release_gain)
EXTENSION_SETS = [(n,) for n in registry()] + [("fatigue", "staircase", "post_activation_potentiation")]


@pytest.mark.parametrize("names", EXTENSION_SETS, ids=lambda names: "+".join(names))
def test_extensions_drive_the_fused_ports_bit_for_bit(ct09, names):
    # random length with movement compensation, eq 18 off: every extension acts (its defaults are not neutral,
    # eq 18 is one of them) and every port is read; three gains on KimCa's release_gain meet in a chain of
    # PortCombines
    extensions = {n: {} for n in names}
    trace = random_length(1500.0, seed=3)
    spikes = list(30.0 + 25.0 * np.arange(55))
    three = simulate(ct09, spikes, trace, 1500.0, excitation=kim_excitation(False, True), extensions=extensions,
                     record=THREE)
    fused = simulate(ct09, spikes, trace, 1500.0, excitation=kim_fused(False, True), extensions=extensions,
                     record=FUSED)
    plain = simulate(ct09, spikes, trace, 1500.0, excitation=kim_fused(False, True), record=["muscle.F"])
    assert np.max(np.abs(fused["muscle.F"] - plain["muscle.F"])) > 1e-3   # the extension changed the force
    _assert_identical(three, fused)


def test_extensions_on_the_fused_ports_under_cvode_are_bit_for_bit(ct09):
    # one unit under CVODE: the ports are read in the same right-hand side evaluations as the three mechanisms'
    extensions = {"fatigue": {"k": 0.05}, "staircase": {}, "force_enhancement_after_stretch": {}}
    trace = random_length(800.0, seed=5)
    spikes = list(30.0 + 30.0 * np.arange(25))
    sim = dict(method="cvode", atol=1e-3, rtol=1e-6)
    three = simulate(ct09, spikes, trace, 800.0, excitation=kim_excitation(True, True), extensions=extensions,
                     record=THREE, **sim)
    fused = simulate(ct09, spikes, trace, 800.0, excitation=kim_fused(True, True), extensions=extensions,
                     record=FUSED, **sim)
    assert three["force.F"].max() > 1.0
    _assert_identical(three, fused)


def test_a_second_contraction_is_refused(ct09):
    with pytest.raises(InputError, match="no contraction"):
        MuscleUnit(ct09, excitation=kim_fused(), contraction="kim")
    with pytest.raises(InputError, match="substeps"):
        kim_fused(substeps=0)


def test_simulate_records_the_fused_unit_by_default_like_the_three_mechanisms(ct09):
    # simulate()'s default recordings asked for "act.A" and failed on the fused unit (slot "muscle"); now they
    # find A, Atil and Module 1's states in whichever slot has them, and the result's properties do too
    fused = simulate(ct09, [10.0], -8.0, 100.0, excitation=kim_fused())
    three = simulate(ct09, [10.0], -8.0, 100.0)
    assert "muscle.A" in fused.traces and "act.A" in three.traces
    for name in ("force_N", "A", "atil"):
        np.testing.assert_array_equal(getattr(fused, name), getattr(three, name), err_msg=name)
    assert sorted(fused.ca_M) == sorted(three.ca_M) == ["CaSP", "CaSPB", "CaSPT", "CaSR", "CaSRCS"]
    np.testing.assert_array_equal(fused.ca_M["CaSPT"], three.ca_M["CaSPT"])
