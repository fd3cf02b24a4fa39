"""A simulated pool's discharges against recorded ones: rates, recruitment thresholds, onion skin, Delta F, and the
acceptance criteria they are held to.

    cmp = compare_discharges(trial, model_trains_ms, model_t_ms, model_force_percent)
    cmp.summary()            # JSON-ready: recorded and model figures side by side, and each criterion's verdict

The units are not matched one to one: each side's statistics are computed on its own units (the recorded ones, and
the model units that discharge at least ``MIN_DISCHARGES`` times, as a decomposition needs a unit to fire repeatedly
to find it). Criteria: every model unit's median rate inside the recorded 5th-95th percentile range of the unit
medians; the largest model peak rate (95th percentile of a unit's instantaneous rates) at most 1.5 times the
recorded largest; the recruitment thresholds (% MVC) within Kolmogorov-Smirnov distance 0.25 of the recorded ones;
onion skin (plateau rate falling with recruitment threshold, Spearman rho < 0); Delta F reported beside the recorded
value, with each side's rate decline over the plateau (part of a trapezoid's Delta F).

Given the model units' P0 and the muscle's number of motor units, the model units a decomposition of the recording
would identify (``identification.identify``: the recording's count of the units of highest weight in it) are
compared too, beside the whole pool (``Comparison.identified``; each identified model unit weighs in the thresholds'
KS distance by the muscle units it stands for).  Units: ms, Hz, % MVC."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from . import discharge_stats as ds
from .discharges import DischargeTrial
from .identification import Identification, IdentificationModel, identify

#: A model unit counts when it discharges at least this many times in the trial.
MIN_DISCHARGES = 10
#: Acceptance limits (module docstring).
PEAK_RATIO_LIMIT = 1.5
KS_LIMIT = 0.25


@dataclass(frozen=True)
class SideStats:
    """One side's (recorded or model) statistics."""

    rates: ds.UnitRates
    thresholds_percent: np.ndarray
    onion: ds.OnionSkin
    delta_f: ds.DeltaF
    plateau_decline_hz: float
    isi_cv: np.ndarray

    def summary(self) -> dict[str, Any]:
        """JSON-ready figures."""
        return {**self.rates.summary(), "onion_skin_rho": self.onion.rho,
                "onion_skin_slope_hz_per_percent_mvc": self.onion.slope_hz_per_unit,
                "thresholds_percent_mvc_quartiles": [float(x) for x in np.nanpercentile(self.thresholds_percent,
                                                                                          [0, 25, 50, 75, 100])],
                "delta_f": self.delta_f.summary(), "plateau_rate_decline_hz": self.plateau_decline_hz,
                "isi_cv_p5_p50_p95": _percentiles(self.isi_cv)}


def _percentiles(x: np.ndarray) -> list[float] | None:
    """5th, 50th and 95th percentiles of the finite values (None when there are none)."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    return [float(v) for v in np.percentile(x, [5, 50, 95])] if x.size else None


def side_stats(trains_ms: Sequence[np.ndarray], t_ms: np.ndarray, force_percent: np.ndarray,
               plateau_ms: tuple[float, float]) -> SideStats:
    """Rates, thresholds, onion skin, Delta F, the rates' decline over the plateau (ms) and the interspike
    intervals' variation on it of one set of trains against its force (% MVC)."""
    return SideStats(ds.unit_rates(trains_ms), ds.recruitment_thresholds(trains_ms, t_ms, force_percent),
                     ds.onion_skin(trains_ms, t_ms, force_percent, plateau_ms), ds.delta_f(trains_ms),
                     ds.plateau_rate_decline_hz(trains_ms, plateau_ms), ds.isi_cv(trains_ms, plateau_ms))


def side_criteria(side: SideStats, recorded: SideStats, medians_range_hz: tuple[float, float],
                  weights: np.ndarray | None = None) -> dict[str, Any]:
    """The criteria of one set of model units (``side``) against the recorded ones; ``weights`` weigh the model
    units' thresholds in the KS distance."""
    lo, hi = medians_range_hz
    med = side.rates.median_hz[np.isfinite(side.rates.median_hz)]
    inside = (med >= lo) & (med <= hi)
    peak_ratio = float(np.nanmax(side.rates.peak_hz) / np.nanmax(recorded.rates.peak_hz))
    ks = ds.ks_distance(side.thresholds_percent, recorded.thresholds_percent, weights)
    return {"medians_inside": {"value": f"{int(inside.sum())} of {inside.size}", "range_hz": [lo, hi],
                               "fraction": float(inside.mean()) if inside.size else float("nan"),
                               "pass": bool(inside.size and inside.all())},
            "peak_ratio": {"value": peak_ratio, "limit": PEAK_RATIO_LIMIT, "pass": peak_ratio <= PEAK_RATIO_LIMIT},
            "thresholds_ks": {"value": ks, "limit": KS_LIMIT, "pass": bool(ks <= KS_LIMIT)},
            "onion_skin": {"value": side.onion.rho, "recorded": recorded.onion.rho, "pass": side.onion.holds},
            "delta_f_hz": {"value": side.delta_f.median_hz, "recorded": recorded.delta_f.median_hz}}


def _pct(values: Sequence[float]) -> list[float]:
    """Median, 5th and 95th percentiles."""
    return [float(x) for x in np.percentile(values, [50, 5, 95])]


@dataclass(frozen=True)
class IdentifiedSide:
    """The model units a decomposition would identify: which (``identification``) and their statistics
    (``stats``, one entry per identified model unit, in ``identification.units`` order); every model unit's P0
    (``p0_N``, N) and time discharging (``active_s``, s: its first to its last discharge)."""

    identification: Identification
    stats: SideStats
    p0_N: np.ndarray
    active_s: np.ndarray


@dataclass(frozen=True)
class Comparison:
    """Recorded and model statistics and the criteria's verdicts; ``identified`` (or None): the identified model
    units' statistics."""

    recorded: SideStats
    model: SideStats
    model_units: np.ndarray
    plateau_ms: tuple[float, float]
    identified: IdentifiedSide | None = None

    @property
    def medians_range_hz(self) -> tuple[float, float]:
        """The recorded 5th-95th percentile range of the unit median rates (Hz)."""
        m = self.recorded.rates.median_hz
        m = m[np.isfinite(m)]
        return float(np.percentile(m, 5)), float(np.percentile(m, 95))

    def criteria(self) -> dict[str, Any]:
        """Each criterion's measured value and verdict (the whole pool's active units)."""
        return side_criteria(self.model, self.recorded, self.medians_range_hz)

    def identified_criteria(self) -> dict[str, Any] | None:
        """The criteria of the identified model units (None without an identification)."""
        if self.identified is None:
            return None
        return side_criteria(self.identified.stats, self.recorded, self.medians_range_hz,
                             self.identified.identification.weights)

    def identified_over_seeds(self, seeds: Sequence[int] = range(20)) -> dict[str, Any] | None:
        """How the identified units' thresholds KS distance and share of medians inside the recorded range vary
        with the identification's seed (median and 5th-95th percentiles over ``seeds``), and the thresholds of the
        units identified over all ``seeds`` together against the recorded ones (``thresholds_ks_expected``);
        None without an identification.

        The identification drawn with one seed is one possible sample of the pool, as the recording is one sample
        of the muscle: two small samples differ by chance (two samples of 20 units from one distribution are a KS
        distance of 0.25 or more apart more than half the time).  The identifications over every seed give the
        distribution of thresholds a decomposition of this pool would find, and ``thresholds_ks_expected``
        holds the recording against it, with the distance a recording of as many units drawn from that very
        distribution would show by chance (median and 95th percentile)."""
        if self.identified is None:
            return None
        base = self.identified.identification
        active = np.zeros(base.copies.size, bool)
        active[self.model_units] = True
        where = {int(u): k for k, u in enumerate(self.model_units)}
        lo, hi = self.medians_range_hz
        ks, inside = [], []
        total = np.zeros(self.model_units.size)
        for seed in seeds:
            found = identify(self.identified.p0_N, active, base.count, motor_units=base.motor_units,
                             model=replace(base.model, seed=int(seed)), active_s=self.identified.active_s)
            k = np.array([where[int(u)] for u in found.units], int)
            total[k] += found.weights
            ks.append(ds.ks_distance(self.model.thresholds_percent[k], self.recorded.thresholds_percent,
                                     found.weights))
            med = self.model.rates.median_hz[k]
            inside.append(float(np.mean((med >= lo) & (med <= hi))))
        thr = self.model.thresholds_percent
        expected = ds.ks_distance(thr, self.recorded.thresholds_percent, total)
        n_rec = int(np.isfinite(self.recorded.thresholds_percent).sum())
        return {"seeds": [int(x) for x in seeds], "thresholds_ks_median_p5_p95": _pct(ks),
                "thresholds_ks_pass_fraction": float(np.mean(np.array(ks) <= KS_LIMIT)),
                "medians_inside_fraction_median_p5_p95": _pct(inside),
                "thresholds_ks_expected": {"value": expected, "limit": KS_LIMIT, "pass": bool(expected <= KS_LIMIT),
                                           "recorded_units": n_rec,
                                           "by_chance_p50_p95": ds.ks_sampling_percentiles(thr, total, n_rec)}}

    def summary(self) -> dict[str, Any]:
        """JSON-ready: both sides and the criteria (and the identified units' beside them, when given)."""
        out = {"plateau_ms": list(self.plateau_ms), "model_units": int(self.model_units.size),
               "recorded": self.recorded.summary(), "model": self.model.summary(), "criteria": self.criteria()}
        if self.identified is not None:
            ident = self.identified.identification
            out["identified"] = {**self.identified.stats.summary(), "identification": ident.summary(),
                                 "criteria": self.identified_criteria(), "over_seeds": self.identified_over_seeds()}
        return out


def discharging_s(train_ms: Sequence[float] | np.ndarray) -> float:
    """Time from a train's first to its last discharge (s; 0 with fewer than two)."""
    t = np.asarray(train_ms, float)
    return float(t.max() - t.min()) / 1000.0 if t.size > 1 else 0.0


def compare_discharges(trial: DischargeTrial, model_trains_ms: Sequence[np.ndarray], model_t_ms: np.ndarray,
                       model_force_percent: np.ndarray, *, p0_N: Sequence[float] | np.ndarray | None = None,
                       motor_units: int | None = None,
                       identification: IdentificationModel | None = None) -> Comparison:
    """Statistics of the recorded trial and of the model trains (ms, the trial's clock) against their own forces
    (% MVC), on the recorded force's plateau (``discharge_stats.plateau_window_ms``).  With ``p0_N`` (every model
    unit's P0, N) and ``motor_units`` (the muscle's), also those of the model units a decomposition would identify
    (``identification``'s parameters and seed, default ``IdentificationModel()``; each unit's time discharging,
    its first to its last discharge, in ``identify``'s ``active_s``), as many muscle units as the trial has."""
    plateau = ds.plateau_window_ms(trial.force_t_ms, trial.force_percent_mvc)
    units = np.array([i for i, s in enumerate(model_trains_ms) if len(s) >= MIN_DISCHARGES], int)
    model = [np.asarray(model_trains_ms[i], float) for i in units]
    ident = None
    if p0_N is not None or motor_units is not None:
        if p0_N is None or motor_units is None:
            raise InputError("compare_discharges: give both p0_N and motor_units to compare the identified units")
        active = np.zeros(len(model_trains_ms), bool)
        active[units] = True
        count = sum(1 for d in trial.discharges_ms if len(d))
        active_s = np.array([discharging_s(s) for s in model_trains_ms])
        found = identify(p0_N, active, count, motor_units=motor_units, model=identification, active_s=active_s)
        trains = [np.asarray(model_trains_ms[i], float) for i in found.units]
        ident = IdentifiedSide(found, side_stats(trains, model_t_ms, model_force_percent, plateau),
                               np.asarray(p0_N, float), active_s)
    return Comparison(side_stats(trial.discharges_ms, trial.force_t_ms, trial.force_percent_mvc, plateau),
                      side_stats(model, model_t_ms, model_force_percent, plateau), units, plateau, ident)
