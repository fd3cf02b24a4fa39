"""Length inputs: the LengthTrace Xm(t) (mm) NEURON plays into a MuscleLength, and the length protocols of
Kim et al. 2015.

Length protocols return LengthTrace objects sampled from 0 ms to (at least) the requested duration, with Xm in mm
relative to the physiological maximum and velocity in mm/s (positive = lengthening).  Random protocols take an
explicit integer ``seed``.
"""

from __future__ import annotations

import math
from numbers import Integral
from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from ..errors import InputError
from ..validate import finite_number, nonnegative_number, positive_number, seed_value

#: Speed (mm/s) above which the muscle counts as moving, for the movement clock of eqs 19-20.
MOVEMENT_SPEED_MM_S = 1.0


@dataclass(frozen=True)
class LengthTrace:
    """Muscle length Xm (mm, relative to the physiological maximum) sampled at times t (ms).

    ``velocity_mm_s`` is dXm/dt (mm/s, positive = lengthening); computed by finite differences when not given.
    ``onset_ms`` is the movement clock's zero for eqs 19-20: the first time |velocity| exceeds
    MOVEMENT_SPEED_MM_S, or None for an isometric trace (or set explicitly).
    """

    t_ms: np.ndarray
    xm_mm: np.ndarray
    velocity_mm_s: np.ndarray = field(default=None)  # type: ignore[assignment]
    onset_ms: float | None = field(default=None)
    name: str = "length"

    def __post_init__(self) -> None:
        t = np.asarray(self.t_ms, dtype=float)
        x = np.asarray(self.xm_mm, dtype=float)
        if t.ndim != 1 or x.ndim != 1 or t.size != x.size:
            raise InputError(f"{self.name}: time and length must be 1-D arrays of equal size "
                             f"(got {t.shape} and {x.shape})")
        if t.size < 2:
            raise InputError(f"{self.name}: needs at least two samples")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
            bad = int(np.flatnonzero(~(np.isfinite(t) & np.isfinite(x)))[0])
            raise InputError(f"{self.name}: non-finite time or length at sample {bad}")
        if np.any(np.diff(t) <= 0):
            bad = int(np.flatnonzero(np.diff(t) <= 0)[0]) + 1
            raise InputError(f"{self.name}: time must be strictly increasing (sample {bad})")
        if self.velocity_mm_s is None:
            v = np.gradient(x, t) * 1000.0
        else:
            v = np.asarray(self.velocity_mm_s, dtype=float)
            if v.shape != x.shape or not np.all(np.isfinite(v)):
                raise InputError(f"{self.name}: velocity must be finite and match the length samples")
        onset = self.onset_ms
        if onset is None:
            moving = np.flatnonzero(np.abs(v) > MOVEMENT_SPEED_MM_S)
            onset = float(t[moving[0]]) if moving.size else None
        object.__setattr__(self, "t_ms", t)
        object.__setattr__(self, "xm_mm", x)
        object.__setattr__(self, "velocity_mm_s", v)
        object.__setattr__(self, "onset_ms", onset)

    @classmethod
    def isometric(cls, xm_mm: float, duration_ms: float) -> LengthTrace:
        """A constant length xm_mm (mm) from 0 to duration_ms (ms)."""
        if not np.isfinite(xm_mm):
            raise InputError(f"isometric length {xm_mm} mm is not finite")
        return cls(np.array([0.0, float(duration_ms)]), np.array([float(xm_mm)] * 2),
                   np.zeros(2), None, f"isometric {xm_mm} mm")

    @property
    def is_isometric(self) -> bool:
        """True when the length never changes."""
        return bool(np.all(self.xm_mm == self.xm_mm[0]))

    def covers(self, duration_ms: float) -> bool:
        """True when the trace spans [0, duration_ms]."""
        return bool(self.t_ms[0] <= 0.0 and self.t_ms[-1] >= duration_ms)

    def at(self, t_ms: np.ndarray) -> np.ndarray:
        """Length (mm) linearly interpolated at times t_ms (ms)."""
        return np.interp(t_ms, self.t_ms, self.xm_mm)

    def velocity_at(self, t_ms: np.ndarray) -> np.ndarray:
        """Velocity (mm/s) linearly interpolated at times t_ms (ms)."""
        return np.interp(t_ms, self.t_ms, self.velocity_mm_s)


def as_length_trace(length: LengthTrace | float, duration_ms: float) -> LengthTrace:
    """A LengthTrace covering 0..duration_ms (ms) from a trace or a constant length (mm); InputError otherwise."""
    if isinstance(length, LengthTrace):
        trace = length
    elif isinstance(length, (int, float)) and not isinstance(length, bool):
        trace = LengthTrace.isometric(float(length), duration_ms)
    else:
        raise InputError(f"length must be a LengthTrace or a constant length in mm, got {type(length)}")
    if not trace.covers(duration_ms):
        raise InputError(f"length trace {trace.name!r} spans {trace.t_ms[0]}..{trace.t_ms[-1]} ms, shorter "
                         f"than the run 0..{duration_ms} ms")
    return trace


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
    at = nonnegative_number("at_ms", at_ms)
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
    start = nonnegative_number("start_ms", start_ms)
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
    rng_seed = seed_value(seed)
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
    taper = 1000.0 / band if taper_ms is None else nonnegative_number("taper_ms", taper_ms)
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
