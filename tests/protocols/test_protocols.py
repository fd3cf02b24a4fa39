"""Protocols of the seed: stimulus trains (ms) and length inputs (LengthTrace, mm)."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.protocols import LengthTrace
from neuromuscle.protocols import (constant_rate, isokinetic_ramp, isometric, random_interval, random_length,
                                   step_shortening, twitch)


# ------------------------------------------------------------------------------------------ stimulus trains

def test_twitch_is_one_spike_after_settling():
    spikes = twitch()
    assert spikes.dtype == np.float64
    np.testing.assert_array_equal(spikes, [500.0])
    np.testing.assert_array_equal(twitch(at_ms=10.0), [10.0])


@pytest.mark.parametrize("rate_hz, count", [(10.0, 10), (20.0, 20), (40.0, 40), (100.0, 100), (30.0, 30)])
def test_constant_rate_counts_and_spacing(rate_hz, count):
    spikes = constant_rate(rate_hz, 1000.0)
    assert spikes.dtype == np.float64
    assert spikes.size == count
    assert spikes[0] == 500.0
    assert spikes[-1] < 1500.0
    np.testing.assert_allclose(np.diff(spikes), 1000.0 / rate_hz)


def test_constant_rate_excludes_the_end_of_the_window():
    np.testing.assert_allclose(constant_rate(1000.0 / 3.0, 10.0, start_ms=0.0), [0.0, 3.0, 6.0, 9.0])
    np.testing.assert_allclose(constant_rate(100.0, 30.0, start_ms=0.0), [0.0, 10.0, 20.0])


def test_random_interval_is_reproducible_and_seed_dependent():
    a = random_interval(50.0, 5000.0, seed=7)
    b = random_interval(50.0, 5000.0, seed=7)
    c = random_interval(50.0, 5000.0, seed=8)
    np.testing.assert_array_equal(a, b)
    assert a.size != c.size or not np.array_equal(a, c)


@pytest.mark.parametrize("mean_ms", [100.0, 50.0, 33.0])
def test_random_interval_bounds(mean_ms):
    spikes = random_interval(mean_ms, 20000.0, seed=3, start_ms=200.0)
    isi = np.diff(spikes)
    assert spikes.dtype == np.float64
    assert spikes[0] == 200.0
    assert spikes[-1] < 20200.0
    assert np.all(isi >= 10.0) and np.all(isi <= 2.0 * mean_ms)
    # uniform on [10, 2 mean]: mean + 5 ms on average, and the whole range is used
    assert abs(isi.mean() - (mean_ms + 5.0)) < 0.05 * mean_ms
    assert isi.min() < 10.0 + 0.05 * mean_ms and isi.max() > 1.95 * mean_ms
    assert spikes[-1] + 2.0 * mean_ms >= 20200.0  # the train fills the window


def test_random_interval_prefix_does_not_depend_on_duration():
    short = random_interval(50.0, 1000.0, seed=11)
    long = random_interval(50.0, 4000.0, seed=11)
    np.testing.assert_array_equal(long[:short.size], short)


@pytest.mark.parametrize("call, culprit", [
    (lambda: twitch(at_ms=float("nan")), "at_ms"),
    (lambda: twitch(at_ms=-1.0), "at_ms"),
    (lambda: constant_rate(0.0, 1000.0), "rate_hz"),
    (lambda: constant_rate(-5.0, 1000.0), "rate_hz"),
    (lambda: constant_rate(10.0, -1.0), "duration_ms"),
    (lambda: constant_rate(10.0, float("inf")), "duration_ms"),
    (lambda: constant_rate(10.0, 100.0, start_ms=-1.0), "start_ms"),
    (lambda: random_interval(10.0, 1000.0, seed=1), "mean_interval_ms"),
    (lambda: random_interval(5.0, 1000.0, seed=1), "mean_interval_ms"),
    (lambda: random_interval(50.0, 0.0, seed=1), "duration_ms"),
    (lambda: random_interval(50.0, 1000.0, seed=1.5), "seed"),
    (lambda: random_interval(50.0, 1000.0, seed=-3), "seed"),
    (lambda: random_interval(50.0, 1000.0, seed=None), "seed"),
])
def test_stimulus_bad_inputs_name_the_culprit(call, culprit):
    with pytest.raises(InputError, match=culprit):
        call()


# --------------------------------------------------------------------------------------- length protocols

def test_isometric():
    trace = isometric(-16.0, 1500.0)
    assert isinstance(trace, LengthTrace)
    assert trace.is_isometric and trace.covers(1500.0)
    np.testing.assert_array_equal(trace.xm_mm, -16.0)
    with pytest.raises(InputError, match="duration_ms"):
        isometric(-8.0, -1.0)
    with pytest.raises(InputError, match="xm_mm"):
        isometric(float("nan"), 100.0)


def test_step_shortening_amplitude_and_timing():
    trace = step_shortening(-8.0, 0.5, at_ms=100.0, duration_ms=300.0, ramp_ms=1.0, sample_ms=0.1)
    assert trace.covers(300.0) and trace.t_ms[0] == 0.0
    before = trace.t_ms <= 100.0
    after = trace.t_ms >= 101.0
    np.testing.assert_array_equal(trace.xm_mm[before], -8.0)
    np.testing.assert_allclose(trace.xm_mm[after], -8.5, atol=1e-12)
    inside = (trace.t_ms > 100.0 + 1e-9) & (trace.t_ms < 101.0 - 1e-9)
    assert inside.sum() >= 8
    np.testing.assert_allclose(trace.velocity_mm_s[inside], -500.0)  # 0.5 mm in 1 ms
    assert trace.onset_ms == pytest.approx(100.0)
    np.testing.assert_allclose(np.diff(trace.t_ms).max(), 0.1, rtol=1e-9)


def test_step_shortening_off_grid_times_are_exact():
    trace = step_shortening(-4.0, 2.0, at_ms=50.03, duration_ms=100.05, ramp_ms=0.55, sample_ms=0.1)
    assert trace.t_ms[-1] == 100.05
    assert trace.at(np.array([50.03]))[0] == -4.0
    assert trace.at(np.array([50.58]))[0] == pytest.approx(-6.0, abs=1e-12)
    assert np.all(np.diff(trace.t_ms) > 1e-6)


@pytest.mark.parametrize("x0, x1, v", [(-16.0, 0.0, 80.0), (0.0, -16.0, 40.0), (-8.0, -4.0, -20.0)])
def test_isokinetic_ramp(x0, x1, v):
    start, duration = 200.0, 1000.0
    trace = isokinetic_ramp(x0, x1, v, start, duration)
    stop = start + abs(x1 - x0) / abs(v) * 1000.0
    t, x, vel = trace.t_ms, trace.xm_mm, trace.velocity_mm_s
    assert trace.covers(duration)
    np.testing.assert_array_equal(x[t <= start], x0)
    np.testing.assert_allclose(x[t >= stop], x1, atol=1e-12)
    moving = (t > start + 1e-9) & (t < stop - 1e-9)
    np.testing.assert_allclose(vel[moving], np.sign(x1 - x0) * abs(v), rtol=1e-9)
    np.testing.assert_allclose(vel[(t < start - 1e-9) | (t > stop + 1e-9)], 0.0, atol=1e-9)
    assert trace.at(np.array([0.5 * (start + stop)]))[0] == pytest.approx(0.5 * (x0 + x1))


@pytest.mark.parametrize("call, culprit", [
    (lambda: step_shortening(-8.0, 0.0, 100.0, 200.0), "step_mm"),
    (lambda: step_shortening(-8.0, 0.5, 100.0, 100.5), "duration_ms"),
    (lambda: step_shortening(-8.0, 0.5, -1.0, 200.0), "at_ms"),
    (lambda: step_shortening(-8.0, 0.5, 100.0, 200.0, ramp_ms=0.0), "ramp_ms"),
    (lambda: step_shortening(-8.0, 0.5, 100.0, 200.0, sample_ms=float("nan")), "sample_ms"),
    (lambda: isokinetic_ramp(-16.0, 0.0, 0.0, 100.0, 1000.0), "velocity_mm_s"),
    (lambda: isokinetic_ramp(-8.0, -8.0, 10.0, 100.0, 1000.0), "x_end_mm"),
    (lambda: isokinetic_ramp(-16.0, 0.0, 10.0, 100.0, 1000.0), "duration_ms"),
    (lambda: isokinetic_ramp(-16.0, float("inf"), 10.0, 100.0, 1000.0), "x_end_mm"),
    (lambda: isokinetic_ramp(-16.0, 0.0, 80.0, -5.0, 1000.0), "start_ms"),
])
def test_length_bad_inputs_name_the_culprit(call, culprit):
    with pytest.raises(InputError, match=culprit):
        call()


# ------------------------------------------------------------------------------------------ random length

@pytest.fixture(scope="module")
def random_trace():
    return random_length(10000.0, seed=2015)


def test_random_length_is_reproducible_and_seed_dependent(random_trace):
    again = random_length(10000.0, seed=2015)
    other = random_length(10000.0, seed=2016)
    np.testing.assert_array_equal(random_trace.xm_mm, again.xm_mm)
    assert np.max(np.abs(random_trace.xm_mm - other.xm_mm)) > 1.0


def test_random_length_time_base(random_trace):
    t = random_trace.t_ms
    assert t[0] == 0.0 and t[-1] == pytest.approx(10000.0)
    np.testing.assert_allclose(np.diff(t), 0.1)  # 10 kHz


def test_random_length_centred_bounded_and_reaching(random_trace):
    x = random_trace.xm_mm
    assert np.mean(x) == pytest.approx(-8.0, abs=1e-9)
    assert x.min() >= -16.0 and x.max() <= 0.0
    # the larger excursion just fits, the other reaches well out
    assert min(x.min() + 16.0, 0.0 - x.max()) < 1e-9
    assert x.min() < -14.0 and x.max() > -2.0


def test_random_length_is_band_limited(random_trace):
    x = random_trace.xm_mm - np.mean(random_trace.xm_mm)
    power = np.abs(np.fft.rfft(x)) ** 2
    freq = np.fft.rfftfreq(x.size, d=1e-4)  # s
    below = power[(freq > 0) & (freq <= 5.0)].sum()
    above = power[freq >= 10.0].sum()
    assert above < 1e-5 * below


def test_random_length_starts_and_ends_smoothly(random_trace):
    x, v = random_trace.xm_mm, random_trace.velocity_mm_s
    assert x[0] == pytest.approx(-8.0, abs=1e-12) and x[-1] == pytest.approx(-8.0, abs=1e-12)
    assert abs(v[0]) < 1.0 and abs(v[-1]) < 1.0
    assert np.max(np.abs(v)) > 20.0  # it does move in between


def test_random_length_asymmetric_bounds():
    trace = random_length(4000.0, seed=5, centre_mm=-4.0, low_mm=-16.0, high_mm=0.0, band_hz=3.0)
    x = trace.xm_mm
    assert np.mean(x) == pytest.approx(-4.0, abs=1e-9)
    assert x.min() >= -16.0 and x.max() <= 0.0
    assert x.max() > -1e-9  # the short side is the binding one


@pytest.mark.parametrize("kwargs, culprit", [
    (dict(duration_ms=-5.0, seed=1), "duration_ms"),
    (dict(duration_ms=1000.0, seed=2.0), "seed"),
    (dict(duration_ms=1000.0, seed=1, centre_mm=-20.0), "centre_mm"),
    (dict(duration_ms=1000.0, seed=1, low_mm=0.0, high_mm=-16.0), "low_mm"),
    (dict(duration_ms=1000.0, seed=1, band_hz=0.0), "band_hz"),
    (dict(duration_ms=1000.0, seed=1, band_hz=6000.0), "band_hz"),
    (dict(duration_ms=1000.0, seed=1, sample_rate_hz=float("nan")), "sample_rate_hz"),
    (dict(duration_ms=1000.0, seed=1, numtaps=2), "numtaps"),
    (dict(duration_ms=1000.0, seed=1, numtaps=101.5), "numtaps"),
    (dict(duration_ms=300.0, seed=1), "taper_ms"),
    (dict(duration_ms=1000.0, seed=1, taper_ms=-1.0), "taper_ms"),
])
def test_random_length_bad_inputs_name_the_culprit(kwargs, culprit):
    with pytest.raises(InputError, match=culprit):
        random_length(**kwargs)
