"""The fused channels (mn_soma + mn_pic) against the reference channels (mn_naf, mn_kdr, mn_can, mn_cadyn,
mn_kca + mn_cal): the same equations, so the same spikes, under the fixed step and under CVODE; their fixed-step
forms (mn_soma_fixed + mn_pic_fixed) against them under the fixed step, and refused under CVODE."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.motoneuron import Motoneuron, motoneuron_parameters

DT = 0.025


def _spikes(channels: str, size: float, *, table: bool = True, method: str = "fixed", dt_ms: float = DT,
            duration_ms: float = 1000.0, secondorder: int = 0, atol: float | None = None,
            pic_substeps: int = 1) -> np.ndarray:
    """Spike times (ms) of one cell under a current ramp 0 -> 3 rheobase with a step to 5 in the middle (the
    PIC turns on, the AHP calcium builds up)."""
    from neuron import h

    from neuromuscle.model.mechanisms import load_mechanisms
    from neuromuscle.sim import Simulator

    load_mechanisms()
    h.usetable_mn_soma = h.usetable_mn_pic = h.usetable_mn_soma_fixed = h.usetable_mn_pic_fixed = 1 if table else 0
    try:
        with Motoneuron(motoneuron_parameters(size), channels=channels, pic_substeps=pic_substeps) as mn:
            ic = h.IClamp(mn.soma(0.5))
            ic.delay, ic.dur = 0.0, 1e9
            tv = h.Vector([0.0, 400.0, 400.0, duration_ms])
            rheobase = 4.6 * 3.9 ** size    # nA, the cells' measured rheobase (tests/pool/test_motoneuron_physiology)
            av = h.Vector([0.0, 3.0 * rheobase, 5.0 * rheobase, 2.0 * rheobase])
            av.play(ic._ref_amp, tv, 1)
            out = h.Vector()
            nc = h.NetCon(mn.spike_source(), None, sec=mn.soma)
            nc.threshold = -10.0
            nc.record(out)
            tol = {} if atol is None else {"atol": atol}
            Simulator(method=method, dt_ms=dt_ms, v_init_mV=-70.0, secondorder=secondorder, **tol).run(duration_ms)
            spikes = np.array(out)
            av.play_remove()
            del nc, ic
    finally:
        h.usetable_mn_soma = h.usetable_mn_pic = h.usetable_mn_soma_fixed = h.usetable_mn_pic_fixed = 1
    return spikes


def _max_shift(a: np.ndarray, b: np.ndarray) -> float:
    assert a.size == b.size, f"{a.size} vs {b.size} spikes"
    return float(np.abs(a - b).max()) if a.size else 0.0


@pytest.mark.parametrize("size", [0.0, 1.0])
def test_fused_exact_is_the_reference_to_rounding(size):
    ref = _spikes("separate", size)
    assert ref.size > 20
    # cnexp's update and ours differ only in the order of the floating-point operations
    assert _max_shift(_spikes("fused", size, table=False), ref) <= DT + 1e-9


def _drift(a: np.ndarray, b: np.ndarray) -> float:
    """Largest shift (ms) of the k-th spike over the spikes both trains have."""
    n = min(a.size, b.size)
    return float(np.abs(a[:n] - b[:n]).max())


@pytest.mark.parametrize("size", [0.0, 1.0])
def test_the_tables_err_less_than_the_fixed_step(size):
    ref = _spikes("separate", size)
    tabled = _spikes("fused", size)
    halved = _spikes("separate", size, dt_ms=DT / 2)
    # the tables (0.025 mV) move a spike by at most two steps in a second of firing (measured: one step);
    # halving dt moves them far more (tens of ms by the end of the run, and a spike more or less)
    assert _max_shift(tabled, ref) <= 2 * DT + 1e-9
    assert _drift(halved, ref) > 4 * DT


@pytest.mark.parametrize("size", [0.0, 1.0])
def test_fused_and_separate_agree_under_crank_nicolson(size):
    """Under secondorder 1 and 2 NEURON calls the fused channels' METHOD euler block with dt halved; they still
    advance their gates over the whole step, as cnexp does for the separate channels (before they counted the step,
    the fused cell fired at other times and rates)."""
    ref = _spikes("separate", size, secondorder=1)
    assert ref.size > 20
    assert _max_shift(_spikes("fused", size, table=False, secondorder=1), ref) <= DT + 1e-9
    assert _max_shift(_spikes("fused", size, secondorder=1), ref) <= 2 * DT + 1e-9
    # secondorder 2 also corrects the ionic currents to the half step: the separate channels' calcium current (an
    # ion) is corrected, the fused soma's (its own state) is not: 0.25 ms apart after a second of firing
    ref2 = _spikes("separate", size, secondorder=2)
    assert _max_shift(_spikes("fused", size, secondorder=2), ref2) <= 12 * DT


def test_crank_nicolson_converges_faster_than_backward_euler():
    """The discharge times converge at second order in dt under secondorder 2, at first order under 0: at dt 0.025
    ms Crank-Nicolson is much closer to a fine-step reference than backward Euler."""
    ref = _spikes("fused", 1.0, dt_ms=DT / 8, secondorder=2)
    backward_euler = _drift(_spikes("fused", 1.0), ref)
    crank_nicolson = _drift(_spikes("fused", 1.0, secondorder=2), ref)
    # measured: 7.4 ms against 1.7 ms by the last of 67 spikes
    assert crank_nicolson < backward_euler / 3, (crank_nicolson, backward_euler)


def test_fused_and_separate_agree_under_cvode():
    """The integrators' error control sees different state sets (the ions' or the mechanism's own calcium) and
    sums the currents in another order, so the spikes differ by the error control's own size and come together
    as the tolerance tightens (measured: 0.17, 0.04 and 0.004 ms at atol 1e-3, 1e-4, 1e-5)."""
    shifts = []
    for atol in (1e-4, 1e-5):
        a = _spikes("separate", 0.5, method="cvode", duration_ms=600.0, atol=atol)
        b = _spikes("fused", 0.5, method="cvode", duration_ms=600.0, atol=atol)
        assert a.size > 10
        shifts.append(_max_shift(a, b))
    assert shifts[0] < 0.1 and shifts[1] < 0.02 and shifts[1] < shifts[0] / 3, shifts


@pytest.mark.parametrize("secondorder", [0, 2])
def test_the_pic_gate_every_few_steps_keeps_the_spikes(secondorder):
    """The PIC's gate (time constant 60 ms) advanced every 8 steps (0.2 ms) by one step of 8 dt moves no spike by
    more than a step in a second of firing under the ramp and step that turn the PIC on, under backward Euler and
    Crank-Nicolson (a gate left at rest would keep the PIC off, and the discharge far from this one)."""
    every = _spikes("fused", 0.3, secondorder=secondorder)
    sparse = _spikes("fused", 0.3, secondorder=secondorder, pic_substeps=8)
    assert every.size > 20
    assert _max_shift(sparse, every) <= DT + 1e-9
    with pytest.raises(InputError, match="pic_substeps"):
        Motoneuron(motoneuron_parameters(0.2), channels="separate", pic_substeps=2)
    with pytest.raises(InputError, match="pic_substeps"):
        Motoneuron(motoneuron_parameters(0.2), pic_substeps=0)


@pytest.mark.parametrize("size", [0.0, 1.0])
def test_the_fixed_step_forms_are_the_fused_channels(size):
    """Backward Euler: the same arithmetic, bit for bit (the PIC gate every step or every 8).  Crank-Nicolson:
    mn_soma advances m, h and n in two half steps with the factors tabulated for dt/2, mn_soma_fixed in one whole
    step with those for dt (the same exponential update, another table interpolation): no spike more than a step
    apart in a second of firing."""
    assert np.array_equal(_spikes("fused_fixed", size), _spikes("fused", size))
    assert np.array_equal(_spikes("fused_fixed", size, pic_substeps=8), _spikes("fused", size, pic_substeps=8))
    dt = 1 / 30
    a = _spikes("fused", size, secondorder=2, dt_ms=dt, pic_substeps=6)
    b = _spikes("fused_fixed", size, secondorder=2, dt_ms=dt, pic_substeps=6)
    assert a.size > 20
    assert _max_shift(b, a) <= dt + 1e-9


def test_the_fixed_step_forms_are_refused_under_cvode():
    with pytest.raises(InputError, match="mn_soma_fixed in 1 section.*fixed step only"):
        _spikes("fused_fixed", 0.0, method="cvode", duration_ms=10.0)


def test_unknown_channels_are_refused():
    with pytest.raises(InputError, match="channels must be one of"):
        Motoneuron(motoneuron_parameters(0.2), channels="hh")


@pytest.mark.parametrize("size", [0.0, 1.0])
def test_fused_and_separate_have_the_same_input_resistance(size):
    # NEURON's extended impedance linearises each mechanism's CVODE right-hand side and currents
    rin = {}
    for channels in ("separate", "fused", "fused_fixed"):
        with Motoneuron(motoneuron_parameters(size), channels=channels) as mn:
            rin[channels] = mn.input_resistance_MOhm()
    assert rin["fused"] == pytest.approx(rin["separate"], rel=1e-9)
    assert rin["fused_fixed"] == rin["fused"]
