"""Summary measures of force traces: twitch peak, time to peak, half-relaxation, train plateaus, and the
NRMSE of a simulated trace against a measured one (eq 17)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..validate import finite_series


@dataclass(frozen=True)
class Twitch:
    """Twitch measures: peak force (N), time to peak after the stimulus (ms), half-relaxation time after the
    peak (ms, linearly interpolated crossing of half the peak)."""

    peak_N: float
    time_to_peak_ms: float
    half_relaxation_ms: float


def twitch_metrics(t_ms: np.ndarray, force_N: np.ndarray, stimulus_ms: float) -> Twitch:
    """Measure a twitch elicited at stimulus_ms (ms). The peak time is refined by a parabola through the
    three samples around the sampled maximum."""
    t = np.asarray(t_ms, dtype=float)
    f = np.asarray(force_N, dtype=float)
    after = t >= stimulus_ms
    if not np.any(after):
        raise InputError(f"no samples after the stimulus at {stimulus_ms} ms")
    i = int(np.flatnonzero(after)[0] + np.argmax(f[after]))
    tp, fp = t[i], f[i]
    if 0 < i < len(f) - 1:
        y0, y1, y2 = f[i - 1], f[i], f[i + 1]
        den = y0 - 2 * y1 + y2
        if den < 0:
            off = 0.5 * (y0 - y2) / den
            tp = t[i] + off * (t[i + 1] - t[i - 1]) / 2
            fp = y1 - 0.25 * (y0 - y2) * off
    below = np.flatnonzero(f[i:] < fp / 2)
    if below.size == 0:
        raise InputError("the force does not relax to half its peak within the trace")
    j = i + int(below[0])
    tj = t[j - 1] + (fp / 2 - f[j - 1]) * (t[j] - t[j - 1]) / (f[j] - f[j - 1])
    return Twitch(float(fp), float(tp - stimulus_ms), float(tj - tp))


def plateau(t_ms: np.ndarray, force_N: np.ndarray, start_ms: float, end_ms: float) -> tuple[float, float, float]:
    """Mean, minimum and maximum force (N) over [start_ms, end_ms) (ms)."""
    t = np.asarray(t_ms)
    sel = (t >= start_ms) & (t < end_ms)
    if not np.any(sel):
        raise InputError(f"no samples in the plateau window {start_ms}..{end_ms} ms")
    f = np.asarray(force_N)[sel]
    return float(f.mean()), float(f.min()), float(f.max())


def nrmse_percent(measured: Sequence[float], simulated: Sequence[float]) -> float:
    """Eq 17: 100 * RMS(measured - simulated) / (max(measured) - min(measured)), in % (any force unit)."""
    m = finite_series("measured", measured)
    s = finite_series("simulated", simulated)
    if m.shape != s.shape:
        raise InputError(f"simulated must match measured in shape, got {s.shape} and {m.shape}")
    if m.size == 0:
        raise InputError("measured is empty")
    span = float(m.max() - m.min())
    if span <= 0.0:
        raise InputError("measured has zero range (constant): NRMSE is undefined")
    return 100.0 * math.sqrt(float(np.mean((m - s) ** 2))) / span
