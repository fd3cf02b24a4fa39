"""Experimental protocols of the seed: stimulus trains (spike times, ms) and length inputs (LengthTrace, mm).

Stimulus trains are sorted float64 arrays of spike times in ms.  Length protocols return
:class:`neuromuscle.length.LengthTrace` objects sampled from 0 ms to (at least) the requested duration, with
Xm in mm relative to the physiological maximum and velocity in mm/s (positive = lengthening).

Random protocols take an explicit integer ``seed`` (fed to ``numpy.random.default_rng``): the same seed gives
the same protocol, and the caller records it.
"""

from __future__ import annotations

import math
from numbers import Integral

import numpy as np
from scipy import signal

from .validate import finite_number, positive_number
from .errors import InputError
from .length import LengthTrace

#: Shortest inter-pulse interval (ms) of the random-interval trains.
MIN_INTERVAL_MS = 10.0


# ---------------------------------------------------------------------------------------------- validation



def _nonnegative(name: str, value: object) -> float:
    x = finite_number(name, value)
    if x < 0.0:
        raise InputError(f"{name} must be >= 0, got {x}")
    return x


def _seed(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, Integral) or value < 0:
        raise InputError(f"seed must be a non-negative integer, got {value!r}")
    return int(value)


# ------------------------------------------------------------------------------------------ stimulus trains

def twitch(at_ms: float = 500.0) -> np.ndarray:
    """A single spike at ``at_ms`` (ms); the default leaves the model 500 ms to settle."""
    return np.array([_nonnegative("at_ms", at_ms)], dtype=np.float64)


def constant_rate(rate_hz: float, duration_ms: float, start_ms: float = 500.0) -> np.ndarray:
    """Spikes (ms) at ``start_ms + k * 1000 / rate_hz`` for every k >= 0 with time < start_ms + duration_ms."""
    rate = positive_number("rate_hz", rate_hz)
    duration = positive_number("duration_ms", duration_ms)
    start = _nonnegative("start_ms", start_ms)
    n_periods = duration * rate / 1000.0
    count = max(1, math.ceil(n_periods - 1e-9 * max(1.0, n_periods)))  # k < n_periods, rounding-safe
    return start + np.arange(count, dtype=np.float64) * (1000.0 / rate)


def random_interval(mean_interval_ms: float, duration_ms: float, seed: int,
                    start_ms: float = 500.0) -> np.ndarray:
    """Spikes (ms) from ``start_ms`` with inter-pulse intervals uniform on [10 ms, 2 * mean_interval_ms].

    Follows the seed's wording literally, so the intervals average ``mean_interval_ms + 5`` ms.  Spikes stop
    before ``start_ms + duration_ms``.  The k-th interval depends only on ``seed`` (not on the duration).
    """
    mean = finite_number("mean_interval_ms", mean_interval_ms)
    if mean <= MIN_INTERVAL_MS:
        raise InputError(f"mean_interval_ms must be > {MIN_INTERVAL_MS} ms (the shortest interval), got {mean}")
    duration = positive_number("duration_ms", duration_ms)
    start = _nonnegative("start_ms", start_ms)
    rng = np.random.default_rng(_seed(seed))
    intervals = rng.uniform(MIN_INTERVAL_MS, 2.0 * mean, size=math.ceil(duration / MIN_INTERVAL_MS) + 1)
    times = start + np.concatenate(([0.0], np.cumsum(intervals)))
    return times[times < start + duration].astype(np.float64)


# --------------------------------------------------------------------------------------- length protocols

def _grid_with_knots(duration_ms: float, sample_ms: float, knots: list[float]) -> np.ndarray:
    """Times (ms) every ``sample_ms`` from 0 to ``duration_ms``, plus the knots, without near-duplicates."""
    tol = 1e-6 * sample_ms
    grid = np.arange(math.floor(duration_ms / sample_ms + 1e-9) + 1) * sample_ms
    exact = np.array(sorted(set([0.0, duration_ms, *knots])))
    near_knot = np.min(np.abs(grid[:, None] - exact[None, :]), axis=1) < tol
    return np.union1d(grid[~near_knot & (grid < duration_ms)], exact)


def _piecewise_linear(name: str, duration_ms: float, sample_ms: float,
                      knots_ms: list[float], knots_mm: list[float]) -> LengthTrace:
    t = _grid_with_knots(duration_ms, sample_ms, knots_ms)
    return LengthTrace(t, np.interp(t, knots_ms, knots_mm), name=name)


def isometric(xm_mm: float, duration_ms: float) -> LengthTrace:
    """Length held at ``xm_mm`` (mm) from 0 to ``duration_ms`` (ms)."""
    return LengthTrace.isometric(finite_number("xm_mm", xm_mm), positive_number("duration_ms", duration_ms))


def step_shortening(xm_mm: float, step_mm: float, at_ms: float, duration_ms: float,
                    ramp_ms: float = 1.0, sample_ms: float = 0.1) -> LengthTrace:
    """Series-elastic stiffness test: hold ``xm_mm`` (mm), shorten by ``step_mm`` (mm, > 0) linearly over
    ``ramp_ms`` (ms) from ``at_ms`` (ms), hold to ``duration_ms`` (ms); sampled every ``sample_ms`` (ms)."""
    x0 = finite_number("xm_mm", xm_mm)
    step = positive_number("step_mm", step_mm)
    at = _nonnegative("at_ms", at_ms)
    duration = positive_number("duration_ms", duration_ms)
    ramp = positive_number("ramp_ms", ramp_ms)
    dt = positive_number("sample_ms", sample_ms)
    if at + ramp > duration:
        raise InputError(f"at_ms + ramp_ms ({at + ramp} ms) must not exceed duration_ms ({duration} ms)")
    return _piecewise_linear(f"step shortening {step} mm at {at} ms", duration, dt,
                             [0.0, at, at + ramp, duration], [x0, x0, x0 - step, x0 - step])


def isokinetic_ramp(x_start_mm: float, x_end_mm: float, velocity_mm_s: float, start_ms: float,
                    duration_ms: float, sample_ms: float = 0.1) -> LengthTrace:
    """Isometric-isokinetic-isometric: hold ``x_start_mm`` (mm) until ``start_ms`` (ms), move toward
    ``x_end_mm`` (mm) at speed |``velocity_mm_s``| (mm/s), then hold ``x_end_mm`` until ``duration_ms`` (ms).

    The sign of ``velocity_mm_s`` is ignored: the direction is from x_start to x_end.
    """
    x0 = finite_number("x_start_mm", x_start_mm)
    x1 = finite_number("x_end_mm", x_end_mm)
    speed = abs(finite_number("velocity_mm_s", velocity_mm_s))
    if speed == 0.0:
        raise InputError("velocity_mm_s must be non-zero")
    if x1 == x0:
        raise InputError(f"x_end_mm must differ from x_start_mm ({x0} mm); use isometric() for a hold")
    start = _nonnegative("start_ms", start_ms)
    duration = positive_number("duration_ms", duration_ms)
    dt = positive_number("sample_ms", sample_ms)
    stop = start + abs(x1 - x0) / speed * 1000.0
    if stop > duration:
        raise InputError(f"duration_ms ({duration} ms) ends before the ramp does ({stop} ms): "
                         "lengthen it or raise velocity_mm_s")
    return _piecewise_linear(f"ramp {x0} -> {x1} mm at {speed} mm/s", duration, dt,
                             [0.0, start, stop, duration], [x0, x0, x1, x1])


def _lowpass_noise(n_samples: int, seed: int, band_hz: float, sample_rate_hz: float,
                   numtaps: int) -> np.ndarray:
    """Uniform white noise low-pass filtered by a Blackman-window FIR; only fully-filtered samples are kept,
    so there is no start-up transient (the linear-phase delay is immaterial for white noise)."""
    taps = signal.firwin(numtaps, band_hz, window="blackman", fs=sample_rate_hz)
    noise = np.random.default_rng(seed).uniform(-1.0, 1.0, size=n_samples + numtaps - 1)
    return signal.fftconvolve(noise, taps, mode="valid")


def _taper(n_samples: int, taper_samples: int) -> np.ndarray:
    """1 in the middle, raised-cosine ramps from 0 over ``taper_samples`` at each end."""
    w = np.ones(n_samples)
    if taper_samples > 0:
        rise = 0.5 * (1.0 - np.cos(np.pi * np.arange(taper_samples) / taper_samples))
        w[:taper_samples] = rise
        w[n_samples - taper_samples:] = rise[::-1]
    return w


def _fit_between(deviation: np.ndarray, centre: float, low: float, high: float) -> np.ndarray:
    """centre + s * deviation, with s such that the larger excursion just reaches low or high.

    s is shrunk by 1e-12 (relative) so rounding can never carry a sample past a bound: nothing is clipped.
    """
    limits = []
    if deviation.max() > 0.0:
        limits.append((high - centre) / deviation.max())
    if deviation.min() < 0.0:
        limits.append((low - centre) / deviation.min())
    return centre + min(limits, default=0.0) * (1.0 - 1e-12) * deviation


def _default_numtaps(band_hz: float, sample_rate_hz: float) -> int:
    """Odd tap count giving a Blackman transition band about ``band_hz`` wide (width ~ 5.5 fs / numtaps)."""
    return 2 * math.ceil(2.75 * sample_rate_hz / band_hz) + 1


def random_length(duration_ms: float, seed: int, centre_mm: float = -8.0, low_mm: float = -16.0,
                  high_mm: float = 0.0, band_hz: float = 5.0, sample_rate_hz: float = 10000.0,
                  numtaps: int | None = None, taper_ms: float | None = None) -> LengthTrace:
    """Band-limited random length (mm) for ``duration_ms`` (ms), sampled at ``sample_rate_hz`` (Hz).

    Uniform white noise at ``sample_rate_hz`` is low-pass filtered by an FIR (``scipy.signal.firwin``, Blackman
    window, cutoff ``band_hz`` in Hz, ``numtaps`` taps; default: transition band about ``band_hz`` wide).
    Raised-cosine tapers of ``taper_ms`` (ms; default one period of ``band_hz``) make the trace start and end
    at ``centre_mm`` with zero velocity.  The excursion is then shifted to average exactly ``centre_mm`` and
    scaled so the larger excursion just reaches ``low_mm`` or ``high_mm``; nothing is clipped.
    """
    duration = positive_number("duration_ms", duration_ms)
    rng_seed = _seed(seed)
    centre, low, high = (finite_number(n, v) for n, v in
                         (("centre_mm", centre_mm), ("low_mm", low_mm), ("high_mm", high_mm)))
    if not low < centre < high:
        raise InputError(f"need low_mm < centre_mm < high_mm, got {low}, {centre}, {high}")
    fs = positive_number("sample_rate_hz", sample_rate_hz)
    band = positive_number("band_hz", band_hz)
    if band >= fs / 2.0:
        raise InputError(f"band_hz ({band} Hz) must be below half of sample_rate_hz ({fs / 2.0} Hz)")
    taps = _default_numtaps(band, fs) if numtaps is None else numtaps
    if isinstance(taps, bool) or not isinstance(taps, Integral) or taps < 3:
        raise InputError(f"numtaps must be an integer >= 3, got {numtaps!r}")
    taper = 1000.0 / band if taper_ms is None else _nonnegative("taper_ms", taper_ms)
    if 2.0 * taper > duration:
        raise InputError(f"taper_ms ({taper} ms) must be at most half of duration_ms ({duration} ms)")

    dt_ms = 1000.0 / fs
    n = math.ceil(duration / dt_ms - 1e-9) + 1
    if n < 3:
        raise InputError(f"duration_ms ({duration} ms) must span at least two samples at {fs} Hz")
    y = _lowpass_noise(n, rng_seed, band, fs, int(taps))
    w = _taper(n, round(taper / dt_ms))
    deviation = w * (y - np.mean(w * y) / np.mean(w))  # zero mean, zero at the tapered ends
    xm = _fit_between(deviation, centre, low, high)
    return LengthTrace(np.arange(n) * dt_ms, xm, name=f"random length seed {rng_seed}")
