"""A pool's drive as data: what ``Pool.drive_synaptic``, ``drive_current_ramp`` and ``drive_poisson`` receive,
checked before anything is built and applied to a pool in one call.

    Drive.recruitment_ramp(0.6, 2000.0)     # synaptic 0 -> 0.6 uS over the first half, held, down to 0 at the end
    Drive.rise("synaptic", 0.6, 500.0)      # synaptic 0 -> 0.6 uS over the whole run
    Drive("current", (0, 500), (0, 40))     # a common current, nA, linear between the times (ms)
    Drive("poisson", rate_hz=400, weight_uS=0.15, seed=1)

The recruitment ramp is the human pool's (networks/human_pool.py): the common synaptic conductance recruits the
units in size order and keeps their rates within those of human motor units (5-30 Hz), then derecruits them.
Units: ms, uS (synaptic, each cell's total), nA (current), Hz.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..validate import check_spike_times, finite_number, nonnegative_number, positive_number, seed_value

#: Drive kinds: a common synaptic conductance, a common current, independent Poisson synaptic input.
DRIVE_KINDS = ("synaptic", "current", "poisson")


@dataclass(frozen=True)
class Drive:
    """One drive: ``kind`` (DRIVE_KINDS); for "synaptic" and "current" the values (uS or nA) linear between
    ``times_ms`` (ms); for "poisson" ``rate_hz`` (Hz), ``weight_uS`` (uS) and ``seed``."""

    kind: str
    times_ms: tuple[float, ...] = ()
    values: tuple[float, ...] = ()
    rate_hz: float = 400.0
    weight_uS: float = 0.15
    seed: int = 0

    def __post_init__(self) -> None:
        if self.kind not in DRIVE_KINDS:
            raise InputError(f"drive kind must be one of {', '.join(DRIVE_KINDS)}, got {self.kind!r}")
        if self.kind == "poisson":
            positive_number("Poisson rate (Hz)", self.rate_hz)
            nonnegative_number("Poisson synaptic weight (uS)", self.weight_uS)
            seed_value(self.seed)
            return
        unit = "uS" if self.kind == "synaptic" else "nA"
        t = check_spike_times(self.times_ms, f"{self.kind} drive times")
        check = nonnegative_number if self.kind == "synaptic" else finite_number
        v = [check(f"{self.kind} drive value {i} ({unit})", x) for i, x in enumerate(self.values)]
        if len(v) != t.size or t.size < 2:
            raise InputError(f"{self.kind} drive: {t.size} times and {len(v)} values (need equal, >= 2)")
        object.__setattr__(self, "times_ms", tuple(float(x) for x in t))
        object.__setattr__(self, "values", tuple(v))

    @classmethod
    def recruitment_ramp(cls, peak_uS: float, duration_ms: float) -> Drive:
        """Synaptic conductance 0 -> ``peak_uS`` (uS) over the first half of ``duration_ms`` (ms), held to three
        quarters, back to 0 at the end."""
        d = positive_number("run duration (ms)", duration_ms)
        peak = positive_number("peak synaptic drive (uS)", peak_uS)
        return cls("synaptic", (0.0, 0.5 * d, 0.75 * d, d), (0.0, peak, peak, 0.0))

    @classmethod
    def rise(cls, kind: str, peak: float, duration_ms: float) -> Drive:
        """``kind`` ("synaptic", uS, or "current", nA) rising linearly from 0 to ``peak`` over ``duration_ms``."""
        return cls(kind, (0.0, positive_number("run duration (ms)", duration_ms)), (0.0, peak))

    def end_ms(self) -> float:
        """The last time (ms) the drive is defined at (0 for Poisson, which runs to the end)."""
        return self.times_ms[-1] if self.times_ms else 0.0

    def held_at_peak_ms(self) -> tuple[float, float] | None:
        """The longest stretch (ms) over which a synaptic or current drive stays at its largest value (the plateau
        of a recruitment ramp), None when it is never held there (a rise, a Poisson drive)."""
        if self.kind == "poisson":
            return None
        t, v = np.asarray(self.times_ms), np.asarray(self.values)
        at_peak = v == v.max()
        best = None
        for i in range(t.size - 1):
            if at_peak[i] and at_peak[i + 1] and (best is None or t[i + 1] - t[i] > best[1] - best[0]):
                best = (float(t[i]), float(t[i + 1]))
        return best

    def falls_back(self) -> bool:
        """Whether a synaptic or current drive ends at half its largest value or less (uS or nA, above its
        smallest), having risen above its start (so its units are recruited and then derecruited, as Delta F
        needs)."""
        if self.kind == "poisson":
            return False
        v = np.asarray(self.values, float)
        return bool(v.max() > v[0] and v[-1] - v.min() <= 0.5 * (v.max() - v.min()))

    def apply(self, pool: Any) -> None:
        """Give this drive to ``pool`` (a Pool without a drive)."""
        if self.kind == "poisson":
            pool.drive_poisson(self.rate_hz, self.weight_uS, seed=self.seed)
        elif self.kind == "synaptic":
            pool.drive_synaptic(self.times_ms, self.values)
        else:
            pool.drive_current_ramp(self.times_ms, self.values)

    def to_dict(self) -> dict[str, Any]:
        """The drive as JSON-ready data (provenance)."""
        if self.kind == "poisson":
            return {"kind": self.kind, "rate_hz": self.rate_hz, "weight_uS": self.weight_uS, "seed": self.seed}
        unit = "values_uS" if self.kind == "synaptic" else "values_nA"
        return {"kind": self.kind, "times_ms": list(self.times_ms), unit: list(np.asarray(self.values).tolist())}
