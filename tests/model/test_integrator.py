"""The mechanisms learn the integrator from their GLOBAL variable_step, set at every finitialize from CVode.active()
(neuromuscle/model/integrator.py), also for a run made without the Simulator."""

import numpy as np

from neuromuscle import MuscleUnit
from neuromuscle.model import integrator, mechanisms

FLAGGED = {"KimCa", "KimAct", "KimForce", "KimUnit", "KimUnitFixed", "HatzeExc", "HatzeMTC", "mn_soma", "mn_pic",
           "mn_soma_fixed", "mn_pic_fixed"}


def test_the_mechanisms_with_an_integrator_specific_step_declare_the_flag():
    names = integrator.flag_names(mechanisms.mod_files())
    assert {n.removeprefix("variable_step_") for n in names} == FLAGGED


def test_finitialize_sets_the_flag_from_cvode_active(ct09):
    from neuron import h

    unit = MuscleUnit(ct09)
    cv = h.CVode()
    was = cv.active()
    try:
        for on in (1, 0, 1):
            cv.active(on)
            h.finitialize()
            assert all(getattr(h, f"variable_step_{m}") == on for m in FLAGGED)
    finally:
        cv.active(was)
        h.finitialize()
        unit.destroy()


def test_a_hand_made_cvode_run_integrates_the_exact_right_hand_side(ct09):
    """CVODE run by hand (no Simulator) gives the twitch the Simulator's CVODE gives (the flag was set by the
    handler, not by the Simulator)."""
    from neuron import h

    from neuromuscle import simulate
    from neuromuscle.sim.simulator import Simulator, _registered_states

    ref = simulate(ct09, [20.0], -8.0, 150.0, method="cvode", record=["force.F"], record_dt_ms=1.0)["force.F"]
    unit = MuscleUnit(ct09)
    unit.length.xm = -8.0
    nc = unit.connect_from(None)[0]
    t = h.Vector(np.arange(0.0, 151.0, 1.0))
    f = h.Vector()
    f.record(unit.force._ref_F, t)
    saved = Simulator.snapshot()
    cv = h.CVode()
    try:
        cv.active(1)
        cv.atol(1e-3)
        cv.rtol(1e-7)
        for name, scale in _registered_states():  # as the Simulator does: each state's error on its own scale
            cv.atolscale(name, scale)
        h.finitialize()
        nc.event(20.0)
        h.continuerun(150.0)
    finally:
        Simulator._restore(saved)
        unit.destroy()
    got = np.array(f)
    np.testing.assert_array_equal(got, ref[:got.size])
    assert ref.max() > 1.0
