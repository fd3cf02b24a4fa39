"""Muscle length inputs: a sampled trace Xm(t) (mm) that NEURON plays into a MuscleLength point process."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import InputError

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
    def isometric(cls, xm_mm: float, duration_ms: float) -> "LengthTrace":
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
