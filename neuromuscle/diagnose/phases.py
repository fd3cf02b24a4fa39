"""What each trial is, described once: its stimulation, its phases (holds, ramps, other movement) and the facts
the diagnosis asks of it.  Every stage (split, calibration, candidates, windows of the rules) reads a
:class:`TrialPhases`; nothing re-derives a trial's kind from its samples elsewhere.

* **Stimulated** samples run from the first stimulus to ACTIVE_AFTER_S after the last, except in a gap between
  stimuli longer than ACTIVE_GAP_FACTOR median intervals (a pause between bursts is not a stimulated hold).
* **Moving** samples have |dXm/dt| > MOVING_MM_S (mm/s).  Runs of moving samples of one sign are *ramps* when the
  speed stays within RAMP_SPEED_TOL of its median over most of the run, else *movement* (random or cyclic
  length); runs of still samples are *holds*.
* The **hold after a movement** of sign +1 (stretch) or -1 (shortening): a stimulated hold that directly follows
  an active ramp of that sign, from HOLD_DELAY_S after the ramp's end to the next movement or the end of
  stimulation.  The force's transient back to the isometric level through the force-velocity relation has a
  time constant A g (1 + c0/P0) / (KSE d0) of about 60 ms at full activation for the Kim, Sandercock & Heckman
  2015 cat soleus (CT09), so after 0.2 s what is left is history, not the movement's own dynamics.
* A **burst after a pause**: at least four short intervals (< 200 ms) and a pause of 200 ms or more (activity
  history inside the trial: potentiation protocols, twitches around a tetanus).

Units: s, mm, mm/s, Hz, ms as named.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..measured import Trial

MOVING_MM_S = 0.5
ACTIVE_AFTER_S = 0.05
ACTIVE_GAP_FACTOR = 1.5
HOLD_DELAY_S = 0.2
MIN_HOLD_S = 0.05
RAMP_SPEED_TOL = 0.25
#: A trial is isometric when its length stays within STILL_MM (mm) of its first value.
STILL_MM = 0.05
#: Regular trains: every interval within REGULAR_TOL of the median.
REGULAR_TOL = 0.2
PAUSE_MS = 200.0


@dataclass(frozen=True)
class Phase:
    """One run of samples [start, stop) of a trial: "hold", "ramp" or "movement"; its time span (s), length at
    its ends (mm), median velocity (mm/s) and whether most of it is stimulated."""

    kind: str
    start: int
    stop: int
    start_s: float
    end_s: float
    length_from_mm: float
    length_to_mm: float
    velocity_mm_s: float
    stimulated: bool

    @property
    def sign(self) -> int:
        """+1 lengthening, -1 shortening, 0 a hold."""
        return 0 if self.kind == "hold" else int(np.sign(self.velocity_mm_s))


@dataclass(frozen=True)
class TrialPhases:
    """A trial described once (module docstring): sample masks, phases, stimulation facts."""

    trial_id: str
    protocol: str
    time_s: np.ndarray
    length_mm: np.ndarray
    velocity_mm_s: np.ndarray
    stimuli_s: np.ndarray
    stimulated: np.ndarray
    moving: np.ndarray
    phases: tuple[Phase, ...]

    # -- stimulation -------------------------------------------------------------------------------------
    @property
    def n_stimuli(self) -> int:
        return int(self.stimuli_s.size)

    @property
    def intervals_ms(self) -> np.ndarray:
        return np.diff(self.stimuli_s) * 1000.0

    @property
    def mean_rate_hz(self) -> float:
        s = self.stimuli_s
        return float((s.size - 1) / (s[-1] - s[0])) if s.size > 1 and s[-1] > s[0] else 0.0

    @property
    def regular_rate_hz(self) -> float:
        """Rate (Hz) of a regular train (module constants); 0 otherwise."""
        isi = self.intervals_ms
        if isi.size == 0:
            return 0.0
        med = float(np.median(isi))
        return 1000.0 / med if med > 0 and np.all(np.abs(isi - med) <= REGULAR_TOL * med) else 0.0

    @property
    def min_isi_ms(self) -> float:
        return float(self.intervals_ms.min()) if self.n_stimuli > 1 else np.inf

    @property
    def max_isi_ms(self) -> float:
        return float(self.intervals_ms.max()) if self.n_stimuli > 1 else 0.0

    @property
    def train_s(self) -> float:
        return float(self.stimuli_s[-1] - self.stimuli_s[0]) if self.n_stimuli > 1 else 0.0

    @property
    def burst_after_pause(self) -> bool:
        isi = self.intervals_ms
        return bool(isi.size >= 5 and isi.max() >= PAUSE_MS and np.sum(isi < PAUSE_MS) >= 4)

    # -- length ------------------------------------------------------------------------------------------
    @property
    def isometric_length_mm(self) -> float | None:
        """The constant length (mm) of an isometric trial; None when the length varies."""
        x = self.length_mm
        return float(x[0]) if float(np.ptp(x)) <= STILL_MM else None

    @property
    def moves(self) -> bool:
        return bool(np.any(self.moving))

    @property
    def movement_kind(self) -> str:
        """How the length moves while the muscle is stimulated: "movement" when some stimulated run of moving
        samples is not a ramp (random, cyclic or stepped length), else "ramps" when one is a ramp, else
        "isometric"."""
        kinds = {p.kind for p in self.phases if p.stimulated}
        return "movement" if "movement" in kinds else "ramps" if "ramp" in kinds else "isometric"

    @property
    def active_movement(self) -> bool:
        """The length moves while the muscle is stimulated."""
        return bool(np.any(self.moving & self.stimulated))

    def length_offset_mm(self, g1_mm: float) -> float:
        """Mean length minus the optimum g1 (mm)."""
        return float(np.mean(self.length_mm) - g1_mm)

    def lengthening_below(self, g1_mm: float) -> bool:
        """Stimulated lengthening below the optimum g1 (mm) somewhere in the trial."""
        return bool(np.any(self.moving & (self.velocity_mm_s > 0) & (self.length_mm < g1_mm) & self.stimulated))

    # -- windows -----------------------------------------------------------------------------------------
    def hold_after(self, sign: int, delay_s: float = HOLD_DELAY_S) -> np.ndarray:
        """Mask of the stimulated holds that directly follow an active ramp of ``sign`` (+1 stretch, -1
        shortening), from ``delay_s`` after it to the next movement or the first unstimulated sample (module
        docstring); all False when they last < MIN_HOLD_S."""
        out = np.zeros(self.time_s.size, bool)
        for before, hold in zip(self.phases[:-1], self.phases[1:]):
            if hold.kind != "hold" or before.kind == "hold" or before.sign != sign or not before.stimulated:
                continue
            active = self.stimulated[hold.start:hold.stop]
            stop = hold.start + (int(np.argmin(active)) if not active.all() else active.size)  # until it rests
            span = np.arange(hold.start, stop)
            out[span[self.time_s[span] > before.end_s + delay_s]] = True
        if out.sum() * self.sample_interval_s < MIN_HOLD_S:
            return np.zeros(self.time_s.size, bool)
        return out

    def isometric_stimulated(self) -> np.ndarray:
        """Mask of stimulated samples in holds that no active movement precedes within HOLD_DELAY_S (where the
        force is isometric: a whole isometric trial, and the holds before a ramp or long after one)."""
        out = np.zeros(self.time_s.size, bool)
        last_move_end = -np.inf
        for ph in self.phases:
            if ph.kind == "hold":
                span = np.arange(ph.start, ph.stop)
                out[span] = self.stimulated[span] & (self.time_s[span] > last_move_end + HOLD_DELAY_S)
            else:
                last_move_end = ph.end_s
        return out

    @property
    def sample_interval_s(self) -> float:
        return float(np.median(np.diff(self.time_s))) if self.time_s.size > 1 else 0.0


def stimulated_mask(time_s: np.ndarray, stimuli_s: np.ndarray) -> np.ndarray:
    """Boolean mask over ``time_s`` (s): the muscle is stimulated (module docstring)."""
    t = np.asarray(time_s, dtype=float)
    stim = np.sort(np.asarray(stimuli_s, dtype=float))
    if stim.size == 0:
        return np.zeros(t.size, bool)
    k = np.searchsorted(stim, t, side="right")
    since = t - stim[np.maximum(k - 1, 0)]
    median = float(np.median(np.diff(stim))) if stim.size > 1 else 0.0
    gap = max(ACTIVE_AFTER_S, ACTIVE_GAP_FACTOR * median)
    return (k >= 1) & (since <= gap) & (t <= stim[-1] + ACTIVE_AFTER_S)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, stop) of each run of equal values of ``mask``."""
    if mask.size == 0:
        return []
    edges = np.flatnonzero(np.diff(mask.astype(np.int8))) + 1
    bounds = np.concatenate([[0], edges, [mask.size]])
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]


def _phases(t: np.ndarray, x: np.ndarray, v: np.ndarray, moving: np.ndarray,
            stimulated: np.ndarray) -> tuple[Phase, ...]:
    sign = np.where(moving, np.sign(v), 0).astype(np.int8)
    out = []
    for a, b in _runs(sign):
        kind = "hold" if sign[a] == 0 else "movement"
        vmed = float(np.median(v[a:b])) if kind != "hold" else 0.0
        if kind == "movement" and vmed != 0.0:
            steady = np.abs(v[a:b] - vmed) <= RAMP_SPEED_TOL * abs(vmed)
            kind = "ramp" if steady.mean() >= 0.7 else "movement"
        out.append(Phase(kind, a, b, float(t[a]), float(t[b - 1]), float(x[a]), float(x[b - 1]), vmed,
                         bool(stimulated[a:b].mean() > 0.5)))
    return tuple(out)


def describe(trial: Trial) -> TrialPhases:
    """The :class:`TrialPhases` of ``trial``."""
    t = np.asarray(trial.time_s, dtype=float)
    x = np.asarray(trial.length_at(), dtype=float)
    v = np.gradient(x, t) if x.size > 1 else np.zeros_like(x)
    stim = np.sort(np.asarray(trial.stimulus_times_s, dtype=float))
    active = stimulated_mask(t, stim)
    moving = np.abs(v) > MOVING_MM_S
    return TrialPhases(trial.trial_id, trial.protocol, t, x, v, stim, active, moving,
                       _phases(t, x, v, moving, active))


def describe_all(trials: Mapping[str, Trial]) -> dict[str, TrialPhases]:
    """Every trial's :class:`TrialPhases`, by id."""
    return {i: describe(t) for i, t in trials.items()}
