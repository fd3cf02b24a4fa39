"""The afferent mechanisms (SpindleIa, SpindleII, TendonOrganIb) fire at the rates of their published equations,
evaluated here in Python and checked at points worked out by hand from the published coefficients (Prochazka &
Gorassini 1998 for Ia; Moraud et al. 2016 after Prochazka 1999 for II; Lin & Crago 2002 for Ib): each rate rises
with what its receptor reads (stretch velocity, stretch, force), a shortening spindle slows, the rate never goes
below 0, and the tendon organ's rate after a step of force follows Lin & Crago's transfer function, integrated
here by SciPy."""

import numpy as np
import pytest

from neuromuscle.model.mechanisms import load_mechanisms

DURATION_MS = 2000.0


def _ia(v, d, fus=0.0):
    """Prochazka & Gorassini 1998, Ia: v in mm/s, d in mm; fusimotor term of Moraud et al. 2016, fus in %."""
    return max(0.0, 4.3 * np.sign(v) * abs(v) ** 0.6 + 2.0 * d + 0.5 * fus + 82.0)


def _ii(d, fus=0.0):
    """Moraud et al. 2016 after Prochazka 1999, II: 80 + 13.5 d + 20 EMG (d in mm, EMG 0..1; fus in %)."""
    return max(0.0, 13.5 * d + 0.2 * fus + 80.0)


def _ib(force_N, fscale=1.0):
    """Lin & Crago 2002, the steady rate: 60 ln(Fm/4 N + 1), Fm = fscale F (N)."""
    return 60.0 * np.log(fscale * max(force_N, 0.0) / 4.0 + 1.0)


def _rate(kind, xm=-8.0, vm=0.0, force_N=0.0, fscale=1.0, fus=0.0):
    """The mechanism's spike count over DURATION_MS as a rate (Hz), the inputs held constant."""
    load_mechanisms()
    from neuron import h

    h.load_file("stdrun.hoc")
    sec = h.Section(name="afferent_test")
    length = h.MuscleLength(sec(0.5))
    length.xm, length.vm = xm, vm
    play = h.SynthPlay(sec(0.5))
    play.force_offset = force_N
    receptor = getattr(h, kind)(sec(0.5))
    if kind == "TendonOrganIb":
        h.setpointer(play._ref_force_offset, "F", receptor)
        receptor.fscale = fscale
    else:
        receptor.xref, receptor.fus = -8.0, fus
        h.setpointer(length._ref_xm, "xm", receptor)
        if kind == "SpindleIa":
            h.setpointer(length._ref_vm, "vm", receptor)
    spikes = h.Vector()
    nc = h.NetCon(receptor, None)
    nc.record(spikes)
    h.CVode().active(0)
    h.dt = 0.025
    pc = h.ParallelContext()
    pc.set_maxstep(10)
    h.finitialize(-65.0)
    pc.psolve(DURATION_MS)  # the fixed step in C, without hoc's loop per step
    return spikes.size() * 1000.0 / DURATION_MS, float(receptor.rate)


# (mechanism, stretch d (mm), velocity v (mm/s), fusimotor drive (%), rate (/s)) from the published coefficients by
# hand: Ia 4.3 sgn(v)|v|^0.6 + 2 d + 82 (10^0.6 = 3.98107, 100^0.6 = 15.84893, 30^0.6 = 7.69610); II 13.5 d + 80,
# + 20 at maximal activation
PUBLISHED_POINTS = [
    ("SpindleIa", 0.0, 0.0, 0.0, 82.0),
    ("SpindleIa", 0.0, 10.0, 0.0, 99.11860),
    ("SpindleIa", 5.0, 100.0, 0.0, 160.15040),
    ("SpindleIa", 6.0, 30.0, 0.0, 127.09339),
    ("SpindleIa", 0.0, -10.0, 0.0, 64.88140),
    ("SpindleIa", 0.0, 0.0, 100.0, 132.0),
    ("SpindleII", 0.0, 0.0, 0.0, 80.0),
    ("SpindleII", 6.0, 30.0, 0.0, 161.0),
    ("SpindleII", 4.0, 0.0, 100.0, 154.0),
    ("SpindleII", -2.0, 0.0, 0.0, 53.0),
]


@pytest.mark.parametrize("kind, d, v, fus, published", PUBLISHED_POINTS)
def test_the_rate_is_the_published_equation_at_worked_points(kind, d, v, fus, published):
    rate, held = _rate(kind, xm=-8.0 + d, vm=v, fus=fus)
    assert held == pytest.approx(published, abs=1e-4)
    assert rate == pytest.approx(published, abs=1.0 / (DURATION_MS / 1000.0))


@pytest.mark.parametrize("v", [0.0, 5.0, 20.0, 80.0, -10.0])
@pytest.mark.parametrize("d", [0.0, 4.0])
def test_ia_rate_is_the_equation(v, d):
    rate, held = _rate("SpindleIa", xm=-8.0 + d, vm=v)
    assert held == pytest.approx(_ia(v, d), rel=1e-12)
    assert rate == pytest.approx(_ia(v, d), abs=1.0 / (DURATION_MS / 1000.0))  # one spike over the run


def test_ia_rate_rises_with_velocity_and_stretch_and_fusimotor_drive():
    by_v = [_rate("SpindleIa", vm=v)[0] for v in (0.0, 10.0, 40.0, 100.0)]
    by_d = [_rate("SpindleIa", xm=-8.0 + d)[0] for d in (0.0, 5.0, 10.0)]
    assert np.all(np.diff(by_v) > 5.0) and np.all(np.diff(by_d) > 5.0)
    assert _rate("SpindleIa", fus=100.0)[0] > by_v[0] + 4.0


@pytest.mark.parametrize("d", [-2.0, 0.0, 3.0, 8.0])
def test_ii_rate_is_the_equation_and_ignores_velocity(d):
    rate, held = _rate("SpindleII", xm=-8.0 + d, vm=50.0)
    assert held == pytest.approx(_ii(d), rel=1e-12)
    assert rate == pytest.approx(_ii(d), abs=0.5)


# (force F (N), fscale, rate (/s)) by hand from Lin & Crago's 60 ln(Fm/4 + 1): ln 2 = 0.693147, ln 4 = 1.386294,
# ln 6.75 = 1.909543
IB_POINTS = [(0.0, 1.0, 0.0), (4.0, 1.0, 41.58883), (2.0, 2.0, 41.58883), (12.0, 1.0, 83.17766),
             (23.0, 1.0, 114.57256), (-3.0, 1.0, 0.0)]


@pytest.mark.parametrize("force_N, fscale, published", IB_POINTS)
def test_ib_steady_rate_is_the_published_equation(force_N, fscale, published):
    rate, held = _rate("TendonOrganIb", force_N=force_N, fscale=fscale)
    assert held == pytest.approx(published, abs=1e-4)
    assert held == pytest.approx(_ib(force_N, fscale), rel=1e-12)
    assert rate == pytest.approx(published, abs=1.0 / (DURATION_MS / 1000.0))


def test_ib_rate_after_a_step_of_force_follows_the_transfer_function():
    """A step of force from 2 to 12 N at 200 ms: the rate jumps to 1.7 times the step of the log term and relaxes
    over seconds, as (1.7 s^2 + 2.58 s + 0.4)/(s^2 + 2.2 s + 0.4) integrated by SciPy gives it."""
    from scipy import signal

    load_mechanisms()
    from neuron import h

    h.load_file("stdrun.hoc")
    sec = h.Section(name="ib_step")
    play = h.SynthPlay(sec(0.5))
    play.force_offset = 2.0
    receptor = h.TendonOrganIb(sec(0.5))
    h.setpointer(play._ref_force_offset, "F", receptor)
    t, rate = h.Vector(), h.Vector()
    t.record(h._ref_t, 1.0)
    rate.record(receptor._ref_rate, 1.0)
    h.CVode().active(0)
    h.dt = 0.025
    h.finitialize(-65.0)
    h.continuerun(200.0)
    play.force_offset = 12.0
    h.continuerun(6000.0)
    t_ms, simulated = np.array(t), np.array(rate)
    x = np.where(t_ms < 200.0, _ib(2.0), _ib(12.0))
    system = signal.lti([1.7, 2.58, 0.4], [1.0, 2.2, 0.4])
    _, expected, _ = signal.lsim(system, x - x[0], t_ms / 1000.0)
    expected = expected + x[0]
    assert simulated[t_ms < 199.0] == pytest.approx(_ib(2.0), abs=1e-6)   # steady from INITIAL
    jump = _ib(2.0) + 1.7 * (_ib(12.0) - _ib(2.0))
    assert simulated[(t_ms > 200.5) & (t_ms < 202.0)].max() == pytest.approx(jump, rel=2e-3)
    after = t_ms > 201.0
    assert np.max(np.abs(simulated[after] - expected[after])) < 1e-3 * jump
    assert _ib(12.0) < simulated[-1] < 1.05 * _ib(12.0)   # still settling from above 5.8 s on (the 5 s pole)


def test_rates_stay_at_or_above_zero():
    assert _rate("SpindleII", xm=-8.0 - 10.0)[0] == 0.0          # 13.5 * -10 + 80 < 0
    assert _rate("SpindleIa", vm=-2000.0)[0] == 0.0
