"""Self-consistent calculation (SCC, van Zandwijk et al. 1998, section 2.3.1, eqs 3-4) of the CE moment-velocity and SEE
moment-extension relations from isokinetic release contractions.

Input: releases, each with time (s), MTC angle (rad; any offset, *decreasing* when the MTC shortens) and moment
(N m), starting isometric at full (voluntary) activation. For each release: omega_mtc = -d angle/dt (rad/s,
shortening > 0), the release starts where omega_mtc first exceeds 5 % of its maximum, M_init is the mean moment
before that, the isokinetic phase is where omega_mtc >= 90 % of its maximum.

The two relations fitted:
  CE (eq 1 at q = 1 and the initial CE angle): omega_ce = (M_init - M) b / (M + a_rel M_init)   -> a_rel, b
  SEE (eq 2): M = k_see e^2                                                                     -> k_see
They are mutually dependent:
  eq 3 (all releases): omega_ce = omega_mtc + (dM/dt) / (2 sqrt(M k_see)), i.e. the MTC velocity minus the SEE
       shortening velocity from the current SEE relation, at each isokinetic sample with M >= ``ce_min_fraction``
       M_init and an estimated CE excursion from its initial angle <= ``max_ce_excursion_rad`` (so that all
       points pertain to nearly the same CE angle, as in the paper's Fig 4);
  eq 4 (fastest release, the controlled release): SEE shortening
       dphi_see(t) = dphi_mtc(t) - int_0^t (M_init - M) b / (M + a_rel M_init) dt from the current CE relation,
       at each sample from the release start until the moment first reaches ``zero_fraction`` M_init; then
       sqrt(M) = sqrt(k_see) (e_init - dphi_see) is fitted by a straight line (slope -sqrt(k_see)).
Iteration: the first k_see comes from the start of the fastest release (moment >= 0.8 M_init, where the CE has
hardly begun to shorten); then eq 3 / CE fit and eq 4 / SEE fit alternate until
k_see, a_rel and b change by less than ``rtol`` (relative); both relations are then self-consistent.

The CE fit solves the linearised Hill equation M omega = b (M_init - M) - a_rel M_init omega by least squares
and refines (a_rel, b) by nonlinear least squares on the velocity residuals.
A data set without a release fast enough for the moment to reach ~zero is refused (InputError): the SEE
relation cannot be derived from it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import least_squares

from ..errors import InputError, NumericalError
from ..model.hatze_parameters import check_positive


@dataclass(frozen=True)
class Release:
    """One isokinetic release: ``t_s`` (s), ``mtc_angle_rad`` (rad, decreasing = shortening), ``moment_nm`` (N m)."""

    t_s: NDArray[np.float64]
    mtc_angle_rad: NDArray[np.float64]
    moment_nm: NDArray[np.float64]


@dataclass(frozen=True)
class _Prepared:
    index: int
    t: NDArray[np.float64]
    moment: NDArray[np.float64]
    dmdt: NDArray[np.float64]
    omega_mtc: NDArray[np.float64]
    dphi_mtc: NDArray[np.float64]        # MTC shortening since the release start, rad
    start: int
    m_init: float
    velocity: float
    isokinetic: NDArray[np.bool_]


@dataclass(frozen=True)
class SCCResult:
    """Self-consistent CE and SEE relations.

    ``k_see`` (N m/rad^2), ``a_rel`` (1), ``b_rad_s`` (rad/s) of omega_ce = (M_init - M) b/(M + a_rel M_init);
    ``m_init_nm`` (N m, mean initial moment); ``iterations``; ``fastest_release`` (index in the input);
    ``ce_points`` (moment N m, omega_ce rad/s) and ``see_points`` (SEE shortening rad, moment N m) of the final
    iteration; ``see_extension_init_rad``: SEE extension at M_init from the SEE line fit (rad).
    """

    k_see: float
    a_rel: float
    b_rad_s: float
    m_init_nm: float
    iterations: int
    fastest_release: int
    ce_points: tuple[NDArray[np.float64], NDArray[np.float64]]
    see_points: tuple[NDArray[np.float64], NDArray[np.float64]]
    see_extension_init_rad: float

    def b_rel(self, phi_ce_opt_rad: float) -> float:
        """b_rel = b / phi_ce_opt (Hz)."""
        return self.b_rad_s / check_positive("phi_ce_opt_rad", phi_ce_opt_rad)


def _as_release(item: object, i: int) -> Release:
    if isinstance(item, Release):
        parts = (item.t_s, item.mtc_angle_rad, item.moment_nm)
    elif isinstance(item, (tuple, list)) and len(item) == 3:
        parts = tuple(item)
    else:
        raise InputError(f"releases[{i}] must be a Release or a (t_s, mtc_angle_rad, moment_nm) triple")
    names = ("t_s", "mtc_angle_rad", "moment_nm")
    arrs = []
    for name, p in zip(names, parts):
        try:
            a = np.asarray(p, dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"releases[{i}].{name} must be an array of numbers") from None
        if not np.all(np.isfinite(a)):
            raise InputError(f"releases[{i}].{name} contains non-finite values")
        arrs.append(a)
    n = arrs[0].size
    if any(a.size != n for a in arrs) or n < 10:
        raise InputError(f"releases[{i}]: t_s, mtc_angle_rad and moment_nm must have one common length >= 10 "
                         f"(got {[a.size for a in arrs]})")
    if np.any(np.diff(arrs[0]) <= 0):
        raise InputError(f"releases[{i}].t_s must increase strictly")
    return Release(*arrs)


def _prepare(rel: Release, i: int) -> _Prepared:
    t, ang, m = rel.t_s, rel.mtc_angle_rad, rel.moment_nm
    omega = -np.gradient(ang, t)
    v = float(np.max(omega))
    if not v > 0.0:
        raise InputError(f"releases[{i}]: the MTC angle never decreases (no release)")
    start = int(np.argmax(omega > 0.05 * v))
    if start < 1:
        raise InputError(f"releases[{i}]: no isometric phase before the release")
    m_init = float(np.mean(m[:start]))
    if not m_init > 0.0:
        raise InputError(f"releases[{i}].moment_nm: initial isometric moment {m_init} N m is not positive")
    dphi = np.maximum(ang[start] - ang, 0.0)
    dphi[:start] = 0.0
    iso = omega >= 0.9 * v
    iso[:start] = False
    return _Prepared(i, t, m, np.gradient(m, t), omega, dphi, start, m_init, v, iso)


def _fit_ce(points_m: NDArray[np.float64], points_m0: NDArray[np.float64], points_w: NDArray[np.float64],
            guess: tuple[float, float] | None) -> tuple[float, float]:
    """(a_rel, b) of omega = (M0 - M) b / (M + a_rel M0) by linear then nonlinear least squares."""
    a_mat = np.column_stack([points_m0 - points_m, -points_m0 * points_w])
    rhs = points_m * points_w
    (b0, a0), *_ = np.linalg.lstsq(a_mat, rhs, rcond=None)
    if guess is not None:
        a0, b0 = guess
    if not (a0 > 0 and b0 > 0):               # fall back to a generic Hill curve through the fastest point
        a0 = 0.25
        b0 = max(float(np.max(points_w)), 1e-3) * a0

    def resid(p: NDArray[np.float64]) -> NDArray[np.float64]:
        a, b = math.exp(p[0]), math.exp(p[1])
        return (points_m0 - points_m) * b / (points_m + a * points_m0) - points_w

    sol = least_squares(resid, np.log([a0, b0]), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return math.exp(sol.x[0]), math.exp(sol.x[1])


def self_consistent_calculation(releases: Sequence[object], zero_fraction: float = 0.02,
                                ce_min_fraction: float = 0.05, max_ce_excursion_rad: float = 0.1,
                                rtol: float = 1e-10, max_iterations: int = 200) -> SCCResult:
    """SCC (eqs 3-4) on ``releases``: Release objects or (t_s, mtc_angle_rad, moment_nm) triples (s, rad, N m).

    ``zero_fraction``: the fastest release must bring the moment to <= this fraction of its initial moment, else
    InputError; ``ce_min_fraction`` and ``max_ce_excursion_rad`` select the CE points (module docstring).
    """
    if isinstance(releases, (Release, np.ndarray)) or not isinstance(releases, Sequence) or len(releases) < 2:
        raise InputError("releases must be a sequence of at least 2 releases (different velocities)")
    zero_fraction = check_positive("zero_fraction", zero_fraction)
    ce_min_fraction = check_positive("ce_min_fraction", ce_min_fraction)
    max_exc = check_positive("max_ce_excursion_rad", max_ce_excursion_rad)
    prepared = [_prepare(_as_release(r, i), i) for i, r in enumerate(releases)]
    fast = max(prepared, key=lambda p: p.velocity)
    after = fast.moment[fast.start:]
    hit = np.nonzero(after <= zero_fraction * fast.m_init)[0]
    if hit.size == 0:
        raise InputError(
            f"releases: the fastest release (releases[{fast.index}], {fast.velocity:.3g} rad/s) only brings the "
            f"moment down to {after.min():.3g} N m ({100 * after.min() / fast.m_init:.1f} % of its initial "
            f"{fast.m_init:.3g} N m); SCC needs a release fast enough for the moment to reach zero "
            f"(<= {100 * zero_fraction:g} %)")
    stop = fast.start + int(hit[0])          # first sample at ~zero moment
    see_sl = slice(fast.start, stop)
    if stop - fast.start < 3:
        raise InputError(f"releases[{fast.index}]: fewer than 3 samples between release start and zero moment")

    def fit_see(a_rel: float | None, b: float | None) -> tuple[float, float, NDArray, NDArray]:
        m = fast.moment[see_sl]
        tt = fast.t[see_sl]
        if a_rel is None:
            ce_short = np.zeros_like(m)
        else:
            w = (fast.m_init - m) * b / (m + a_rel * fast.m_init)  # type: ignore[operator]
            ce_short = cumulative_trapezoid(w, tt, initial=0.0)
        dsee = fast.dphi_mtc[see_sl] - ce_short
        slope, intercept = np.polyfit(dsee, np.sqrt(np.maximum(m, 0.0)), 1)
        if not slope < 0.0:
            raise NumericalError("SEE fit: sqrt(moment) does not fall with SEE shortening")
        k = slope * slope
        return k, intercept / -slope, dsee, m

    def ce_points(k: float) -> tuple[NDArray, NDArray, NDArray]:
        ms, m0s, ws = [], [], []
        for p in prepared:
            m = p.moment
            ok = p.isokinetic & (m >= ce_min_fraction * p.m_init) & (m < p.m_init)
            see_short = (math.sqrt(p.m_init) - np.sqrt(np.maximum(m, 0.0))) / math.sqrt(k)
            ok &= (p.dphi_mtc - see_short) <= max_exc
            mm = m[ok]
            w = p.omega_mtc[ok] + p.dmdt[ok] / (2.0 * np.sqrt(mm * k))      # eq 3
            ms.append(mm)
            m0s.append(np.full(mm.shape, p.m_init))
            ws.append(w)
        m_all, m0_all, w_all = np.concatenate(ms), np.concatenate(m0s), np.concatenate(ws)
        if m_all.size < 3 or np.unique(np.round(w_all, 6)).size < 2:
            raise InputError("releases: too few isokinetic samples for the CE moment-velocity fit "
                             "(increase max_ce_excursion_rad or give more releases)")
        return m_all, m0_all, w_all

    # first guess of k_see: the start of the controlled release (M >= 0.8 M_init), where the CE barely moves
    early = np.nonzero(fast.moment[fast.start:stop] >= 0.8 * fast.m_init)[0] + fast.start
    early = early if early.size >= 3 else np.arange(fast.start, fast.start + 3)
    slope0 = np.polyfit(fast.dphi_mtc[early], np.sqrt(fast.moment[early]), 1)[0]
    if not slope0 < 0.0:
        raise InputError(f"releases[{fast.index}]: the moment does not fall at the start of the fastest release")
    k = slope0 * slope0
    a_rel = b = None
    guess = None
    for it in range(1, max_iterations + 1):
        m_all, m0_all, w_all = ce_points(k)
        a_new, b_new = _fit_ce(m_all, m0_all, w_all, guess)
        k_new, e0, dsee, m_see = fit_see(a_new, b_new)
        change = max(abs(k_new / k - 1.0),
                     abs(a_new / a_rel - 1.0) if a_rel else 1.0,
                     abs(b_new / b - 1.0) if b else 1.0)
        k, a_rel, b = k_new, a_new, b_new
        guess = (a_rel, b)
        if change < rtol:
            return SCCResult(k, a_rel, b, float(np.mean([p.m_init for p in prepared])), it, fast.index,
                             (m_all, w_all), (dsee, m_see), float(e0))
    raise NumericalError(f"SCC did not converge in {max_iterations} iterations (last relative change {change:.2e})")
