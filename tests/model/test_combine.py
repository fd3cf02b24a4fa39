"""Two extensions on one modulation port: a PortCombine multiplies their gains (or adds their force offsets), so
several causes act in one unit; one extension per port is wired directly, as before."""

import numpy as np

from neuromuscle import MuscleUnit, load_parameters, simulate
from neuromuscle.protocols import constant_rate, isokinetic_ramp


def _force(ext, length=-8.0, spikes=None):
    p = load_parameters("CT09")
    s = constant_rate(5, 2000.0, start_ms=100.0) if spikes is None else spikes
    r = simulate(p, s, length, 2300.0, extensions=ext, dt_ms=0.1, record=("force.F",), record_dt_ms=1.0)
    return r.force_N


def test_two_gains_on_release_multiply():
    """With one of the two at neutral the pair gives the other's force (within the one-step lag of the combiner);
    with both on, the force differs from each alone."""
    alone = _force({"staircase": {"k": 0.5}})
    pair_neutral = _force({"staircase": {"k": 0.5}, "doublet_potentiation": {"k": 0.0}})
    assert np.max(np.abs(pair_neutral - alone)) < 2e-3 * np.max(alone)
    both = _force({"staircase": {"k": 0.5}, "fatigue": {}})
    assert np.max(np.abs(both - alone)) > 1e-3 * np.max(alone)
    assert np.max(np.abs(both - _force({"fatigue": {}}))) > 1e-2 * np.max(alone)


def test_two_force_offsets_add():
    """Force enhancement and depression after a stretch-shorten cycle: with depression at neutral the pair is
    enhancement alone; the combiner is a slot of the unit, named after the port."""
    law = isokinetic_ramp(-8.0, -3.0, 20.0, 600.0, 2300.0)
    s = constant_rate(40, 2000.0, start_ms=100.0)
    fe = _force({"force_enhancement_after_stretch": {"k": 0.3}}, law, s)
    pair = _force({"force_enhancement_after_stretch": {"k": 0.3}, "force_depression_after_shortening": {"k": 0.0}},
                  law, s)
    assert np.max(np.abs(pair - fe)) < 2e-3 * np.max(fe)
    unit = MuscleUnit(load_parameters("CT09"), extensions={"force_enhancement_after_stretch": {},
                                                           "force_depression_after_shortening": {}})
    try:
        assert "force_force_offset_combine1" in unit.components
        assert unit.components["force_force_offset_combine1"].switches() == {"mode": "sum"}
    finally:
        unit.destroy()
