"""What a motor-unit physiologist measures on discharge trains and force: rates, thresholds, onion skin, Delta F.

The same functions run on decomposed human discharges and on a simulated pool, so the two compare like with
like (``networks/pool_vs_recorded.py``):

    rates = unit_rates(trains_ms)                                 # per-unit median and peak (95th pct) rate, Hz
    thr = recruitment_thresholds(trains_ms, t_ms, force)          # force (% MVC) at each unit's first discharge
    onion = onion_skin(trains_ms, t_ms, force, plateau_ms)        # earlier-recruited units faster on the plateau?
    df = delta_f(trains_ms)                                       # paired-unit Delta F (Gorassini et al. 2002)
    cv = isi_cv(trains_ms, plateau_ms)                            # each unit's discharge irregularity on the plateau
    ks_distance(a, b)                                             # two-sample Kolmogorov-Smirnov distance

Instantaneous rate: 1 / ISI for the intervals shorter than ``MAX_ISI_MS`` (longer ones separate firing episodes,
as in the decomposition literature).  A unit's peak rate is the 95th percentile of its instantaneous rates
(robust to the odd doublet or missed discharge of a decomposition).  Smoothed rate (for Delta F): the
instantaneous rate held between discharges on a 1-ms grid, filtered by a 2-s Hann window (Hassan et al. 2020,
J Neurophysiol 124:1165, in the form of Afsharipour et al. 2020).  Units: ms, Hz, % MVC.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..errors import InputError

#: Interspike intervals (ms) longer than this separate firing episodes and give no instantaneous rate.
MAX_ISI_MS = 500.0
#: Smoothing window (ms) of the rate profiles used for Delta F.
SMOOTHING_MS = 2000.0
#: Paired-unit criteria (Gorassini et al. 2002; Stephenson & Maluf 2011; Hassan et al. 2020): the test unit is
#: recruited at least this long (ms) after the reference unit ...
MIN_RECRUITMENT_LAG_MS = 1000.0
#: ... the smoothed rates of the two units correlate at least this much while both fire ...
MIN_RATE_CORRELATION = 0.7
#: ... and the reference unit's rate changes at least this much (Hz) while the test unit fires.
MIN_REFERENCE_MODULATION_HZ = 0.5
#: Recorded human motor units (Hz): the 5th and 95th percentiles of the unit median rates, over the 291 units of
#: the eight HD-EMG decompositions of Caillet et al. 2022, 2023 (tibialis anterior and gastrocnemius medialis,
#: trapezoidal isometric contractions at 30-50 % MVC), and the largest unit peak (95th percentile) rate among them.
HUMAN_MEDIAN_RATES_HZ = (10.1, 23.4)
HUMAN_PEAK_RATE_HZ = 46.1
#: The same units' interspike-interval coefficients of variation on the plateaus (``isi_cv``): median and 5th-95th
#: percentiles.
HUMAN_ISI_CV_MEDIAN = 0.165
HUMAN_ISI_CV = (0.108, 0.421)
#: Fewest plateau intervals for an interspike-interval coefficient of variation.
MIN_CV_INTERVALS = 10


def _trains(trains_ms: Sequence[Sequence[float]]) -> list[np.ndarray]:
    out = [np.asarray(t, float) for t in trains_ms]
    for i, t in enumerate(out):
        if t.ndim != 1 or np.any(np.diff(t) <= 0) or not np.all(np.isfinite(t)):
            raise InputError(f"discharge train {i} must be finite, 1-D and strictly increasing (ms)")
    return out


def instantaneous_rates_hz(train_ms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(times ms, rates Hz): 1 / ISI at the second discharge of every interval shorter than MAX_ISI_MS."""
    isi = np.diff(train_ms)
    keep = isi < MAX_ISI_MS
    return train_ms[1:][keep], 1000.0 / isi[keep]


@dataclass(frozen=True)
class UnitRates:
    """Per-unit median and peak (95th percentile) instantaneous rates (Hz); NaN for a unit with no interval."""

    median_hz: np.ndarray
    peak_hz: np.ndarray

    def summary(self) -> dict[str, float]:
        """Percentiles over the units (the recorded file's reference range is the 5th-95th of the medians)."""
        m, p = self.median_hz[np.isfinite(self.median_hz)], self.peak_hz[np.isfinite(self.peak_hz)]
        if not m.size:
            return {"units": 0}
        return {"units": int(m.size), "median_of_medians_hz": float(np.median(m)),
                "medians_p5_hz": float(np.percentile(m, 5)), "medians_p95_hz": float(np.percentile(m, 95)),
                "medians_min_hz": float(m.min()), "medians_max_hz": float(m.max()), "peak_max_hz": float(p.max())}


def unit_rates(trains_ms: Sequence[Sequence[float]]) -> UnitRates:
    """Median and peak (95th percentile) instantaneous rate of every unit (Hz)."""
    med, peak = [], []
    for t in _trains(trains_ms):
        _, r = instantaneous_rates_hz(t)
        med.append(float(np.median(r)) if r.size else np.nan)
        peak.append(float(np.percentile(r, 95)) if r.size else np.nan)
    return UnitRates(np.array(med), np.array(peak))


def inside_human_range(rates: UnitRates) -> float:
    """The share of the units with a median rate whose median lies within ``HUMAN_MEDIAN_RATES_HZ``."""
    m = rates.median_hz[np.isfinite(rates.median_hz)]
    lo, hi = HUMAN_MEDIAN_RATES_HZ
    return float(np.mean((m >= lo) & (m <= hi))) if m.size else float("nan")


def isi_cv(trains_ms: Sequence[Sequence[float]], window_ms: tuple[float, float]) -> np.ndarray:
    """Each unit's interspike-interval coefficient of variation (1: standard deviation / mean) over its intervals
    within ``window_ms`` (ms, e.g. the plateau) shorter than MAX_ISI_MS; NaN for a unit with fewer than
    MIN_CV_INTERVALS of them."""
    a, b = window_ms
    out = []
    for t in _trains(trains_ms):
        isi = np.diff(t[(t >= a) & (t <= b)])
        isi = isi[isi < MAX_ISI_MS]
        out.append(float(np.std(isi) / np.mean(isi)) if isi.size >= MIN_CV_INTERVALS else np.nan)
    return np.array(out)


def recruitment_thresholds(trains_ms: Sequence[Sequence[float]], t_ms: np.ndarray, force: np.ndarray
                           ) -> np.ndarray:
    """Force (the unit of ``force``, e.g. % MVC) at each unit's first discharge; NaN for a silent unit."""
    return np.array([np.interp(t[0], t_ms, force) if t.size else np.nan for t in _trains(trains_ms)])


def derecruitment_thresholds(trains_ms: Sequence[Sequence[float]], t_ms: np.ndarray, force: np.ndarray
                             ) -> np.ndarray:
    """Force at each unit's last discharge; NaN for a silent unit."""
    return np.array([np.interp(t[-1], t_ms, force) if t.size else np.nan for t in _trains(trains_ms)])


def spearman(x: np.ndarray, y: np.ndarray) -> float:
    """Spearman rank correlation of x and y (NaN pairs dropped; NaN if fewer than 3 pairs)."""
    from scipy.stats import spearmanr

    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3:
        return float("nan")
    return float(spearmanr(x[ok], y[ok]).statistic)


@dataclass(frozen=True)
class OnionSkin:
    """Plateau rate (Hz, median over the plateau window) against recruitment threshold: ``rho`` is their Spearman
    correlation, negative when earlier-recruited units fire faster (De Luca & Erim 1994's onion skin)."""

    thresholds: np.ndarray
    plateau_rate_hz: np.ndarray
    rho: float
    slope_hz_per_unit: float

    @property
    def holds(self) -> bool:
        """Earlier-recruited units fire faster on the plateau (rho < 0)."""
        return bool(self.rho < 0.0)


def onion_skin(trains_ms: Sequence[Sequence[float]], t_ms: np.ndarray, force: np.ndarray,
               plateau_ms: tuple[float, float]) -> OnionSkin:
    """Each unit's median instantaneous rate within ``plateau_ms`` (ms window) against its recruitment threshold
    (force at first discharge); units silent on the plateau are left out."""
    trains = _trains(trains_ms)
    thr = recruitment_thresholds(trains, t_ms, force)
    a, b = plateau_ms
    rate = []
    for t in trains:
        tt, r = instantaneous_rates_hz(t)
        sel = (tt >= a) & (tt < b)
        rate.append(float(np.median(r[sel])) if sel.sum() >= 3 else np.nan)
    rate_a = np.array(rate)
    ok = np.isfinite(thr) & np.isfinite(rate_a)
    slope = float(np.polyfit(thr[ok], rate_a[ok], 1)[0]) if ok.sum() >= 3 else float("nan")
    return OnionSkin(thr, rate_a, spearman(thr, rate_a), slope)


def plateau_window_ms(t_ms: np.ndarray, force: np.ndarray, fraction: float = 0.9) -> tuple[float, float]:
    """(first, last) time (ms) at which ``force`` is at least ``fraction`` of its 99th percentile: the plateau of
    a trapezoidal contraction."""
    top = float(np.percentile(force, 99.0))
    above = np.flatnonzero(force >= fraction * top)
    if not above.size:
        raise InputError("the force never reaches its plateau")
    return float(t_ms[above[0]]), float(t_ms[above[-1]])


def plateau_rate_decline_hz(trains_ms: Sequence[Sequence[float]], plateau_ms: tuple[float, float],
                            edge_ms: float = 3000.0, min_discharges: int = 10) -> float:
    """Median over the units firing through the plateau (at least ``min_discharges`` discharges in each edge) of
    the rate (Hz; 1 / median interval) over its first ``edge_ms`` (ms) minus that over its last: the slow decline
    of human discharge rates at a constant force (Kernell & Monster 1982 in the cat under constant current), part of
    what the paired-unit Delta F of a trapezoid measures.  NaN when no unit qualifies."""
    p0, p1 = plateau_ms
    out = []
    for s in _trains(trains_ms):
        a = s[(s >= p0) & (s < p0 + edge_ms)]
        b = s[(s > p1 - edge_ms) & (s <= p1)]
        if a.size >= min_discharges and b.size >= min_discharges:
            out.append(1000.0 / np.median(np.diff(a)) - 1000.0 / np.median(np.diff(b)))
    return float(np.median(out)) if out else float("nan")


def smoothed_rate_hz(train_ms: np.ndarray, grid_ms: np.ndarray) -> np.ndarray:
    """The unit's rate on ``grid_ms`` (1-ms grid): the instantaneous rate held from each discharge to the next,
    filtered by a SMOOTHING_MS Hann window; NaN outside the unit's firing (first to last discharge) and in gaps
    longer than MAX_ISI_MS."""
    out = np.full(grid_ms.size, np.nan)
    if train_ms.size < 2:
        return out
    idx = np.searchsorted(train_ms, grid_ms, side="right") - 1
    inside = (idx >= 0) & (idx < train_ms.size - 1)
    isi = np.diff(train_ms)
    raw = np.zeros(grid_ms.size)
    raw[inside] = 1000.0 / isi[idx[inside]]
    valid = inside.copy()
    valid[inside] = isi[idx[inside]] < MAX_ISI_MS
    raw[~valid] = 0.0
    step = float(grid_ms[1] - grid_ms[0]) if grid_ms.size > 1 else 1.0
    w = np.hanning(max(int(round(SMOOTHING_MS / step)), 3))
    # "full" then the centred grid-length part: "same" returns the window's length when it is the longer
    lead = (w.size - 1) // 2
    num = np.convolve(raw, w, mode="full")[lead:lead + grid_ms.size]
    den = np.convolve(valid.astype(float), w, mode="full")[lead:lead + grid_ms.size]
    with np.errstate(invalid="ignore", divide="ignore"):
        sm = num / den
    out[valid] = sm[valid]
    return out


@dataclass(frozen=True)
class DeltaF:
    """Paired-unit Delta F: ``per_test_unit_hz`` (unit index -> mean Delta F over its valid reference units, Hz),
    ``pairs`` the number of valid (reference, test) pairs."""

    per_test_unit_hz: dict[int, float]
    pairs: int

    @property
    def median_hz(self) -> float:
        """Median over the test units (NaN when no pair qualified)."""
        v = list(self.per_test_unit_hz.values())
        return float(np.median(v)) if v else float("nan")

    def summary(self) -> dict[str, float | int]:
        """JSON-ready: median, quartiles, numbers of test units and pairs."""
        v = np.array(list(self.per_test_unit_hz.values()))
        if not v.size:
            return {"median_hz": float("nan"), "test_units": 0, "pairs": 0}
        return {"median_hz": float(np.median(v)), "p25_hz": float(np.percentile(v, 25)),
                "p75_hz": float(np.percentile(v, 75)), "test_units": int(v.size), "pairs": int(self.pairs)}


def delta_f(trains_ms: Sequence[Sequence[float]], max_pairs_per_test: int | None = None) -> DeltaF:
    """Paired-unit Delta F (Gorassini, Yang, Eken & Bennett 2002): for a test unit and an earlier-recruited
    reference unit, the reference's smoothed rate at the test unit's recruitment minus that at its derecruitment.
    A pair counts when the test unit is recruited MIN_RECRUITMENT_LAG_MS after the reference, the reference fires
    throughout the test unit's firing, their smoothed rates correlate (r >= MIN_RATE_CORRELATION) and the
    reference's rate changes by MIN_REFERENCE_MODULATION_HZ or more meanwhile.  ``max_pairs_per_test``: only that
    many references, those recruited closest before the test unit (None: all)."""
    trains = [t for t in _trains(trains_ms)]
    active = [i for i, t in enumerate(trains) if t.size >= 3]
    if not active:
        return DeltaF({}, 0)
    lo = min(trains[i][0] for i in active)
    hi = max(trains[i][-1] for i in active)
    grid = np.arange(np.floor(lo), np.ceil(hi) + 1.0, 1.0)
    smooth = {i: smoothed_rate_hz(trains[i], grid) for i in active}
    per_test: dict[int, float] = {}
    pairs = 0
    for test in active:
        on, off = trains[test][0], trains[test][-1]
        refs = [r for r in active if r != test and trains[r][0] <= on - MIN_RECRUITMENT_LAG_MS
                and trains[r][-1] >= off]
        refs.sort(key=lambda r: -trains[r][0])
        if max_pairs_per_test is not None:
            refs = refs[:max_pairs_per_test]
        values = []
        k_on, k_off = int(round(on - grid[0])), int(round(off - grid[0]))
        for ref in refs:
            fr, ft = smooth[ref][k_on:k_off + 1], smooth[test][k_on:k_off + 1]
            ok = np.isfinite(fr) & np.isfinite(ft)
            if ok.sum() < 100:
                continue
            fr_ok, ft_ok = fr[ok], ft[ok]
            if np.ptp(fr_ok) < MIN_REFERENCE_MODULATION_HZ:
                continue
            if np.std(ft_ok) == 0 or np.corrcoef(fr_ok, ft_ok)[0, 1] < MIN_RATE_CORRELATION:
                continue
            first, last = np.flatnonzero(np.isfinite(fr))[[0, -1]]
            values.append(float(fr[first] - fr[last]))
        if values:
            per_test[test] = float(np.mean(values))
            pairs += len(values)
    return DeltaF(per_test, pairs)


def ks_distance(a: np.ndarray, b: np.ndarray, weights_a: np.ndarray | None = None) -> float:
    """Two-sample Kolmogorov-Smirnov distance (largest gap between the empirical CDFs) of samples a and b (NaNs
    dropped); ``weights_a`` weighs the values of a (e.g. the chance a decomposition identifies each unit)."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    wa = np.ones(a.size) if weights_a is None else np.asarray(weights_a, float)
    keep = np.isfinite(a) & (wa > 0)
    a, wa = a[keep], wa[keep]
    b = b[np.isfinite(b)]
    if not a.size or not b.size:
        return float("nan")
    x = np.sort(np.concatenate([a, b]))
    order = np.argsort(a)
    ca = np.concatenate([[0.0], np.cumsum(wa[order])]) / wa.sum()
    fa = ca[np.searchsorted(a[order], x, side="right")]
    fb = np.searchsorted(np.sort(b), x, side="right") / b.size
    return float(np.max(np.abs(fa - fb)))


def ks_sampling_percentiles(values: np.ndarray, weights: np.ndarray, n: int, *, draws: int = 1000, seed: int = 0,
                            percentiles: Sequence[float] = (50.0, 95.0)) -> list[float]:
    """Percentiles of the KS distance between a distribution (``values`` with ``weights``) and samples of ``n``
    values drawn from it (``draws`` samples, random ``seed``): how far a recording of ``n`` units would fall from
    a model that is exactly right, by chance alone.  KS distances are fractions of units (1); ``values`` in any unit."""
    v = np.asarray(values, float)
    w = np.asarray(weights, float)
    keep = np.isfinite(v) & (w > 0)
    v, w = v[keep], w[keep]
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or draws < 1:
        raise InputError(f"draws must be a positive integer, got {draws!r}")
    if not v.size or n < 1:
        return [float("nan")] * len(percentiles)
    rng = np.random.default_rng(seed)
    d = [ks_distance(v, rng.choice(v, int(n), p=w / w.sum()), w) for _ in range(int(draws))]
    return [float(x) for x in np.percentile(d, list(percentiles))]
