"""The twitch-sum reference: force from recorded discharges as a sum of Fuglevand-style twitches, fitted on a
calibration window.

Model (Fuglevand, Winter & Patla 1993, J Neurophysiol 70:2470): unit i at position x_i in [0, 1] (its recruitment
rank, lowest threshold 0) has peak twitch force P_i = RP ** x_i and contraction time T_i = TL * RT ** -x_i (ms);
each discharge adds the twitch f(t) = gain_k * P_i * (t / T_i) * exp(1 - t / T_i), whose amplitude gain_k depends on
the normalised instantaneous rate T_i / ISI_k (ISI_k: the interval before discharge k): 1 up to 0.4, above it
``(1 - exp(-2 r^3)) / r`` relative to its value at r = 0.4, so that the mean force of a train, which grows as gain x r,
follows the sigmoid force-rate relation of Fuglevand et al. (steeper above 0.4, saturating at high rates).
The predicted force is ``scale * sum_i force_i(t - delay) + offset``.

Fitted on the calibration window (:func:`fit_twitch_sum`): RP (1..1000), TL (20..200 ms), RT (1..5) and the delay
(0..200 ms) by Nelder-Mead on bounded transforms; scale and offset in closed form (linear least squares).
Units: ms; force in the target's unit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.signal import lfilter

from ..errors import InputError
from ..validate import finite_series
from .window_fit import WindowScores, bounded_minimize, linear_scale_offset, window_mask, window_scores

#: Normalised instantaneous rate (T / ISI) below which a twitch keeps its full amplitude (Fuglevand et al. 1993).
LINEAR_RATE = 0.4
#: Bounds of the fitted parameters: peak-force range, longest contraction time (ms), contraction-time range, delay
#: (ms).
BOUNDS = {"RP": (1.0, 1000.0, True), "TL_ms": (20.0, 200.0, True), "RT": (1.0, 5.0, True),
          "delay_ms": (0.0, 200.0, False)}

#: Starting points of the search (RP, TL ms, RT, delay ms): a wide and a narrow force range.
STARTS = ((30.0, 90.0, 3.0, 40.0), (3.0, 60.0, 1.5, 20.0))


def rate_gain(t_over_isi: np.ndarray) -> np.ndarray:
    """The twitch amplitude factor (1/1) at normalised instantaneous rates T / ISI (1/1): 1 up to 0.4, then
    (1 - exp(-2 r^3)) / r relative to its value at 0.4 (Fuglevand et al. 1993)."""
    r = np.maximum(np.asarray(t_over_isi, float), 1e-12)
    ref = (1.0 - np.exp(-2.0 * LINEAR_RATE ** 3)) / LINEAR_RATE
    return np.where(r <= LINEAR_RATE, 1.0, (1.0 - np.exp(-2.0 * r ** 3)) / r / ref)


def unit_twitch_force(discharges_ms: np.ndarray, t_ms: np.ndarray, contraction_ms: float) -> np.ndarray:
    """One unit's summed twitches of peak 1 (before the rate gain) at ``t_ms`` (a uniform grid, ms) for
    ``discharges_ms`` (ms, increasing) and contraction time ``contraction_ms`` (ms)."""
    step = float(t_ms[1] - t_ms[0])
    d = np.asarray(discharges_ms, float)
    isi = np.diff(d, prepend=-np.inf)
    amp = rate_gain(contraction_ms / isi)
    pos = (d - t_ms[0]) / step
    keep = (pos >= 0) & (pos < t_ms.size - 1)
    lo = np.floor(pos[keep]).astype(int)
    frac = pos[keep] - lo
    impulses = np.zeros(t_ms.size)
    np.add.at(impulses, lo, amp[keep] * (1.0 - frac))
    np.add.at(impulses, lo + 1, amp[keep] * frac)
    a = np.exp(-step / contraction_ms)
    # the impulse response n a^n * (step e / T) is (t / T) exp(1 - t / T) sampled at t = n step
    return lfilter([0.0, a * step * np.e / contraction_ms], [1.0, -2.0 * a, a * a], impulses)


def twitch_sum_basis(discharges_ms: Sequence[np.ndarray], t_ms: np.ndarray, x: np.ndarray, rp: float, tl_ms: float,
                     rt: float, delay_ms: float = 0.0) -> np.ndarray:
    """The summed force (peak-twitch units) of every unit at ``t_ms`` (ms): unit i at position ``x[i]`` (0..1) with
    P_i = rp ** x_i, T_i = tl_ms * rt ** -x_i (ms), its discharges delayed by ``delay_ms`` (ms)."""
    out = np.zeros(t_ms.size)
    for d, xi in zip(discharges_ms, x):
        out += rp ** xi * unit_twitch_force(np.asarray(d, float) + delay_ms, t_ms, tl_ms * rt ** -xi)
    return out


@dataclass(frozen=True)
class TwitchSumFit(WindowScores):
    """A fitted twitch sum: parameters (module docstring), and its windows, NRMSE and prediction."""

    rp: float = 1.0
    tl_ms: float = 100.0
    rt: float = 1.0
    delay_ms: float = 0.0
    scale: float = 1.0
    offset: float = 0.0

    def summary(self) -> dict[str, float | list[float]]:
        """The fit as a JSON-ready dict."""
        return {"RP": self.rp, "TL_ms": self.tl_ms, "RT": self.rt, "delay_ms": self.delay_ms, "scale": self.scale,
                "offset": self.offset, **self.scores()}


def fit_twitch_sum(discharges_ms: Sequence[np.ndarray], t_ms: np.ndarray, x: Sequence[float], target: Sequence[float],
                   *, calibration_ms: tuple[float, float], heldout_ms: tuple[float, float],
                   starts: Sequence[tuple[float, float, float, float]] = STARTS) -> TwitchSumFit:
    """Fit RP, TL, RT, delay, scale and offset (module docstring) to ``target`` (sampled at the uniform ``t_ms``,
    ms) on ``calibration_ms`` from each of ``starts`` (RP, TL, RT, delay), keeping the lowest calibration error;
    NRMSE there and on ``heldout_ms`` ([start, end) ms)."""
    t = finite_series("t_ms", t_ms)
    y = finite_series("target force", target)
    xs = finite_series("unit positions", x)
    if y.size != t.size or xs.size != len(discharges_ms):
        raise InputError(f"target ({y.size}) must match t ({t.size}) and positions ({xs.size}) the units "
                         f"({len(discharges_ms)})")
    if np.any((xs < 0) | (xs > 1)):
        raise InputError("unit positions must lie in [0, 1]")
    cal = window_mask(t, calibration_ms, "calibration")
    window_mask(t, heldout_ms, "held-out")

    def cost(p: dict[str, float]) -> float:
        h = twitch_sum_basis(discharges_ms, t, xs, p["RP"], p["TL_ms"], p["RT"], p["delay_ms"])[cal]
        scale, offset = linear_scale_offset(h, y[cal])
        return float(np.sum((scale * h + offset - y[cal]) ** 2))

    fits = [bounded_minimize(cost, dict(zip(BOUNDS, s)), BOUNDS) for s in starts]
    best = min(fits, key=cost)
    rp, tl, rt, delay = (best[n] for n in BOUNDS)
    h = twitch_sum_basis(discharges_ms, t, xs, rp, tl, rt, delay)
    scale, offset = linear_scale_offset(h[cal], y[cal])
    return TwitchSumFit(**window_scores(t, y, scale * h + offset, calibration_ms, heldout_ms), rp=rp, tl_ms=tl,
                        rt=rt, delay_ms=delay, scale=scale, offset=offset)
