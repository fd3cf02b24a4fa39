"""Step 3 (ranking) of the diagnosis: the canonical causes, which trials can show each, and their order.

``CAUSES`` holds, for every canonical name of shared/spec/diagnosis.md, the kind of trial that would show the
cause (``telling``: a test on a trial's :class:`TrialFeatures`) and the explanatory variable its residual should
follow.  A cause is *untestable* when no calibration trial or no held-out trial is of its telling kind (it can be
neither fitted nor judged); it is listed as such, never guessed.  Testable causes are ranked by the structure of
the baseline residual on their telling trials: score = (share of all trials' excess squared error above noise that
sits on the telling trials) x (eta^2 of the pooled residual of those trials against the cause's variable).

Two causes are defined by what the force does *after* a movement: force enhancement after stretch and force
depression after shortening ("force after an active stretch stays above the isometric force", shared/spec/
diagnosis.md).  Their ``after`` is the sign of that movement, and :func:`hold_window` gives the samples where the
definition applies: the isometric hold from ``HOLD_DELAY_S`` after the trial's last active movement of that sign,
while stimulated.  The same window makes a trial telling for them (``TrialFeatures.hold_after_*``) and is where
:mod:`.verdict` requires their extension to gain (rule 7), measured from "the isometric force at the same length":
:func:`hold` finds the isometric trials at the hold's length and stimulation rate, whose mean residual over the
same span of stimulation (:meth:`Window.level`) is a misfit a history effect does not explain.  Every other cause is
defined on its telling trials (:meth:`Cause.where`), the moving ones only for the two causes that act through the
movement (movement-induced depression, lengthening below the optimum).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np

from ..measured import Trial
from .residuals import MOVING_MM_S, Noise, correlation_ratio

#: Time (s) after the end of an active stretch or shortening before the hold counts as "after" it.  The force's
#: transient back to the isometric level (the CE-SE relaxation through the force-velocity relation) has a time
#: constant A g (1 + c0/P0) / (KSE d0) of about 60 ms at full activation with CT09's Module 3 (0.68 / (0.4 /mm x
#: 30.3 mm/s)), so after 0.2 s (3.5 of them) what is left is history, not the movement's own dynamics.
HOLD_DELAY_S = 0.2
#: Least hold (s) after that delay for a trial to have a hold window (and so to be telling for force enhancement
#: or depression).
MIN_HOLD_S = 0.05
#: A sample is stimulated from the first stimulus to ACTIVE_AFTER_S (s) after the last, except in a gap between
#: stimuli longer than ACTIVE_GAP_FACTOR median intervals (a pause between bursts is not a stimulated hold).
ACTIVE_AFTER_S = 0.05
ACTIVE_GAP_FACTOR = 1.5
#: The rise of an isometric train (s after its first stimulus) left out of its plateau.
RISE_S = 0.2
#: An isometric trial gives "the isometric force at the same length" of a hold when its length is constant within
#: STILL_MM (mm) and lies within ISOMETRIC_LENGTH_TOL_MM of the hold's, and it is a regular train (every interval
#: within ISOMETRIC_RATE_TOL of its median) at the hold's rate within ISOMETRIC_RATE_TOL (synth sets lengths to
#: 0.1 mm; a 40 Hz hold is matched by 40 Hz trains, not by 30 or 50 Hz ones, nor by doublets or post-tetanic
#: probes).
STILL_MM = 0.05
ISOMETRIC_LENGTH_TOL_MM = 0.5
ISOMETRIC_RATE_TOL = 0.2


def _median_interval_s(stimuli_s: np.ndarray) -> float:
    """Median interval (s) between sorted stimuli; 0 with fewer than two."""
    s = np.sort(np.asarray(stimuli_s, dtype=float))
    return float(np.median(np.diff(s))) if s.size > 1 else 0.0


def stimulated(time_s: np.ndarray, stimuli_s: np.ndarray) -> np.ndarray:
    """Boolean mask over ``time_s`` (s): the muscle is stimulated (from the first stimulus to ACTIVE_AFTER_S after
    the last, gaps over ACTIVE_GAP_FACTOR median intervals left out)."""
    t = np.asarray(time_s, dtype=float)
    stim = np.sort(np.asarray(stimuli_s, dtype=float))
    if stim.size == 0:
        return np.zeros(t.size, bool)
    k = np.searchsorted(stim, t, side="right")
    since = t - stim[np.maximum(k - 1, 0)]
    gap = max(ACTIVE_AFTER_S, ACTIVE_GAP_FACTOR * _median_interval_s(stim))
    return (k >= 1) & (since <= gap) & (t <= stim[-1] + ACTIVE_AFTER_S)


def _motion(trial: Trial) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """time (s), velocity (mm/s), moving (|v| > MOVING_MM_S) and stimulated masks of a trial."""
    t = np.asarray(trial.time_s, dtype=float)
    x = trial.length_at()
    v = np.gradient(x, t) if x.size > 1 else np.zeros_like(x)
    return t, v, np.abs(v) > MOVING_MM_S, stimulated(t, trial.stimulus_times_s)


def hold_window(trial: Trial, sign: int, delay_s: float = HOLD_DELAY_S) -> np.ndarray:
    """Boolean mask over ``trial``'s samples: each stimulated isometric hold that directly follows an active
    movement of ``sign`` (+1 lengthening, -1 shortening; |velocity| > MOVING_MM_S while stimulated), from
    ``delay_s`` (s) after that movement ends to the next movement or the end of the stimulation.  All False when
    the trial has no such hold or when it lasts less than MIN_HOLD_S in all (the brief stops of a random or cyclic
    length are not holds)."""
    t, v, moving, active = _motion(trial)
    out = np.zeros(t.size, bool)
    still = ~moving & active
    starts = np.flatnonzero(still & ~np.concatenate([[False], still[:-1]]))
    for a in starts:
        p = a - 1  # the sample before the hold: the movement it follows
        if p < 0 or not (moving[p] and active[p] and np.sign(v[p]) == sign):
            continue
        b = a + int(np.argmin(still[a:])) if not still[a:].all() else t.size
        out[a:b] = t[a:b] > t[p] + delay_s
    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    return out if out.sum() * dt >= MIN_HOLD_S else np.zeros(t.size, bool)


@dataclass(frozen=True)
class Window:
    """Where a cause is judged in one trial (rule 7 of :mod:`.verdict`): the samples (``mask``) and, for a hold
    after a movement (:func:`hold_window`), the isometric trials at its length and rate (``references``) and the
    span of stimulation (s since the first stimulus) over which their force is compared, to the end of the hold
    (``until_s``); no references otherwise."""

    mask: np.ndarray
    references: tuple[str, ...]
    until_s: float

    def level(self, trials: Mapping[str, Trial], residuals: Mapping[str, np.ndarray]) -> float:
        """The isometric misfit (N, model - measured) the hold is measured from: the mean over the ``references``
        (each counting once) of their mean residual from RISE_S after their first stimulus to their last or to
        ``until_s``, whichever is first; 0 without references."""
        means = []
        for i in self.references:
            t = np.asarray(trials[i].time_s, dtype=float)
            stim = np.asarray(trials[i].stimulus_times_s, dtype=float)
            m = (t >= stim.min() + RISE_S) & (t <= min(stim.max(), stim.min() + self.until_s))
            if m.any():
                means.append(float(np.mean(np.asarray(residuals[i])[m])))
        return float(np.mean(means)) if means else 0.0


def _regular_rate_hz(stimuli_s: np.ndarray) -> float:
    """Rate (Hz) of a regular train (two stimuli or more, every interval within ISOMETRIC_RATE_TOL of the median);
    0 otherwise."""
    s = np.sort(np.asarray(stimuli_s, dtype=float))
    if s.size < 2:
        return 0.0
    isi = np.diff(s)
    med = float(np.median(isi))
    return 1.0 / med if med > 0 and np.all(np.abs(isi - med) <= ISOMETRIC_RATE_TOL * med) else 0.0


def hold(trials: Mapping[str, Trial], trial_id: str, sign: int) -> Window:
    """The :class:`Window` of trial ``trial_id`` for movements of ``sign``: its hold window and the isometric trials
    of ``trials`` (either side of the split: the model's misfit there is calibration, not history) whose constant
    length lies within ISOMETRIC_LENGTH_TOL_MM (mm) of the hold's mean length and whose regular rate is the
    hold's within ISOMETRIC_RATE_TOL."""
    trial = trials[trial_id]
    mask = hold_window(trial, sign)
    if not mask.any():
        return Window(mask, (), 0.0)
    t = np.asarray(trial.time_s, dtype=float)
    stim = np.sort(np.asarray(trial.stimulus_times_s, dtype=float))
    x_hold = float(np.mean(trial.length_at()[mask]))
    during = stim[(stim >= t[mask].min() - HOLD_DELAY_S) & (stim <= t[mask].max())]  # from the movement's end
    m = _median_interval_s(during)
    rate = 1.0 / m if m > 0 else 0.0
    refs = []
    for i, other in trials.items():
        x = other.length_at()
        r = _regular_rate_hz(other.stimulus_times_s)
        if (i != trial_id and x.size and float(np.ptp(x)) <= STILL_MM and r > 0 and rate > 0
                and abs(float(np.mean(x)) - x_hold) <= ISOMETRIC_LENGTH_TOL_MM
                and abs(r - rate) <= ISOMETRIC_RATE_TOL * rate):
            refs.append(i)
    return Window(mask, tuple(refs), float(t[mask].max() - stim[0]))


@dataclass(frozen=True)
class TrialFeatures:
    """What kind of trial it is: stimuli, rates (Hz), shortest ISI (ms), train duration (s), length (mm, mean) and
    its offset from the optimum g1, movement, lengthening below the optimum, a hold after a stretch / shortening
    while stimulated, and a second burst after a pause (activity history inside the trial)."""

    n_stimuli: int
    mean_rate_hz: float
    min_isi_ms: float
    max_isi_ms: float
    train_s: float
    length_offset_mm: float
    moving: bool
    lengthening_below_optimum: bool
    hold_after_stretch: bool
    hold_after_shortening: bool
    burst_after_pause: bool


def trial_features(trial: Trial, g1_mm: float) -> TrialFeatures:
    """The :class:`TrialFeatures` of a trial, given the optimum g1 (mm)."""
    stim = np.sort(np.asarray(trial.stimulus_times_s, dtype=float))
    isi = np.diff(stim) * 1000.0
    x = trial.length_at()
    _, v, moving, active = _motion(trial)
    return TrialFeatures(
        n_stimuli=int(stim.size),
        mean_rate_hz=float((stim.size - 1) / (stim[-1] - stim[0])) if stim.size > 1 and stim[-1] > stim[0] else 0.0,
        min_isi_ms=float(isi.min()) if isi.size else np.inf, max_isi_ms=float(isi.max()) if isi.size else 0.0,
        train_s=float(stim[-1] - stim[0]) if stim.size > 1 else 0.0,
        length_offset_mm=float(np.mean(x) - g1_mm), moving=bool(np.any(moving)),
        lengthening_below_optimum=bool(np.any(moving & (v > 0) & (x < g1_mm) & active)),
        hold_after_stretch=bool(hold_window(trial, 1).any()), hold_after_shortening=bool(hold_window(trial, -1).any()),
        burst_after_pause=bool(isi.size >= 5 and isi.max() >= 200.0 and np.sum(isi < 200.0) >= 4))


@dataclass(frozen=True)
class Cause:
    """A canonical cause: what the data show, the telling trial kind (text and test), the variable to follow."""

    name: str
    shows: str
    telling_text: str
    telling: Callable[[TrialFeatures], bool]
    variable: str
    after: int = 0  # +1 / -1: defined by the force after an active stretch / shortening (hold_window); 0: not
    moves: bool = False  # acts through the movement itself (judged on moving trials too)

    def where(self, trials: Mapping[str, Trial], trial_id: str, telling: bool) -> Window:
        """Where the cause is defined in trial ``trial_id`` of ``trials`` (rule 7 of :mod:`.verdict`), given
        whether the trial is of its telling kind: for a cause defined after a movement, the hold after it
        (:func:`hold`); for a cause that acts through the movement, the whole of a telling trial; for any other,
        the whole of a telling trial that does not move (movement brings the force-velocity misfit of a
        preparation, which such a cause does not explain).  An empty mask elsewhere."""
        if self.after:
            return hold(trials, trial_id, self.after)
        trial = trials[trial_id]
        n = np.asarray(trial.time_s).size
        ok = telling and (self.moves or not bool(np.any(_motion(trial)[2])))
        return Window(np.full(n, ok), (), 0.0)


CAUSES: tuple[Cause, ...] = (
    Cause("length_dependent_activation", "low-rate force falls off away from the optimum more than g(Xm) allows",
          "isometric twitches or trains <= 20 Hz more than 2 mm from the optimum",
          lambda f: not f.moving and f.mean_rate_hz <= 20.0 and abs(f.length_offset_mm) > 2.0, "length"),
    Cause("movement_induced_depression", "force sinks progressively during movement at low rates",
          "stimulated trials with movement at <= 20 Hz",
          lambda f: f.moving and 0 < f.mean_rate_hz <= 20.0, "time_since_movement_onset", moves=True),
    Cause("lengthening_below_optimum", "excess model force while lengthening below the optimum",
          "stimulated lengthening below the optimum", lambda f: f.lengthening_below_optimum, "velocity", moves=True),
    Cause("staircase", "twitch amplitude changes over successive stimuli at low rates",
          "trains of >= 5 stimuli at <= 15 Hz", lambda f: f.n_stimuli >= 5 and 0 < f.mean_rate_hz <= 15.0,
          "position_in_train"),
    Cause("doublet_potentiation", "extra force after short inter-spike intervals (5-15 ms)",
          "trains with an ISI <= 15 ms among longer ones (doublets, random trains)",
          lambda f: f.min_isi_ms <= 15.0 and f.max_isi_ms >= 2.0 * f.min_isi_ms, "isi"),
    Cause("post_activation_potentiation", "after activity, twitches grow and relaxation slows",
          "stimuli after a pause that follows a burst of activity", lambda f: f.burst_after_pause,
          "recent_activity"),
    Cause("relaxation_rate", "the model relaxes slower or faster than the data",
          "any trial with a relaxation after its last stimulus", lambda f: f.n_stimuli >= 1,
          "time_since_last_stimulus"),
    Cause("force_enhancement_after_stretch", "force after an active stretch stays above the isometric force",
          "an isometric hold after an active stretch", lambda f: f.hold_after_stretch, "stretch_history", after=1),
    Cause("force_depression_after_shortening", "force after active shortening stays below the isometric force",
          "an isometric hold after active shortening", lambda f: f.hold_after_shortening, "stretch_history",
          after=-1),
    Cause("fatigue", "force declines over long high-rate trains",
          "trains of >= 1 s at >= 30 Hz", lambda f: f.train_s >= 1.0 and f.mean_rate_hz >= 30.0,
          "recent_activity"),
)


@dataclass
class Candidate:
    """A cause's standing before its extension is fitted: telling trials on each side, score, why untestable."""

    cause: Cause
    telling_calibration: list[str]
    telling_heldout: list[str]
    score: float
    eta2: float
    excess_share: float
    untestable: str | None = None


def rank_candidates(trials: Mapping[str, Trial], g1_mm: float, calibration: Sequence[str], heldout: Sequence[str],
                    residuals: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
                    variables: Mapping[str, Mapping[str, np.ndarray]]) -> list[Candidate]:
    """Every cause of ``CAUSES`` with its telling trials and score, testable ones first by score (module
    docstring); residuals in N, noise per trial."""
    feats = {i: trial_features(t, g1_mm) for i, t in trials.items()}
    excess = {i: max(float(residuals[i] @ residuals[i]) - residuals[i].size * noise[i].sd_N ** 2, 0.0)
              / max(float(np.ptp(trials[i].force)), 1e-12) ** 2 for i in residuals}
    total = sum(excess.values()) or 1.0
    out = []
    for c in CAUSES:
        cal = [i for i in calibration if c.telling(feats[i])]
        held = [i for i in heldout if c.telling(feats[i])]
        why = None
        if not cal and not held:
            why = f"no trial of the telling kind ({c.telling_text})"
        elif not cal or not held:
            side = "calibration" if not cal else "held-out"
            why = f"no {side} trial of the telling kind ({c.telling_text}); give --split to put one there"
        ids = cal + held
        share = sum(excess[i] for i in ids) / total
        eta = 0.0
        if ids:
            r = np.concatenate([residuals[i] / max(float(np.ptp(trials[i].force)), 1e-12) for i in ids])
            eta = correlation_ratio(np.concatenate([variables[i][c.variable] for i in ids]), r)
        out.append(Candidate(c, cal, held, share * eta, eta, share, why))
    return sorted(out, key=lambda c: (c.untestable is not None, -c.score))
