"""The unrecorded part of the pool, described explicitly: force from recorded discharges with every unit of the
muscle's pool, not only the decomposed ones.

A decomposition identifies a sample of the pool (16-84 units of a few hundred).  Instead of weighting the recorded
units to stand for the others (:mod:`.human_units`' interval weight W and offset, fitted to one sample), the pool is
completed:

1. **Pool.**  The muscle's units and their recruitment thresholds (% MVC) are the published distribution of
   :data:`.follow_force.HUMAN_MUSCLES` (Caillet, Phillips, Farina & Modenese 2022, fitted to published thresholds of
   human tibialis anterior and gastrocnemius medialis; 400 units, the last recruited at 90 % MVC).  Each recorded
   unit takes the place of the pool unit whose threshold is nearest its own (:func:`unrecorded_thresholds`); the
   others are the unrecorded units.
2. **Their discharges** (:func:`neighbour_rate`, the default): an unrecorded unit between two recorded units in
   threshold is recruited and derecruited at times interpolated between theirs (below the lowest or above the
   highest recorded unit: shifted by the threshold difference over the speed at which recruitment and
   derecruitment sweep the thresholds), and fires at its neighbours' smoothed rates lowered by k Hz per % MVC that
   its threshold lies above theirs (onion skin: at one excitation the lower-threshold units fire faster; De Luca &
   Hostage 2010, J Neurophysiol 104:1034; De Luca & Contessa 2012, J Neurophysiol 107:178), regularly.  k and the
   rate at recruitment (``a0 + a1 th``) are read from the recorded discharges alone at the recruited units'
   first discharges, where the force is the recruited unit's threshold (:func:`fit_rate_model`): no force beyond
   the thresholds is used and nothing here is fitted to the force.  No unit is recruited above the highest of the
   recorded thresholds and the top of the excitation (step 3).  The unrecorded units are simulated in groups of
   neighbouring thresholds at most :data:`GROUP_WIDTH_PERCENT_MVC` % MVC wide (:func:`group_thresholds`): one
   train per group, at the group's mean threshold, standing for each member.
3. **Excitation** (the alternative ``rates_from="excitation"``, and the ceiling of step 2): E(t) (% MVC) is the
   mean over the active recorded units of ``th_j + (r_j(t) - a(th_j)) / k`` (:func:`excitation`), and every
   unrecorded unit fires at ``a(th) + k (E - th)`` while E exceeds its threshold.  Rates decline through a
   plateau and units derecruit at lower rates than they were recruited at, so E sags on the plateau and falls
   seconds before the force on the descent: this variant loses the descent.
4. **Forces.**  Every unit, recorded or not, has the twitch speed ``S0 * RS ** (th / 100)`` of
   :mod:`.human_units` (same priors) and the relative P0 of its rank in the muscle's pool under the spread
   ``P0 = 1 + (R - 1) rank ** q`` that makes the model pool recruit at the published thresholds
   (:data:`PUBLISHED_P0_SPREAD`, :func:`published_p0`; most units alike, the last ones up to R times larger, as
   in the P0 distributions of human TA and GM, Caillet et al. 2022).  ``p0_from="fitted"`` uses ``RP ** (th /
   100)`` with RP fitted instead.  The predicted force is ``scale * sum over all units of P0 g(t - delay)``: no
   interval weight and no offset (a pool at rest pulls nothing).  Fitted per file on the calibration window: S0,
   RS and the delay (bounded Nelder-Mead from two starts, :mod:`.window_fit`) and the scale (closed form).

Units: ms, Hz, % MVC.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from scipy.signal import fftconvolve

from ..errors import InputError
from ..parameters import load_parameters
from ..validate import finite_series, positive_number
from .discharges import DischargeTrial
from .follow_force import HUMAN_MUSCLES, HumanMuscle, p0_spread
from .human_units import BOUNDS as HUMAN_BOUNDS
from .human_units import SpeedBases, speed_bases
from .window_fit import WindowScores, bounded_minimize, window_mask, window_scores

#: Width (ms) of the Hann window that smooths the recorded units' instantaneous rates.
SMOOTHING_MS = 1000.0
#: Interval (ms) above which a unit counts as silent between two discharges (a pause, not a rate).
LONGEST_INTERVAL_MS = 400.0
#: Time after a recorded unit's first discharge (ms) at which the rates of the active units are read (step 2).
RECRUITMENT_READ_MS = 300.0
#: Span (ms) of recorded excitation from which E is extrapolated before the first and after the last discharge.
EXTRAPOLATION_MS = 1000.0
#: Widest threshold range (% MVC) of the unrecorded units one simulated train stands for.
GROUP_WIDTH_PERCENT_MVC = 2.0
#: Rates (Hz) the unrecorded units' discharges are kept within.
RATE_LIMITS_HZ = (4.0, 50.0)
#: Smallest rate gain with excitation (Hz per % MVC) accepted from a recording.
MIN_SLOPE_HZ_PER_PERCENT = 0.02
#: Sampling step (ms) of rates and excitation.
STEP_MS = 10.0
#: How the unrecorded units' rates are made (:func:`complete_pool`).
RATES_FROM = ("neighbours", "excitation")
#: P0 spread over the pool's ranks, (largest / smallest P0, exponent q) of ``P0 = 1 + (R - 1) rank ** q``: the
#: spread with which the pool of :data:`.follow_force.HUMAN_MUSCLES` recruits its units at the published thresholds
#: (calibrated once per muscle, docs/validation/pools_vs_recorded.md; nothing fitted to a recording).
PUBLISHED_P0_SPREAD = {"TA": (53.0, 12.0), "GM": (106.0, 12.0)}
#: Where the units' relative force comes from: the muscle's published spread (RP not fitted), or RP ** (th / 100)
#: with RP fitted as in :mod:`.human_units`.
P0_FROM = ("published", "fitted")
#: Fitted parameters: those of :mod:`.human_units` without the interval weight W (RP only with p0_from "fitted").
BOUNDS = {k: v for k, v in HUMAN_BOUNDS.items() if k != "W"}
#: Starting points of the search.
STARTS = ({"S0": 1.0, "RS": 1.5, "RP": 10.0, "delay_ms": 40.0},
          {"S0": 1.6, "RS": 1.2, "RP": 2.0, "delay_ms": 20.0})


def published_p0(muscle: str, thresholds_percent_mvc: np.ndarray) -> np.ndarray:
    """Relative P0 (1 for the first unit of the pool) of units with these recruitment thresholds (% MVC) in
    ``muscle``'s pool: the rank at which the published distribution reaches the threshold (clipped to 0..1), and
    :data:`PUBLISHED_P0_SPREAD` there."""
    if muscle not in PUBLISHED_P0_SPREAD:
        raise InputError(f"muscle must be one of {', '.join(PUBLISHED_P0_SPREAD)}, got {muscle!r}")
    rank = np.linspace(0.0, 1.0, 4001)
    th = HUMAN_MUSCLES[muscle].thresholds(rank)
    return p0_spread(np.interp(np.asarray(thresholds_percent_mvc, float), th, rank),
                     *PUBLISHED_P0_SPREAD[muscle])


def muscle_of(source: str) -> HumanMuscle:
    """The human muscle of a Caillet file from its name: gastrocnemius medialis for ``GM_*``, tibialis anterior
    otherwise (the ``TA_*`` and ``S1_*`` files)."""
    from pathlib import Path

    return HUMAN_MUSCLES["GM" if Path(source).stem.upper().startswith("GM") else "TA"]


def smoothed_rates(discharges_ms: Sequence[np.ndarray], t_ms: np.ndarray, *, smoothing_ms: float = SMOOTHING_MS,
                   longest_interval_ms: float = LONGEST_INTERVAL_MS) -> tuple[np.ndarray, np.ndarray]:
    """(rates Hz, active) of each unit at ``t_ms`` (a uniform grid, ms), shape (units, samples): the instantaneous
    rate 1000 / ISI held between two discharges closer than ``longest_interval_ms``, averaged over a Hann window
    of ``smoothing_ms`` over the unit's active time only; a unit is active where more than half the window is."""
    step = float(t_ms[1] - t_ms[0])
    raw = np.zeros((len(discharges_ms), t_ms.size))
    on = np.zeros_like(raw)
    for i, d in enumerate(discharges_ms):
        d = np.asarray(d, float)
        isi = np.diff(d)
        for a, b, q in zip(d[:-1][isi < longest_interval_ms], d[1:][isi < longest_interval_ms],
                           isi[isi < longest_interval_ms]):
            lo, hi = np.searchsorted(t_ms, (a, b))
            raw[i, lo:hi] = 1000.0 / q
            on[i, lo:hi] = 1.0
    w = np.hanning(max(int(round(smoothing_ms / step)), 3))
    w /= w.sum()
    r = fftconvolve(raw, w[None], mode="same", axes=1)
    a = fftconvolve(on, w[None], mode="same", axes=1)
    active = a > 0.5
    return np.where(active, r / np.maximum(a, 1e-12), 0.0), active


@dataclass(frozen=True)
class RateModel:
    """Onion-skin rates: ``a0 + a1 * clip(th, *threshold_range) + k * (E - th)`` Hz for a unit of threshold th
    (% MVC) at excitation E (% MVC), zero below its threshold; from ``events`` recruitment instants."""

    a0_hz: float
    a1_hz_per_percent: float
    k_hz_per_percent: float
    threshold_range: tuple[float, float]
    events: int = 0

    def at_recruitment(self, th: np.ndarray) -> np.ndarray:
        """Rate (Hz) at recruitment of units of threshold ``th`` (% MVC)."""
        return self.a0_hz + self.a1_hz_per_percent * np.clip(th, *self.threshold_range)

    def rate(self, th: float, e: np.ndarray) -> np.ndarray:
        """Rate (Hz) of a unit of threshold ``th`` at excitation ``e`` (% MVC): 0 below the threshold, else within
        :data:`RATE_LIMITS_HZ`."""
        e = np.asarray(e, float)
        r = np.clip(self.at_recruitment(np.float64(th)) + self.k_hz_per_percent * (e - th), *RATE_LIMITS_HZ)
        return np.where(e >= th, r, 0.0)


def fit_rate_model(discharges_ms: Sequence[np.ndarray], thresholds_percent_mvc: np.ndarray, t_ms: np.ndarray,
                   rates: np.ndarray, active: np.ndarray, *, until_ms: float, source: str = "discharges"
                   ) -> RateModel:
    """The :class:`RateModel` of a recording by least squares over the recruitment instants before ``until_ms``
    (ms): :data:`RECRUITMENT_READ_MS` after unit m's first discharge the force is taken to be its threshold th_m,
    so every active unit j gives ``r_j = a0 + a1 th_j + k (th_m - th_j)``.  ``rates``/``active``:
    :func:`smoothed_rates` at ``t_ms``.  InputError (naming ``source``) when fewer than 3 instants are usable or
    the slope is below :data:`MIN_SLOPE_HZ_PER_PERCENT`."""
    th = np.asarray(thresholds_percent_mvc, float)
    rows = []
    for m, d in enumerate(discharges_ms):
        if d[0] >= until_ms:
            continue
        k = min(int(np.searchsorted(t_ms, d[0] + RECRUITMENT_READ_MS)), t_ms.size - 1)
        for j in np.flatnonzero(active[:, k]):
            rows.append((th[j], th[m] - th[j], rates[j, k]))
    if len(rows) < 3:
        raise InputError(f"{source}: discharges: fewer than 3 recruitment instants to read the rates from")
    x = np.asarray(rows)
    design = np.column_stack([np.ones(len(x)), x[:, 0], x[:, 1]])
    (a0, a1, k), *_ = np.linalg.lstsq(design, x[:, 2], rcond=None)
    if not k >= MIN_SLOPE_HZ_PER_PERCENT:
        raise InputError(f"{source}: discharges: the rates do not grow with the force above threshold "
                         f"(slope {k:.3g} Hz per % MVC)")
    return RateModel(float(a0), float(a1), float(k), (float(th.min()), float(th.max())), len(rows))


def excitation(rates: np.ndarray, active: np.ndarray, thresholds_percent_mvc: np.ndarray, t_ms: np.ndarray,
               model: RateModel) -> np.ndarray:
    """E(t) (% MVC) at ``t_ms``: the mean over the active recorded units of ``th_j + (r_j - a(th_j)) / k``;
    interpolated across times when none is active, extrapolated linearly (at least 0) before the first and after
    the last active time from :data:`EXTRAPOLATION_MS` of it."""
    th = np.asarray(thresholds_percent_mvc, float)
    each = th[:, None] + (rates - model.at_recruitment(th)[:, None]) / model.k_hz_per_percent
    n = active.sum(axis=0)
    known = n > 0
    if not known.any():
        raise InputError("excitation: no recorded unit is active")
    e = np.where(known, np.where(active, each, 0.0).sum(axis=0) / np.maximum(n, 1), np.nan)
    idx = np.flatnonzero(known)
    t0, t1 = t_ms[idx[0]], t_ms[idx[-1]]
    out = np.interp(t_ms, t_ms[known], e[known])
    for near, before in ((t_ms[known] <= t0 + EXTRAPOLATION_MS, True), (t_ms[known] >= t1 - EXTRAPOLATION_MS, False)):
        tt, ee = t_ms[known][near], e[known][near]
        slope = float(np.polyfit(tt, ee, 1)[0]) if tt.size > 2 else 0.0
        if before:
            sel = t_ms < t0
            out[sel] = ee[0] + max(slope, 0.0) * (t_ms[sel] - t0)
        else:
            sel = t_ms > t1
            out[sel] = ee[-1] + min(slope, 0.0) * (t_ms[sel] - t1)
    return np.maximum(out, 0.0)


def discharges_at_rate(rate_hz: np.ndarray, t_ms: np.ndarray) -> np.ndarray:
    """Regular discharge times (ms) at ``rate_hz`` (Hz at the uniform ``t_ms``, ms; 0: silent), the first at the
    start of each active stretch."""
    r = np.asarray(rate_hz, float)
    on = np.concatenate([[0], (r > 0).astype(int), [0]])
    starts, stops = np.flatnonzero(np.diff(on) == 1), np.flatnonzero(np.diff(on) == -1)
    step = float(t_ms[1] - t_ms[0])
    out = []
    for a, b in zip(starts, stops):
        phase = np.concatenate([[0.0], np.cumsum(r[a:b]) * step / 1000.0])
        times = t_ms[a] + step * np.arange(b - a + 1)
        out.append(np.interp(np.arange(np.floor(phase[-1]) + 1.0), phase, times))
    return np.concatenate(out) if out else np.zeros(0)


def synthetic_discharges(e: np.ndarray, t_ms: np.ndarray, threshold_percent_mvc: float, model: RateModel
                         ) -> np.ndarray:
    """Discharge times (ms) of a unit of this threshold (% MVC) under excitation ``e`` (% MVC at ``t_ms``):
    regular at :meth:`RateModel.rate`, the first discharge at each recruitment."""
    return discharges_at_rate(model.rate(threshold_percent_mvc, e), t_ms)


@dataclass(frozen=True)
class RecordedActivity:
    """The recorded units in threshold order: thresholds (% MVC), smoothed rates (Hz) and active masks at ``t_ms``
    (:func:`smoothed_rates`), first and last discharges (ms); the speeds (% MVC per ms) at which recruitment rises
    and derecruitment falls through the thresholds; the median rate at derecruitment (Hz); the highest threshold
    the excitation reaches (% MVC)."""

    t_ms: np.ndarray
    thresholds: np.ndarray
    rates: np.ndarray
    active: np.ndarray
    first_ms: np.ndarray
    last_ms: np.ndarray
    rise: float
    fall: float
    last_rate_hz: float
    ceiling: float


def recorded_activity(discharges_ms: Sequence[np.ndarray], thresholds_percent_mvc: np.ndarray, t_ms: np.ndarray,
                      rates: np.ndarray, active: np.ndarray, e: np.ndarray, *, source: str = "discharges"
                      ) -> RecordedActivity:
    """:class:`RecordedActivity` of a recording; rise and fall are the slopes of the thresholds against the first
    and the last discharges (least squares over every unit); the ceiling is the higher of the highest threshold and
    the top of the excitation ``e`` (% MVC at ``t_ms``).  InputError (naming ``source``) when the thresholds do not
    rise with the first discharges or fall with the last."""
    th = np.asarray(thresholds_percent_mvc, float)
    order = np.argsort(th, kind="stable")
    first = np.array([d[0] for d in discharges_ms])[order]
    last = np.array([d[-1] for d in discharges_ms])[order]
    rise = float(np.polyfit(first, th[order], 1)[0]) if th.size > 1 else 0.0
    fall = -float(np.polyfit(last, th[order], 1)[0]) if th.size > 1 else 0.0
    if not (rise > 0 and fall > 0):
        raise InputError(f"{source}: discharges: the thresholds do not rise with the first discharges and fall "
                         f"with the last (slopes {rise:.3g}, {-fall:.3g} % MVC per ms): not a ramp contraction")
    ends = [np.flatnonzero(a)[-1] for a in active[order] if a.any()]
    last_rate = float(np.median([rates[order][i, k] for i, k in enumerate(ends)])) if ends else RATE_LIMITS_HZ[0]
    return RecordedActivity(t_ms, th[order], rates[order], active[order], first, last, rise, fall, last_rate,
                            max(float(th.max()), float(e.max())))


def neighbour_rate(threshold_percent_mvc: float, act: RecordedActivity, model: RateModel) -> np.ndarray:
    """Rate (Hz at ``act.t_ms``, 0 while silent) of an unrecorded unit of this threshold, from the recorded units
    next to it in threshold.  Between recorded units j and j+1 (fraction f of the way from th_j to th_j+1) it is
    recruited and derecruited at the times interpolated between theirs, and fires at the f-weighted mean, over
    those of the two that are active, of ``r_n(t) + k (th_n - th)`` (onion skin: k Hz per % MVC of threshold
    below).  Below the lowest (above the highest) recorded unit, its first and last discharges are shifted by the
    threshold difference divided by ``act.rise`` and ``act.fall``; above ``act.ceiling`` it is never recruited.
    Where no neighbour is active the rate runs linearly in time between the rate at recruitment
    (:meth:`RateModel.at_recruitment`), the neighbours' values and the rate at derecruitment (``act.last_rate_hz``).
    Within :data:`RATE_LIMITS_HZ`."""
    th, t = act.thresholds, act.t_ms
    x = float(threshold_percent_mvc)
    if x > act.ceiling:
        return np.zeros(t.size)
    if x <= th[0] or th.size == 1:
        n, w = [0], [1.0]
        on = act.first_ms[0] - (th[0] - x) / act.rise
        off = act.last_ms[0] + (th[0] - x) / act.fall
    elif x >= th[-1]:
        n, w = [th.size - 1], [1.0]
        on = act.first_ms[-1] + (x - th[-1]) / act.rise
        off = act.last_ms[-1] - (x - th[-1]) / act.fall
    else:
        j = int(np.clip(np.searchsorted(th, x, side="right") - 1, 0, th.size - 2))
        f = (x - th[j]) / (th[j + 1] - th[j]) if th[j + 1] > th[j] else 0.5
        n, w = [j, j + 1], [1.0 - f, f]
        on = (1.0 - f) * act.first_ms[j] + f * act.first_ms[j + 1]
        off = (1.0 - f) * act.last_ms[j] + f * act.last_ms[j + 1]
    window = (t >= on) & (t <= off)
    if off <= on or not window.any():
        return np.zeros(t.size)
    num = sum(wi * act.active[i] * (act.rates[i] + model.k_hz_per_percent * (th[i] - x)) for i, wi in zip(n, w))
    den = sum(wi * act.active[i] for i, wi in zip(n, w))
    known = window & (den > 0)
    at_t = np.concatenate([[on], t[known], [off]])
    at_r = np.concatenate([model.at_recruitment(np.array([x])), num[known] / den[known], [act.last_rate_hz]])
    return np.where(window, np.clip(np.interp(t, at_t, at_r), *RATE_LIMITS_HZ), 0.0)


def unrecorded_thresholds(pool_percent_mvc: np.ndarray, recorded_percent_mvc: np.ndarray) -> np.ndarray:
    """The pool's thresholds (% MVC) less, for each recorded threshold (from the lowest), the nearest pool
    threshold not yet taken; sorted.  More recorded units than pool units leaves none."""
    pool = sorted(np.asarray(pool_percent_mvc, float))
    for th in np.sort(np.asarray(recorded_percent_mvc, float)):
        if not pool:
            break
        pool.pop(int(np.argmin(np.abs(np.asarray(pool) - th))))
    return np.asarray(pool)


def group_thresholds(thresholds_percent_mvc: np.ndarray, width: float = GROUP_WIDTH_PERCENT_MVC
                     ) -> list[np.ndarray]:
    """Sorted thresholds (% MVC) cut into consecutive groups, each spanning at most ``width`` % MVC."""
    positive_number("group width", width)
    th = np.sort(np.asarray(thresholds_percent_mvc, float))
    groups: list[list[float]] = []
    for v in th:
        if groups and v - groups[-1][0] <= width:
            groups[-1].append(float(v))
        else:
            groups.append([float(v)])
    return [np.asarray(g) for g in groups]


@dataclass(frozen=True)
class CompletedPool:
    """A recording's units and its unrecorded ones: the recorded thresholds (% MVC) and unit forces per newton
    (``recorded``), the unrecorded units' groups (member thresholds, % MVC) with their trains' forces per newton
    (``unrecorded``, one unit per group), the excitation (% MVC at ``t_ms``) and the rate model."""

    recorded_thresholds: np.ndarray
    recorded: SpeedBases
    groups: list[np.ndarray]
    unrecorded: SpeedBases | None
    t_ms: np.ndarray
    excitation: np.ndarray
    rate_model: RateModel
    muscle: str
    group_discharges_ms: list[np.ndarray] = field(default_factory=list, repr=False)

    @property
    def n_unrecorded(self) -> int:
        """Unrecorded units the excitation recruits."""
        return sum(g.size for g in self.groups)


def complete_pool(trial: DischargeTrial, thresholds_percent_mvc: Sequence[float], recorded: SpeedBases, *,
                  until_ms: float, muscle: HumanMuscle | None = None, dt_ms: float = 0.05,
                  group_width: float = GROUP_WIDTH_PERCENT_MVC, length_mm: float = -8.0,
                  base_set: str = "CT09", simulate: Callable[..., SpeedBases] | None = None,
                  rates_from: str = "neighbours") -> CompletedPool:
    """Complete ``trial``'s recorded units (thresholds in % MVC, their forces ``recorded``) with the unrecorded
    units of ``muscle`` (default: :func:`muscle_of` the trial's file) whose thresholds the excitation reaches; the
    rate model from the recruitment instants before ``until_ms`` (ms).  Simulates one train per group at the grid
    speeds of ``recorded`` (time step ``dt_ms``); ``simulate(trains, duration_ms, speeds)`` replaces that
    simulation (returns the trains' :class:`SpeedBases` on ``recorded.t_ms``).  ``rates_from``: one of
    :data:`RATES_FROM` (``neighbours``: :func:`neighbour_rate`; ``excitation``: :meth:`RateModel.rate` under the
    excitation, recruited only where it exceeds the threshold)."""
    src = trial.source
    th = finite_series(f"{src}: recruitment thresholds", thresholds_percent_mvc)
    if th.size != len(trial.discharges_ms) or recorded.forces.shape[1] != th.size:
        raise InputError(f"{src}: recruitment thresholds: {th.size} values for {len(trial.discharges_ms)} units "
                         f"and {recorded.forces.shape[1]} unit forces")
    if np.any(th < 0) or np.any(th > 100):
        raise InputError(f"{src}: recruitment thresholds must lie in 0..100 % MVC, got {th.min():g}..{th.max():g}")
    if rates_from not in RATES_FROM:
        raise InputError(f"{src}: rates_from must be one of {', '.join(RATES_FROM)}, got {rates_from!r}")
    muscle = muscle_of(src) if muscle is None else muscle
    t = np.arange(0.0, trial.duration_ms, STEP_MS)
    rates, active = smoothed_rates(trial.discharges_ms, t)
    model = fit_rate_model(trial.discharges_ms, th, t, rates, active, until_ms=until_ms, source=src)
    e = excitation(rates, active, th, t, model)
    pool = muscle.thresholds(np.arange(muscle.motor_units) / (muscle.motor_units - 1))
    rest = unrecorded_thresholds(pool, th)
    if rates_from == "excitation":
        groups = group_thresholds(rest[rest <= e.max()], group_width)
        trains = [synthetic_discharges(e, t, float(g.mean()), model) for g in groups]
    else:
        act = recorded_activity(trial.discharges_ms, th, t, rates, active, e, source=src)
        groups = group_thresholds(rest[rest <= act.ceiling], group_width)
        trains = [discharges_at_rate(neighbour_rate(float(g.mean()), act, model), t) for g in groups]
    trains = [d[d < trial.duration_ms] for d in trains]
    keep = [i for i, d in enumerate(trains) if d.size > 1]
    groups, trains = [groups[i] for i in keep], [trains[i] for i in keep]
    bases = None
    if groups:
        if simulate is None:
            bases = speed_bases(trains, trial.duration_ms, load_parameters(base_set), speeds=recorded.speeds,
                                dt_ms=dt_ms, length_mm=length_mm)
        else:
            bases = simulate(trains, trial.duration_ms, recorded.speeds)
        if bases.t_ms.size != recorded.t_ms.size:
            raise InputError(f"{src}: unrecorded units sampled at {bases.t_ms.size} times, recorded at "
                             f"{recorded.t_ms.size}")
    return CompletedPool(th, recorded, groups, bases, recorded.t_ms, np.interp(recorded.t_ms, t, e), model,
                         muscle.name, trains)


def unit_p0(pool: CompletedPool, thresholds_percent_mvc: np.ndarray, params: dict[str, float]) -> np.ndarray:
    """Relative P0 of units of ``pool`` with these thresholds (% MVC): :func:`published_p0`, or
    ``RP ** (th / 100)`` when ``params`` holds RP (p0_from "fitted")."""
    th = np.asarray(thresholds_percent_mvc, float)
    return params["RP"] ** (th / 100.0) if "RP" in params else published_p0(pool.muscle, th)


def pool_force(pool: CompletedPool, params: dict[str, float]) -> np.ndarray:
    """The summed force (before the scale) of every unit of the completed pool under ``params`` (:data:`BOUNDS`
    names) at ``pool.t_ms``: recorded units and each group (its train's force at the group's mean threshold's
    speed, times the sum of its members' relative forces, :func:`unit_p0`)."""
    p = params
    th = pool.recorded_thresholds
    total = pool.recorded.weighted_sum(p["S0"] * p["RS"] ** (th / 100.0), unit_p0(pool, th, p))
    if pool.unrecorded is not None:
        mean = np.array([g.mean() for g in pool.groups])
        weight = np.array([np.sum(unit_p0(pool, g, p)) for g in pool.groups])
        total = total + pool.unrecorded.weighted_sum(p["S0"] * p["RS"] ** (mean / 100.0), weight)
    return np.interp(pool.t_ms - p["delay_ms"], pool.t_ms, total)


def closed_form_scale(h: np.ndarray, y: np.ndarray) -> float:
    """Least-squares ``scale`` of y ~ scale * h (no offset)."""
    hh = float(h @ h)
    return float(h @ y) / hh if hh > 0 else 0.0


@dataclass(frozen=True)
class CompletedPoolFit(WindowScores):
    """The completed pool fitted to a recording: parameters (:data:`BOUNDS`), scale (% MVC per unit of relative
    force), unrecorded units recruited; windows, NRMSE and prediction (% MVC)."""

    params: dict[str, float] = field(default_factory=dict)
    scale: float = 1.0
    n_unrecorded: int = 0

    def summary(self) -> dict[str, object]:
        """The fit as a JSON-ready dict."""
        return {**self.params, "scale": self.scale, "unrecorded_units": self.n_unrecorded, **self.scores()}


def fit_completed_pool(pool: CompletedPool, target: Sequence[float], *, calibration_ms: tuple[float, float],
                       heldout_ms: tuple[float, float], p0_from: str = "published") -> CompletedPoolFit:
    """Fit S0, RS, delay (and RP with ``p0_from`` "fitted"; one of :data:`P0_FROM`), within the priors of
    :mod:`.human_units`, and the scale to ``target`` (% MVC at ``pool.t_ms``) on ``calibration_ms``; NRMSE there
    and on ``heldout_ms`` ([start, end) ms)."""
    if p0_from not in P0_FROM:
        raise InputError(f"p0_from must be one of {', '.join(P0_FROM)}, got {p0_from!r}")
    bounds = BOUNDS if p0_from == "fitted" else {k: v for k, v in BOUNDS.items() if k != "RP"}
    t = pool.t_ms
    y = finite_series("target force", target)
    if y.size != t.size:
        raise InputError(f"target force: {y.size} samples for {t.size} times")
    cal = window_mask(t, calibration_ms, "calibration")
    window_mask(t, heldout_ms, "held-out")

    def cost(p: dict[str, float]) -> float:
        h = pool_force(pool, p)[cal]
        return float(np.sum((closed_form_scale(h, y[cal]) * h - y[cal]) ** 2))

    best = min((bounded_minimize(cost, s, bounds) for s in STARTS), key=cost)
    h = pool_force(pool, best)
    scale = closed_form_scale(h[cal], y[cal])
    if scale <= 0:
        raise InputError("the calibration found no positive unit force: the force does not follow the discharges")
    return CompletedPoolFit(**window_scores(t, y, scale * h, calibration_ms, heldout_ms), params=best, scale=scale,
                            n_unrecorded=pool.n_unrecorded)


def transferred_pool_force(source: CompletedPoolFit, target: CompletedPool) -> np.ndarray:
    """The target trial's force (% MVC at ``target.t_ms``) from its completed pool with the source's fitted values
    (scale included) unchanged."""
    return source.scale * pool_force(target, source.params)
