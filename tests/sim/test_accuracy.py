"""NEURON mechanisms vs the independent SciPy integration, and vs the spec's reference values.

The accuracy contract: within 0.5 % of SciPy on twitch peak, time to peak, half-relaxation and train
plateaus at dt = 0.025 ms (fixed step and CVODE), within 1 % of the spec's reference values, dt convergence.
"""

import numpy as np
import pytest

from neuromuscle import kim_excitation, simulate
from neuromuscle.analysis.metrics import plateau, twitch_metrics
from neuromuscle.protocols import constant_rate, isokinetic_ramp, random_interval, random_length
from neuromuscle.reference import reference_simulate

pytestmark = pytest.mark.heavy(cost_s=65)

# the reference values of Kim et al. 2015 (docs/reference/kim2015.md), CT09 unless named:
# (set, length mm, stimulus ms, end ms) -> values
TWITCH_REFERENCE = {
    ("CT09", -8.0, 500.0): (3.57, 81.4, 41.2),
    ("CT09", -16.0, 500.0): (0.856, 61.0, 59.1),
    ("CT09", 0.0, 500.0): (5.03, 90.6, 38.8),
    ("CT09", -8.0, 10.0): (2.66, 81.0, 43.9),
    ("CT95", -5.0, 500.0): (9.19, 84.6, 48.3),
}
TRAIN_REFERENCE = {10: 0.544, 20: 0.894, 40: 0.963, 100: 0.989}


def _initial(stimulus_ms: float) -> str:
    # the spec's "twitch at t = 10 ms" is the unsettled twitch: from the published initial state of Kim et al. 2015
    return "published" if stimulus_ms < 100.0 else "rest"


def _rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b)


@pytest.fixture(scope="module", params=list(TWITCH_REFERENCE), ids=lambda k: f"{k[0]}@{k[1]}mm-stim{k[2]}")
def twitch_case(request, ct09, ct95):
    name, x, st = request.param
    p = ct09 if name == "CT09" else ct95
    end = st + 280.0
    ref = reference_simulate(p, np.array([st]), x, end, initial_state=_initial(st))
    return request.param, p, ref, twitch_metrics(ref.t_ms, ref.force_N, st)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_twitch_matches_scipy_within_half_percent(twitch_case, method):
    (name, x, st), p, ref, m_ref = twitch_case
    sim = simulate(p, [st], x, st + 280.0, method=method, dt_ms=0.025, record_dt_ms=0.025,
                   initial_state=_initial(st))
    m = twitch_metrics(sim.t_ms, sim.force_N, st)
    assert _rel(m.peak_N, m_ref.peak_N) < 0.005
    assert _rel(m.time_to_peak_ms, m_ref.time_to_peak_ms) < 0.005
    assert _rel(m.half_relaxation_ms, m_ref.half_relaxation_ms) < 0.005
    # the whole trace, not only its landmarks
    assert np.max(np.abs(np.interp(ref.t_ms, sim.t_ms, sim.force_N) - ref.force_N)) < 0.005 * m_ref.peak_N


def test_twitch_reproduces_spec_reference_values(twitch_case):
    (name, x, st), p, _, _ = twitch_case
    sim = simulate(p, [st], x, st + 280.0, dt_ms=0.025, record_dt_ms=0.025, initial_state=_initial(st))
    m = twitch_metrics(sim.t_ms, sim.force_N, st)
    peak, ttp, half = TWITCH_REFERENCE[(name, x, st)]
    assert _rel(m.peak_N, peak) < 0.01
    assert _rel(m.time_to_peak_ms, ttp) < 0.01
    assert _rel(m.half_relaxation_ms, half) < 0.01


@pytest.mark.parametrize("rate_hz", [10, 20, 40, 100])
def test_train_plateau_matches_scipy_and_spec(ct09, rate_hz):
    spikes = constant_rate(rate_hz, 1000.0, start_ms=500.0)
    ref = reference_simulate(ct09, spikes, -8.0, 1500.0, record_dt_ms=0.1)
    ref_mean, ref_lo, ref_hi = plateau(ref.t_ms, ref.force_N, 1300.0, 1500.0)
    for method in ("fixed", "cvode"):
        sim = simulate(ct09, spikes, -8.0, 1500.0, method=method, record_dt_ms=0.1)
        mean, lo, hi = plateau(sim.t_ms, sim.force_N, 1300.0, 1500.0)
        assert _rel(mean, ref_mean) < 0.005, method
        assert _rel(lo, ref_lo) < 0.005 and _rel(hi, ref_hi) < 0.005, method
    assert _rel(mean / ct09["P0"], TRAIN_REFERENCE[rate_hz]) < 0.01
    if rate_hz == 10:  # the spec's ripple 0.484-0.594 P0
        assert _rel(lo / ct09["P0"], 0.484) < 0.01 and _rel(hi / ct09["P0"], 0.594) < 0.01


def test_dt_convergence(ct09):
    ref = reference_simulate(ct09, np.array([500.0]), -8.0, 700.0)
    m_ref = twitch_metrics(ref.t_ms, ref.force_N, 500.0)
    errors = []
    for dt in (0.1, 0.05, 0.025, 0.0125):
        sim = simulate(ct09, [500.0], -8.0, 700.0, dt_ms=dt, record_dt_ms=dt)
        errors.append(_rel(twitch_metrics(sim.t_ms, sim.force_N, 500.0).peak_N, m_ref.peak_N))
    assert all(b < a for a, b in zip(errors, errors[1:])), errors
    # at least first order: halving dt at least halves the error (measured 2.9, 2.6, 2.8 since K6 reads Atil
    # extrapolated to the step's middle; 1.8-2.0 before), and 0.011 % at dt 0.025 ms (0.078 % before)
    assert all(a / b > 1.8 for a, b in zip(errors, errors[1:])), errors
    assert errors[2] < 0.0003


def test_random_train_during_lengthening_ramp_with_compensations(ct09):
    """Movement (eqs 18-20 on, movement clock from the ramp onset), random stimulation: NEURON (fixed and
    CVODE) vs SciPy over the whole trace."""
    spikes = random_interval(30.0, 1000.0, seed=3, start_ms=100.0)
    trace = isokinetic_ramp(-12.0, -4.0, 20.0, 400.0, 1200.0, sample_ms=1.0)
    ref = reference_simulate(ct09, spikes, trace, 1200.0, record_dt_ms=0.5, movement_compensation=True)
    scale = ref.force_N.max()
    for method in ("fixed", "cvode"):
        sim = simulate(ct09, spikes, trace, 1200.0, method=method, record_dt_ms=0.5,
                       excitation=kim_excitation(movement_compensation=True))
        err = np.interp(ref.t_ms, sim.t_ms, sim.force_N) - ref.force_N
        assert np.sqrt(np.mean(err**2)) < 0.005 * scale, method
        assert np.max(np.abs(err)) < 0.01 * scale, method
        assert sim.settings["movement_onset_ms"] == pytest.approx(400.0, abs=1.0)


def test_random_length_fixed_step_agrees_with_cvode(ct09):
    spikes = random_interval(50.0, 1500.0, seed=5, start_ms=100.0)
    trace = random_length(1700.0, seed=7)
    a = simulate(ct09, spikes, trace, 1700.0, record_dt_ms=0.5, excitation=kim_excitation(movement_compensation=True))
    b = simulate(ct09, spikes, trace, 1700.0, method="cvode", record_dt_ms=0.5,
                 excitation=kim_excitation(movement_compensation=True))
    n = min(a.t_ms.size, b.t_ms.size)
    err = a.force_N[:n] - b.force_N[:n]
    # random lengthening at low activation drives the CE towards the Mashima asymptote, where the force is
    # stiffest: there the fixed step lags CVODE by up to ~2 % of the peak for a few samples
    assert np.sqrt(np.mean(err**2)) < 0.005 * b.force_N.max()
    assert np.max(np.abs(err)) < 0.03 * b.force_N.max()
    assert np.ptp(a.length_mm) > 5.0  # the length really moved
