"""One vocabulary for the uncertainty and identifiability of least-squares estimates, for both fitting engines.

:func:`estimate_uncertainty` turns the Jacobian J = dr/dz of the residuals in the search space z, the residuals r
and the map z -> p to parameter units into an :class:`Uncertainty`.  Shared by both engines:

* s^2 = |r|^2 / dof with dof = max(n - k, 1); cov(z) = s^2 (J^T J)^-1, computed through the column-normalised
  J (columns of unit length, C = Jn^T Jn is the correlation-scaled J^T J); cov(p) = cov(z) (dp/dz)(dp/dz)^T
  (delta method) and std_errors = sqrt(diag cov(p)).
* 95 % intervals with the quantile t_{0.975, dof}; correlation = cov(p) scaled by the SEs (nan where an SE is
  0 or inf); variance inflation factors VIF_k = [C^-1]_kk (1 for an orthogonal design); singular values of
  Jn, largest first.
* A parameter with a zero Jacobian column has no effect: SE inf, flagged.

Which covariance of the residuals (``covariance``, :data:`COVARIANCES`; the interval method is named in
``Uncertainty.method`` and described by :func:`describe_method`):

* ``"iid"``: the above, s^2 (J^T J)^-1: right when the residuals are independent with one variance.
* ``"hac"``: a sandwich (J^T J)^-1 S (J^T J)^-1 (times n / (n - k)) whose middle S is the long-run covariance of
  the scores J_t r_t, summed over independent ``segments`` (the trials; no lag crosses a trial boundary).  Each
  segment is prewhitened by an AR(1) filter (rho = lag-1 autocorrelation of its residuals, Kendall's bias
  correction, capped at +/-``RHO_MAX``; Prais-Winsten first sample), the whitened scores get Newey-West's
  Bartlett estimate with lag floor(4 (n_s / 100)^(2/9)), and the filter is undone on the regressors
  (Andrews & Monahan 1992).  Right for autocorrelated noise (force transducers) and for trials whose residuals
  differ in variance (e.g. the NRMSE objective, which rescales each trial by its range).
* ``model_error`` (optional, residual units): the model's own numerical error at the estimate (e.g. a
  fixed-step integrator's, see :mod:`.intervals`).  It biases the estimate by b = -(J^T J)^-1 J^T e
  (``Uncertainty.numerical_bias``, parameter units); the interval is widened by |b| towards est - b,
  so that it holds both the estimate's interval and the bias-corrected one.

What each engine does its own way is a :class:`Rules` (the constructors keep each engine's rules as they were):

* ``Rules.for_fit`` (:func:`neuromuscle.fit.fit`, the Kim muscle): C^-1 from the SVD of Jn, infinite along
  directions whose singular value is <= 1e-12 of the largest; Wald intervals in parameter units,
  est +/- t SE; flagged when a parameter loads (|v| > 0.2) on a singular direction below ``ident_rcond`` of the
  largest, or when its relative SE exceeds ``max_rel_se``.
* ``Rules.for_twitch_fit`` (:func:`neuromuscle.hatze.twitch_fit.fit_twitch`): C^-1 = pinv(C, rcond=1e-15);
  Wald intervals in the search space mapped back, p(z +/- t SE_z) (asymmetric in theta for z = ln theta);
  flagged when the interval spans more than a factor ``max_ci_factor`` (upper/lower) or VIF > ``max_vif``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from scipy.signal import lfilter
from scipy.stats import t as student_t

from ..errors import InputError

INVERSES = ("svd", "pinv")
INTERVALS = ("parameter", "search")
COVARIANCES = ("iid", "hac")
#: The largest |rho| of the AR(1) prewhitening filter (near a unit root its long-run variance explodes).
RHO_MAX = 0.99


@dataclass(frozen=True)
class Rules:
    """How an engine inverts C and places and flags intervals (module docstring); None disables a flag test."""

    inverse: str = "svd"
    interval: str = "parameter"
    ident_rcond: float | None = None
    max_rel_se: float | None = None
    max_ci_factor: float | None = None
    max_vif: float | None = None

    def __post_init__(self) -> None:
        if self.inverse not in INVERSES or self.interval not in INTERVALS:
            raise InputError(f"Rules: inverse must be one of {INVERSES} and interval one of {INTERVALS}, got "
                             f"{self.inverse!r} and {self.interval!r}")

    @classmethod
    def for_fit(cls, ident_rcond: float = 1e-3, max_rel_se: float = 0.5) -> Rules:
        """The rules of :func:`neuromuscle.fit.fit`."""
        return cls("svd", "parameter", ident_rcond=ident_rcond, max_rel_se=max_rel_se)

    @classmethod
    def for_twitch_fit(cls, max_ci_factor: float = 4.0, max_vif: float = 1e4) -> Rules:
        """The rules of :func:`neuromuscle.hatze.twitch_fit.fit_twitch`."""
        return cls("pinv", "search", max_ci_factor=max_ci_factor, max_vif=max_vif)


#: ``Uncertainty.method`` of estimates whose uncertainty was not made (:meth:`Uncertainty.not_estimated`).
NOT_ESTIMATED = "none"


@dataclass(frozen=True)
class Uncertainty:
    """Uncertainty of the estimates of the fitted parameters ``names`` (parameter units unless stated).

    ``std_errors``: standard errors (inf: no effect or a singular direction); ``ci95``: (lower, upper) 95 %
    intervals; ``correlation``: k x k correlation of the estimates; ``singular_values`` of the column-normalised
    Jacobian; ``vif``: variance inflation factors; ``flags``: why each poorly identified parameter is flagged;
    ``dof``: degrees of freedom; ``residual_sigma``: s = sqrt(|r|^2 / dof) (units of the residuals);
    ``method``: how the intervals were made (:func:`describe_method`); ``numerical_bias``: the estimated bias of
    the estimates from the model's numerical error (0 when not estimated).
    """

    names: tuple[str, ...]
    estimates: dict[str, float]
    std_errors: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    correlation: np.ndarray
    singular_values: np.ndarray
    vif: dict[str, float]
    flags: dict[str, str]
    dof: int
    residual_sigma: float
    method: str = "iid"
    numerical_bias: dict[str, float] = field(default_factory=dict)

    @property
    def identifiable(self) -> dict[str, bool]:
        """False for the flagged parameters."""
        return {n: n not in self.flags for n in self.names}

    @classmethod
    def not_estimated(cls, estimates: dict[str, float], why: str) -> Uncertainty:
        """The estimates with no uncertainty made: infinite SE, unbounded intervals, every parameter flagged with
        ``why`` (so nothing reads them as identified)."""
        names = tuple(estimates)
        k = len(names)
        return cls(names, dict(estimates), {n: math.inf for n in names}, {n: (-math.inf, math.inf) for n in names},
                   np.full((k, k), np.nan), np.full(k, np.nan), {n: math.inf for n in names},
                   {n: why for n in names}, 0, math.nan, NOT_ESTIMATED)


def _inverse_svd(svals: np.ndarray, vt: np.ndarray) -> np.ndarray:
    """C^-1 from the SVD of Jn, infinite along directions with a singular value <= 1e-12 of the largest."""
    smax = svals[0] if svals.size and svals[0] > 0 else 1.0
    inv_s2 = np.array([1.0 / s ** 2 if s > 1e-12 * smax else np.inf for s in svals])
    finite = np.where(np.isfinite(inv_s2), inv_s2, 0.0)
    c_inv = (vt.T * finite) @ vt
    null = vt[~np.isfinite(inv_s2)]
    touched = np.any(np.abs(null) > 1e-8, axis=0)
    c_inv[np.ix_(touched, touched)] = np.inf
    return c_inv


def _to_parameter_units(cov_z: np.ndarray, dp_dz: np.ndarray) -> np.ndarray:
    """The covariance of the parameters from that of z: D cov_z D^T with D = dp/dz (a vector: its diagonal);
    an infinite (unidentified) entry of cov_z makes every entry it reaches infinite."""
    d = np.asarray(dp_dz, dtype=float)
    if d.ndim == 1:
        return cov_z * np.outer(d, d)
    unknown = ~np.isfinite(cov_z)
    cov = d @ np.where(unknown, 0.0, cov_z) @ d.T
    reach = (np.abs(d) > 0).astype(float)
    return np.where(reach @ unknown.astype(float) @ reach.T > 0, np.inf, cov)


def estimate_uncertainty(names: Sequence[str], z: np.ndarray, jac_z: np.ndarray, resid: np.ndarray,
                         to_p: Callable[[np.ndarray], np.ndarray], dp_dz: np.ndarray, rules: Rules, *,
                         covariance: str = "iid", segments: Sequence[int] | None = None,
                         model_error: np.ndarray | None = None) -> Uncertainty:
    """The :class:`Uncertainty` at search vector z from J = dr/dz (n x k), the residuals r (n), the map
    ``to_p`` from z (array) to parameter units and dp/dz at z (a vector when each parameter depends on its own z
    only, else the k x k matrix); ``rules``: the engine's; ``covariance``: one of
    ``COVARIANCES``, ``segments``: lengths of the independent series r is made of (default: one), ``model_error``:
    the model's numerical error at z (n, residual units) or None (module docstring)."""
    if covariance not in COVARIANCES:
        raise InputError(f"covariance must be one of {COVARIANCES}, got {covariance!r}")
    names = tuple(names)
    n, k = jac_z.shape
    segments = [n] if segments is None else [int(m) for m in segments]
    if sum(segments) != n or min(segments) < 1:
        raise InputError(f"segments {segments} must be positive lengths adding up to the {n} residuals")
    dof = max(n - k, 1)
    s2 = float(resid @ resid) / dof
    if rules.inverse == "svd":
        norms = np.linalg.norm(jac_z, axis=0)
    else:
        jtj = jac_z.T @ jac_z
        norms = np.sqrt(np.diag(jtj))
    safe = np.where(norms > 0, norms, 1.0)
    jn = jac_z / safe
    _, svals, vt = np.linalg.svd(jn, full_matrices=False)
    if rules.inverse == "svd":
        c_inv = _inverse_svd(svals, vt)
    else:
        c_inv = np.linalg.pinv(jtj / np.outer(safe, safe), rcond=1e-15)
    c_fin = np.where(np.isfinite(c_inv), c_inv, 0.0)
    with np.errstate(invalid="ignore"):
        if covariance == "iid":
            cov_z = s2 * c_inv / np.outer(safe, safe)
        else:
            cov_n = c_fin @ (hac_middle(jn, resid, segments) * (n / dof)) @ c_fin
            cov_z = np.where(np.isfinite(c_inv), cov_n, np.inf) / np.outer(safe, safe)
        cov_p = _to_parameter_units(cov_z, dp_dz)
    se = np.where(norms > 0, np.sqrt(np.maximum(np.diag(cov_p), 0.0)), np.inf)
    bias_z = np.zeros(k) if model_error is None else -(c_fin @ (jn.T @ model_error)) / safe
    bias_p = bias_z * dp_dz if np.ndim(dp_dz) == 1 else np.asarray(dp_dz) @ bias_z
    tq = float(student_t.ppf(0.975, dof))
    est = to_p(z)
    if rules.interval == "parameter":
        lo, hi = est - tq * se - np.maximum(bias_p, 0.0), est + tq * se + np.maximum(-bias_p, 0.0)
    else:
        half = tq * np.where(norms > 0, np.sqrt(np.maximum(np.diag(cov_z), 0.0)), np.inf)
        lo, hi = to_p(z - half - np.maximum(bias_z, 0.0)), to_p(z + half + np.maximum(-bias_z, 0.0))
    vif = np.diag(c_inv).copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_p / np.outer(se, se)
    flags = _flags(names, norms, svals, vt, est, se, lo, hi, vif, rules)
    method = covariance + ("" if model_error is None else "+integrator")
    return Uncertainty(names, _floats(names, est), _floats(names, se),
                       {nm: (float(a), float(b)) for nm, a, b in zip(names, lo, hi)}, corr, svals,
                       _floats(names, vif), flags, dof, math.sqrt(s2), method, _floats(names, bias_p))


def describe_method(method: str) -> str:
    """One sentence saying how intervals of ``method`` (``Uncertainty.method``) were made."""
    if method == NOT_ESTIMATED:
        return "no intervals: the fit stopped at its iteration limit and none were made at its last point"
    covariance, _, extra = method.partition("+")
    text = {"iid": "Wald 95 % intervals from s^2 (J^T J)^-1 (independent residuals of one variance)",
            "hac": "Wald 95 % intervals from a HAC sandwich covariance (AR(1)-prewhitened Newey-West per trial: "
                   "autocorrelated noise, trials of different residual variance)"}.get(covariance)
    if text is None or extra not in ("", "integrator"):
        raise InputError(f"unknown interval method {method!r}")
    return text + ("; widened by the integrator's own error (fitted model re-run at half the step, first-order "
                   "Richardson estimate)" if extra else "")


def hac_middle(jac: np.ndarray, resid: np.ndarray, segments: Sequence[int]) -> np.ndarray:
    """S = sum over the independent ``segments`` of the long-run covariance of the scores J_t r_t (k x k, units
    of J^T r squared): AR(1) prewhitening, Newey-West (Bartlett) on the whitened scores, recolouring."""
    k = jac.shape[1]
    middle = np.zeros((k, k))
    start = 0
    for m in segments:
        j, r = jac[start:start + m], resid[start:start + m]
        start += m
        rho = _ar1_coefficient(r)
        c = math.sqrt(1.0 - rho * rho)
        u = np.concatenate([[c * r[0]], r[1:] - rho * r[:-1]])
        # regressors through the transposed inverse filter, so that sum_t jw_t u_t = J^T r exactly
        jw = lfilter([1.0], [1.0, -rho], j[::-1], axis=0)[::-1]
        jw[0] /= c
        middle += _newey_west(jw * u[:, None], int(4.0 * (m / 100.0) ** (2.0 / 9.0)))
    return middle


def _ar1_coefficient(r: np.ndarray) -> float:
    """Lag-1 autocorrelation of r with Kendall's bias correction (1 + 3 rho) / n, within +/- RHO_MAX."""
    rr = float(r @ r)
    if r.size < 3 or rr == 0.0:
        return 0.0
    rho = float(r[1:] @ r[:-1]) / rr
    return float(np.clip(rho + (1.0 + 3.0 * rho) / r.size, -RHO_MAX, RHO_MAX))


def _newey_west(h: np.ndarray, lag: int) -> np.ndarray:
    """sum_t h_t h_t^T plus the Bartlett-weighted lagged cross products up to ``lag`` (h: n x k)."""
    out = h.T @ h
    for ell in range(1, min(lag, h.shape[0] - 1) + 1):
        g = h[ell:].T @ h[:-ell]
        out += (1.0 - ell / (lag + 1.0)) * (g + g.T)
    return out


def _floats(names: tuple[str, ...], values: np.ndarray) -> dict[str, float]:
    return {nm: float(v) for nm, v in zip(names, values)}


def _flags(names: tuple[str, ...], norms: np.ndarray, svals: np.ndarray, vt: np.ndarray, est: np.ndarray,
           se: np.ndarray, lo: np.ndarray, hi: np.ndarray, vif: np.ndarray, rules: Rules) -> dict[str, str]:
    """Why each poorly identified parameter is flagged (the first reason found, in the order of the tests)."""
    flags: dict[str, str] = {}
    for i, nm in enumerate(names):
        if not norms[i] > 0:
            flags[nm] = "no effect on the residuals (zero sensitivity)"
    if rules.ident_rcond is not None:
        smax = svals[0] if svals.size and svals[0] > 0 else 1.0
        for j, s in enumerate(svals):
            if s < rules.ident_rcond * smax:
                involved = np.flatnonzero(np.abs(vt[j]) > 0.2)
                for i in involved:
                    others = ", ".join(names[m] for m in involved if m != i) or "nothing else"
                    flags.setdefault(names[i], f"lies in a near-singular direction (singular value "
                                               f"{s / smax:.2g} of the largest) with {others}")
    for i, nm in enumerate(names):
        if rules.max_rel_se is not None:
            rel = se[i] / abs(est[i]) if est[i] != 0 else np.inf
            if rel > rules.max_rel_se:
                flags.setdefault(nm, f"relative standard error {rel:.3g} exceeds {rules.max_rel_se}")
        with np.errstate(divide="ignore", invalid="ignore"):
            factor = hi[i] / lo[i]
        if rules.max_ci_factor is not None and factor > rules.max_ci_factor:
            flags.setdefault(nm, f"95 % interval spans a factor {factor:.3g} > {rules.max_ci_factor}")
        if rules.max_vif is not None and vif[i] > rules.max_vif:
            flags.setdefault(nm, f"variance inflation factor {vif[i]:.3g} > {rules.max_vif}")
    return flags
