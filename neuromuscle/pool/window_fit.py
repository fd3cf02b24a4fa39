"""Helpers shared by the fits of force from recorded discharges: calibration and held-out windows, the closed-form
scale and offset, and a bounded Nelder-Mead search (each parameter mapped from its [low, high] range, linear or
logarithmic, onto an unbounded variable).  Units: whatever the caller's are (ms for windows)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy.optimize import minimize

from ..analysis.metrics import nrmse_percent
from ..errors import InputError


@dataclass(frozen=True)
class WindowScores:
    """A prediction (the target's unit) over the whole trial and its NRMSE (% of the window's recorded range) on
    the calibration and held-out windows ([start, end) ms)."""

    calibration_ms: tuple[float, float]
    heldout_ms: tuple[float, float]
    nrmse_calibration_percent: float
    nrmse_heldout_percent: float
    predicted: np.ndarray = field(repr=False)

    def scores(self) -> dict[str, float | list[float]]:
        """Windows and NRMSE as a JSON-ready dict."""
        return {"calibration_ms": list(self.calibration_ms), "heldout_ms": list(self.heldout_ms),
                "nrmse_calibration_percent": self.nrmse_calibration_percent,
                "nrmse_heldout_percent": self.nrmse_heldout_percent}


def window_scores(t_ms: np.ndarray, target: np.ndarray, predicted: np.ndarray, calibration_ms: tuple[float, float],
                  heldout_ms: tuple[float, float]) -> dict[str, object]:
    """The :class:`WindowScores` fields of ``predicted`` against ``target`` (sampled at ``t_ms``, ms)."""
    cal = window_mask(t_ms, calibration_ms, "calibration")
    held = window_mask(t_ms, heldout_ms, "held-out")
    return {"calibration_ms": tuple(calibration_ms), "heldout_ms": tuple(heldout_ms),
            "nrmse_calibration_percent": nrmse_percent(target[cal], predicted[cal]),
            "nrmse_heldout_percent": nrmse_percent(target[held], predicted[held]), "predicted": predicted}


def window_mask(t_ms: np.ndarray, window: tuple[float, float], name: str) -> np.ndarray:
    """Samples of ``t_ms`` (ms) in ``window`` [start, end) (ms); at least 10, else InputError naming ``name``."""
    a, b = (float(v) for v in window)
    sel = (t_ms >= a) & (t_ms < b)
    if not a < b or sel.sum() < 10:
        raise InputError(f"{name} window {a:g}..{b:g} ms holds fewer than 10 samples of 0..{t_ms[-1]:g} ms")
    return sel


def linear_scale_offset(h: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares ``scale, offset`` of y ~ scale * h + offset."""
    a = np.column_stack([h, np.ones_like(h)])
    (scale, offset), *_ = np.linalg.lstsq(a, y, rcond=None)
    return float(scale), float(offset)


def _fraction(v: float, lo: float, hi: float, log: bool) -> float:
    return (np.log(v) - np.log(lo)) / (np.log(hi) - np.log(lo)) if log else (v - lo) / (hi - lo)


def _value(f: float, lo: float, hi: float, log: bool) -> float:
    return float(np.exp(np.log(lo) + f * (np.log(hi) - np.log(lo)))) if log else float(lo + f * (hi - lo))


def bounded_minimize(cost: Callable[[dict[str, float]], float], start: Mapping[str, float],
                     bounds: Mapping[str, tuple[float, float, bool]], max_evaluations: int = 600
                     ) -> dict[str, float]:
    """Minimise ``cost(params)`` over the named parameters, each within ``bounds[name] = (low, high, log)``, by
    Nelder-Mead from ``start``; returns the best parameters."""
    names: Sequence[str] = tuple(bounds)

    def params(z: np.ndarray) -> dict[str, float]:
        return {n: _value(0.5 * (np.sin(zi) + 1.0), *bounds[n]) for zi, n in zip(z, names)}

    z0 = np.array([np.arcsin(np.clip(2.0 * _fraction(start[n], *bounds[n]) - 1.0, -1.0, 1.0)) for n in names])
    res = minimize(lambda z: cost(params(z)), z0, method="Nelder-Mead",
                   options={"xatol": 1e-3, "fatol": 1e-9, "maxfev": max_evaluations})
    return params(res.x)
