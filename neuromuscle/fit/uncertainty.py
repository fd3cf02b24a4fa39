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
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from scipy.stats import t as student_t

from ..errors import InputError

INVERSES = ("svd", "pinv")
INTERVALS = ("parameter", "search")


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


@dataclass(frozen=True)
class Uncertainty:
    """Uncertainty of the estimates of the fitted parameters ``names`` (parameter units unless stated).

    ``std_errors``: standard errors (inf: no effect or a singular direction); ``ci95``: (lower, upper) 95 %
    intervals; ``correlation``: k x k correlation of the estimates; ``singular_values`` of the column-normalised
    Jacobian; ``vif``: variance inflation factors; ``flags``: why each poorly identified parameter is flagged;
    ``dof``: degrees of freedom; ``residual_sigma``: s = sqrt(|r|^2 / dof) (units of the residuals).
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

    @property
    def identifiable(self) -> dict[str, bool]:
        """False for the flagged parameters."""
        return {n: n not in self.flags for n in self.names}


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


def estimate_uncertainty(names: Sequence[str], z: np.ndarray, jac_z: np.ndarray, resid: np.ndarray,
                         to_p: Callable[[np.ndarray], np.ndarray], dp_dz: np.ndarray, rules: Rules) -> Uncertainty:
    """The :class:`Uncertainty` at search vector z from J = dr/dz (n x k), the residuals r (n), the map
    ``to_p`` from z (array) to parameter units and dp/dz at z; ``rules``: the engine's (module docstring)."""
    names = tuple(names)
    n, k = jac_z.shape
    dof = max(n - k, 1)
    s2 = float(resid @ resid) / dof
    if rules.inverse == "svd":
        norms = np.linalg.norm(jac_z, axis=0)
    else:
        jtj = jac_z.T @ jac_z
        norms = np.sqrt(np.diag(jtj))
    safe = np.where(norms > 0, norms, 1.0)
    _, svals, vt = np.linalg.svd(jac_z / safe, full_matrices=False)
    if rules.inverse == "svd":
        c_inv = _inverse_svd(svals, vt)
    else:
        c_inv = np.linalg.pinv(jtj / np.outer(safe, safe), rcond=1e-15)
    with np.errstate(invalid="ignore"):
        cov_z = s2 * c_inv / np.outer(safe, safe)
        cov_p = cov_z * np.outer(dp_dz, dp_dz)
    se = np.where(norms > 0, np.sqrt(np.maximum(np.diag(cov_p), 0.0)), np.inf)
    tq = float(student_t.ppf(0.975, dof))
    est = to_p(z)
    if rules.interval == "parameter":
        lo, hi = est - tq * se, est + tq * se
    else:
        half = tq * np.where(norms > 0, np.sqrt(np.maximum(np.diag(cov_z), 0.0)), np.inf)
        lo, hi = to_p(z - half), to_p(z + half)
    vif = np.diag(c_inv).copy()
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_p / np.outer(se, se)
    flags = _flags(names, norms, svals, vt, est, se, lo, hi, vif, rules)
    return Uncertainty(names, _floats(names, est), _floats(names, se),
                       {nm: (float(a), float(b)) for nm, a, b in zip(names, lo, hi)}, corr, svals,
                       _floats(names, vif), flags, dof, math.sqrt(s2))


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
