"""Stimulus trains of the protocols of Kim et al. 2015: sorted float64 arrays of spike times (ms).

Random trains take an explicit integer ``seed`` (fed to ``numpy.random.default_rng``): the same seed gives the
same train, and the caller records it.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..validate import finite_number, nonnegative_number, positive_number, seed_value

#: Shortest inter-pulse interval (ms) of the random-interval trains.
MIN_INTERVAL_MS = 10.0


# ------------------------------------------------------------------------------------------ stimulus trains

def twitch(at_ms: float = 500.0) -> np.ndarray:
    """A single spike at ``at_ms`` (ms); the default leaves the model 500 ms to settle."""
    return np.array([nonnegative_number("at_ms", at_ms)], dtype=np.float64)


def constant_rate(rate_hz: float, duration_ms: float, start_ms: float = 500.0) -> np.ndarray:
    """Spikes (ms) at ``start_ms + k * 1000 / rate_hz`` for every k >= 0 with time < start_ms + duration_ms."""
    rate = positive_number("rate_hz", rate_hz)
    duration = positive_number("duration_ms", duration_ms)
    start = nonnegative_number("start_ms", start_ms)
    n_periods = duration * rate / 1000.0
    count = max(1, math.ceil(n_periods - 1e-9 * max(1.0, n_periods)))  # k < n_periods, rounding-safe
    return start + np.arange(count, dtype=np.float64) * (1000.0 / rate)


def random_interval(mean_interval_ms: float, duration_ms: float, seed: int,
                    start_ms: float = 500.0) -> np.ndarray:
    """Spikes (ms) from ``start_ms`` with inter-pulse intervals uniform on [10 ms, 2 * mean_interval_ms].

    Follows the paper's wording literally, so the intervals average ``mean_interval_ms + 5`` ms.  Spikes stop
    before ``start_ms + duration_ms``.  The k-th interval depends only on ``seed`` (not on the duration).
    """
    mean = finite_number("mean_interval_ms", mean_interval_ms)
    if mean <= MIN_INTERVAL_MS:
        raise InputError(f"mean_interval_ms must be > {MIN_INTERVAL_MS} ms (the shortest interval), got {mean}")
    duration = positive_number("duration_ms", duration_ms)
    start = nonnegative_number("start_ms", start_ms)
    rng = np.random.default_rng(seed_value(seed))
    intervals = rng.uniform(MIN_INTERVAL_MS, 2.0 * mean, size=math.ceil(duration / MIN_INTERVAL_MS) + 1)
    times = start + np.concatenate(([0.0], np.cumsum(intervals)))
    return times[times < start + duration].astype(np.float64)


