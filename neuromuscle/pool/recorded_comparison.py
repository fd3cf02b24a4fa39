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
value, with each side's rate decline over the plateau (part of a trapezoid's Delta F). Units: ms, Hz, % MVC."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from . import discharge_stats as ds
from .discharges import DischargeTrial

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

    def summary(self) -> dict[str, Any]:
        """JSON-ready figures."""
        return {**self.rates.summary(), "onion_skin_rho": self.onion.rho,
                "onion_skin_slope_hz_per_percent_mvc": self.onion.slope_hz_per_unit,
                "thresholds_percent_mvc_quartiles": [float(x) for x in np.nanpercentile(self.thresholds_percent,
                                                                                          [0, 25, 50, 75, 100])],
                "delta_f": self.delta_f.summary(), "plateau_rate_decline_hz": self.plateau_decline_hz}


def side_stats(trains_ms: Sequence[np.ndarray], t_ms: np.ndarray, force_percent: np.ndarray,
               plateau_ms: tuple[float, float]) -> SideStats:
    """Rates, thresholds, onion skin, Delta F and the rates' decline over the plateau (ms) of one set of trains
    against its force (% MVC)."""
    return SideStats(ds.unit_rates(trains_ms), ds.recruitment_thresholds(trains_ms, t_ms, force_percent),
                     ds.onion_skin(trains_ms, t_ms, force_percent, plateau_ms), ds.delta_f(trains_ms),
                     ds.plateau_rate_decline_hz(trains_ms, plateau_ms))


@dataclass(frozen=True)
class Comparison:
    """Recorded and model statistics and the criteria's verdicts."""

    recorded: SideStats
    model: SideStats
    model_units: np.ndarray
    plateau_ms: tuple[float, float]

    @property
    def medians_range_hz(self) -> tuple[float, float]:
        """The recorded 5th-95th percentile range of the unit median rates (Hz)."""
        m = self.recorded.rates.median_hz
        m = m[np.isfinite(m)]
        return float(np.percentile(m, 5)), float(np.percentile(m, 95))

    def criteria(self) -> dict[str, Any]:
        """Each criterion's measured value and verdict."""
        lo, hi = self.medians_range_hz
        med = self.model.rates.median_hz[np.isfinite(self.model.rates.median_hz)]
        inside = (med >= lo) & (med <= hi)
        peak_ratio = float(np.nanmax(self.model.rates.peak_hz) / np.nanmax(self.recorded.rates.peak_hz))
        ks = ds.ks_distance(self.model.thresholds_percent, self.recorded.thresholds_percent)
        return {"medians_inside": {"value": f"{int(inside.sum())} of {inside.size}", "range_hz": [lo, hi],
                                   "fraction": float(inside.mean()) if inside.size else float("nan"),
                                   "pass": bool(inside.size and inside.all())},
                "peak_ratio": {"value": peak_ratio, "limit": PEAK_RATIO_LIMIT, "pass": peak_ratio <= PEAK_RATIO_LIMIT},
                "thresholds_ks": {"value": ks, "limit": KS_LIMIT, "pass": bool(ks <= KS_LIMIT)},
                "onion_skin": {"value": self.model.onion.rho, "recorded": self.recorded.onion.rho,
                               "pass": self.model.onion.holds},
                "delta_f_hz": {"value": self.model.delta_f.median_hz, "recorded": self.recorded.delta_f.median_hz}}

    def summary(self) -> dict[str, Any]:
        """JSON-ready: both sides and the criteria."""
        return {"plateau_ms": list(self.plateau_ms), "model_units": int(self.model_units.size),
                "recorded": self.recorded.summary(), "model": self.model.summary(), "criteria": self.criteria()}


def compare_discharges(trial: DischargeTrial, model_trains_ms: Sequence[np.ndarray], model_t_ms: np.ndarray,
                       model_force_percent: np.ndarray) -> Comparison:
    """Statistics of the recorded trial and of the model trains (ms, the trial's clock) against their own forces
    (% MVC), on the recorded force's plateau (``discharge_stats.plateau_window_ms``)."""
    plateau = ds.plateau_window_ms(trial.force_t_ms, trial.force_percent_mvc)
    units = np.array([i for i, s in enumerate(model_trains_ms) if len(s) >= MIN_DISCHARGES], int)
    model = [np.asarray(model_trains_ms[i], float) for i in units]
    return Comparison(side_stats(trial.discharges_ms, trial.force_t_ms, trial.force_percent_mvc, plateau),
                      side_stats(model, model_t_ms, model_force_percent, plateau), units, plateau)
