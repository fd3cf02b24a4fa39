"""The canonical causes as the diagnosis sees them: each one is a catalogue extension
(``neuromuscle.model.extensions``), whose class holds the cause's facts (what the data show, the trials that can
show it, its explanatory variable, whether it acts through movement or after it, the baseline parameters it
interacts with).  This module evaluates those facts on the trials' descriptions (:mod:`.phases`):

* :func:`tells`: whether a trial is of a cause's telling kind;
* :func:`where_defined`: the samples of a trial where a cause is defined, as rule R7 of :mod:`.rules` judges it.
  A cause is defined on its telling trials.  The two causes defined by the force *after* a movement ("force
  after an active stretch stays above the isometric force at the same length") are defined in the stimulated
  holds after it (:meth:`.phases.TrialPhases.hold_after`), each model's residual there measured from its own
  misfit of the isometric force at the hold's length and rate (:meth:`Window.level`): a misfit of the isometric
  force is calibration, not history.  A file with no isometric trial at that length and rate (a design of ramps
  to one final length) is compared where its data compare: a stretch-hold against the shortening-holds at the
  same length and rate, and the other way round.
* :func:`isometric_level`: for the causes that act through movement itself, each model's residual in a moving
  trial is measured from its relative misfit of the isometric force at the same length and rate (interpolated
  between the isometric trains at the lengths the file has): a misfit that the isometric trials at those lengths
  share (a length dependence the model lacks, or has in the wrong form) is not a movement effect.

Units: mm, s, Hz, N.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from ..model.extensions import Extension, Telling, registry
from .phases import STILL_MM, TrialPhases

#: The rise of an isometric train (s after its first stimulus) left out of its plateau.
RISE_S = 0.2
#: An isometric trial gives "the isometric force at the same length" of a hold when its constant length lies
#: within ISOMETRIC_LENGTH_TOL_MM (mm) of the hold's and it is a regular train at the hold's rate within
#: ISOMETRIC_RATE_TOL (relative).
ISOMETRIC_LENGTH_TOL_MM = 0.5
ISOMETRIC_RATE_TOL = 0.2


def causes() -> dict[str, type[Extension]]:
    """Every canonical cause of the catalogue, by name (sorted)."""
    return dict(sorted(registry().items()))


def tells(telling: Telling, ph: TrialPhases, g1_mm: float) -> bool:
    """Whether the trial ``ph`` is of the kind ``telling`` describes, given the optimum g1 (mm)."""
    if ph.n_stimuli < max(telling.min_stimuli, 1):
        return False
    if telling.moving is True and not ph.active_movement:
        return False
    if telling.moving is False and ph.isometric_length_mm is None:
        return False
    rate = ph.mean_rate_hz
    if telling.min_rate_hz > 0 and rate < telling.min_rate_hz:
        return False
    if rate > telling.max_rate_hz:
        return False
    if ph.train_s < telling.min_train_s:
        return False
    if abs(ph.length_offset_mm(g1_mm)) < telling.min_length_offset_mm:
        return False
    if telling.short_interval_ms is not None and not (
            ph.min_isi_ms <= telling.short_interval_ms and ph.max_isi_ms >= 2.0 * ph.min_isi_ms):
        return False
    if telling.burst_after_pause and not ph.burst_after_pause:
        return False
    if telling.lengthening_below_optimum and not ph.lengthening_below(g1_mm):
        return False
    if telling.hold_after and not ph.hold_after(telling.hold_after).any():
        return False
    return True


def telling_trials(ext: type[Extension], phases: Mapping[str, TrialPhases], g1_mm: float,
                   ids: Sequence[str]) -> list[str]:
    """The trials among ``ids`` of ``ext``'s telling kind."""
    return [i for i in ids if tells(ext.telling, phases[i], g1_mm)]


@dataclass(frozen=True)
class Window:
    """Where a cause is judged in one trial: the samples (``mask``) and, for a hold after a movement of ``sign``,
    the trials its force is compared with (``references``): isometric trains at its length and rate, compared
    over the span of stimulation (s since the first stimulus) up to ``until_s``, or, where there are none, the
    holds after the opposite movement at that length and rate (``opposite``)."""

    mask: np.ndarray
    references: tuple[str, ...] = ()
    until_s: float = 0.0
    sign: int = 0
    opposite: bool = False

    def level(self, phases: Mapping[str, TrialPhases], residuals: Mapping[str, np.ndarray]) -> float:
        """The misfit (N, model - measured) the hold is measured from: the mean over the ``references`` (each
        counting once) of their mean residual from RISE_S after their first stimulus to their last or to
        ``until_s``, whichever is first, or over their hold after the opposite movement; 0 without references."""
        means = []
        for i in self.references:
            ph = phases[i]
            if self.opposite:
                m = ph.hold_after(-self.sign)
            else:
                t, s = ph.time_s, ph.stimuli_s
                m = (t >= s.min() + RISE_S) & (t <= min(s.max(), s.min() + self.until_s))
            if m.any():
                means.append(float(np.mean(np.asarray(residuals[i])[m])))
        return float(np.mean(means)) if means else 0.0


def _hold_rate_hz(ph: TrialPhases, mask: np.ndarray) -> float:
    """The stimulation rate (Hz) during a hold ``mask`` (from the movement's end), 0 with fewer than two stimuli."""
    t = ph.time_s[mask]
    during = ph.stimuli_s[(ph.stimuli_s >= t.min() - 0.2) & (ph.stimuli_s <= t.max())]
    return 1000.0 / float(np.median(np.diff(during) * 1000.0)) if during.size > 1 else 0.0


def _matches(x: float, r: float, x_hold: float, rate: float) -> bool:
    return (r > 0 and rate > 0 and abs(x - x_hold) <= ISOMETRIC_LENGTH_TOL_MM
            and abs(r - rate) <= ISOMETRIC_RATE_TOL * rate)


def isometric_references(phases: Mapping[str, TrialPhases], trial_id: str, mask: np.ndarray) -> tuple[str, ...]:
    """The isometric regular trains (either side of the split) at the length and rate of the hold ``mask`` of
    trial ``trial_id`` (module constants)."""
    ph = phases[trial_id]
    x_hold, rate = float(np.mean(ph.length_mm[mask])), _hold_rate_hz(ph, mask)
    out = []
    for i, other in phases.items():
        x = other.isometric_length_mm
        if i != trial_id and x is not None and float(np.ptp(other.length_mm)) <= STILL_MM and \
                _matches(x, other.regular_rate_hz, x_hold, rate):
            out.append(i)
    return tuple(out)


def opposite_holds(phases: Mapping[str, TrialPhases], trial_id: str, mask: np.ndarray, sign: int) -> tuple[str, ...]:
    """The trials (either side of the split) with a hold after a movement of the opposite sign at the length and
    rate of the hold ``mask`` of trial ``trial_id``."""
    ph = phases[trial_id]
    x_hold, rate = float(np.mean(ph.length_mm[mask])), _hold_rate_hz(ph, mask)
    out = []
    for i, other in phases.items():
        m = other.hold_after(-sign) if i != trial_id else None
        if m is not None and m.any() and _matches(float(np.mean(other.length_mm[m])), _hold_rate_hz(other, m), x_hold,
                                                  rate):
            out.append(i)
    return tuple(out)


def isometric_level(phases: Mapping[str, TrialPhases], trial_id: str, simulated: Mapping[str, np.ndarray],
                    measured: Mapping[str, np.ndarray]) -> np.ndarray | float:
    """A model's isometric misfit (N, model - measured) at the length of every sample of moving trial
    ``trial_id`` (module docstring): each isometric regular train at the trial's mean rate (within
    ISOMETRIC_RATE_TOL) gives its relative misfit over its plateau (mean residual / mean model force, from RISE_S
    after its first stimulus to its last); these are interpolated in length (held at the end values beyond the
    lengths the file has) and scaled by the model's force at each sample.  0 with isometric trains at fewer than
    two lengths."""
    ph = phases[trial_id]
    rate = ph.mean_rate_hz
    points: dict[float, list[float]] = {}
    for i, other in phases.items():
        x = other.isometric_length_mm
        r = other.regular_rate_hz
        if i == trial_id or x is None or r <= 0 or rate <= 0 or abs(r - rate) > ISOMETRIC_RATE_TOL * rate:
            continue
        t, st = other.time_s, other.stimuli_s
        m = (t >= st.min() + RISE_S) & (t <= st.max())
        f = float(np.mean(simulated[i][m])) if m.any() else 0.0
        if f > 0:
            key = next((k for k in points if abs(k - x) <= ISOMETRIC_LENGTH_TOL_MM), x)
            points.setdefault(key, []).append(float(np.mean(simulated[i][m] - measured[i][m])) / f)
    if len(points) < 2:
        return 0.0
    xs = np.array(sorted(points))
    rel = np.array([np.mean(points[x]) for x in xs])
    return np.interp(ph.length_mm, xs, rel) * np.asarray(simulated[trial_id], dtype=float)


def where_defined(ext: type[Extension], phases: Mapping[str, TrialPhases], trial_id: str, g1_mm: float) -> Window:
    """Where cause ``ext`` is defined in trial ``trial_id`` (module docstring): the hold after its movement for a
    cause defined after one, the whole of a telling trial otherwise; an empty mask elsewhere."""
    ph = phases[trial_id]
    if ext.after:
        mask = ph.hold_after(ext.after)
        if not mask.any():
            return Window(mask)
        until = float(ph.time_s[mask].max() - ph.stimuli_s[0])
        refs = isometric_references(phases, trial_id, mask)
        if refs:
            return Window(mask, refs, until, ext.after)
        return Window(mask, opposite_holds(phases, trial_id, mask, ext.after), until, ext.after, opposite=True)
    return Window(np.full(ph.time_s.size, tells(ext.telling, ph, g1_mm)))
