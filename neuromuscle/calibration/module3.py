"""Module 3 of the muscle from three kinds of data (Kim et al. 2015, section 2.2.2), and the curves it
fits.

* KSE (:func:`calibrate_kse`): force just before the length step (median over ``pre_ms``) minus the minimum
  (3-sample running mean) within the step and ``post_ms`` after it, divided by the step (mm) and P0.  The CE
  shortens a little during a finite ramp, so this direct estimate is slightly low (a few % for a 1 ms,
  0.5 mm step on CT09); that is the paper's method and it is kept as is.
* Force-length (:func:`calibrate_force_length`): least squares of F = P0 exp(-((X - g1)/g2)^2) (scipy
  curve_fit); SEs from its covariance.
* Force-velocity (:func:`calibrate_force_velocity`): exactly two shortening + two lengthening points -> closed
  form (eqs 13-16); more points -> least squares of the tension residuals of T(V) = (b0 P0 + a0 V)/(b0 - V)
  (V < 0, Hill) and T(V) = (d0 P0 + (2 P0 + c0) V)/(d0 + V) (V > 0, Mashima), each branch separately, started
  from the linear least-squares solution of the rearranged equations.  Points at V = 0 belong to neither branch.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..errors import InputError
from ..analysis.closed_form import hill_mashima_coefficients
from ..analysis.module3 import force_length as gaussian_force_length
from ..analysis.module3 import C0_OVER_P0_MIN, hill_tension, mashima_tension
from ..measured import Trial
from .stage import StageResult
from .trials import in_model_units


def _pairs(name: str, x: Sequence[float], y: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    xa, ya = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
    if xa.size != ya.size:
        raise InputError(f"{name}: {xa.size} abscissae but {ya.size} forces")
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ya))):
        raise InputError(f"{name}: values must be finite")
    return xa, ya


def calibrate_kse(step_trial: Trial, P0: float, *, pre_ms: float = 5.0, post_ms: float = 5.0) -> StageResult:
    """KSE (1/mm) = force drop (N) / length step (mm) / P0 (N) from a step-shortening trial (Kim et al. 2015, 2.2.2)."""
    if not in_model_units(step_trial):
        raise InputError(f"trial '{step_trial.trial_id}': KSE needs force in N and length in mm")
    if step_trial.length is None:
        raise InputError(f"trial '{step_trial.trial_id}': a step-shortening trial needs a sampled length")
    if not (np.isfinite(P0) and P0 > 0):
        raise InputError(f"P0 must be finite and > 0, got {P0}")
    t = np.asarray(step_trial.time_s, dtype=float) * 1000.0
    x = np.asarray(step_trial.length, dtype=float)
    f = np.asarray(step_trial.force, dtype=float)
    x0, x1 = float(x[0]), float(x[-1])
    step = x0 - x1
    if step <= 0:
        raise InputError(f"trial '{step_trial.trial_id}': the length does not shorten ({x0:g} -> {x1:g} mm)")
    i_on = int(np.argmax(x < x0 - 0.02 * step))
    i_end = int(np.argmax(x <= x1 + 0.02 * step))
    t_on, t_end = t[i_on], t[i_end]
    before = (t >= t_on - pre_ms) & (t < t_on)
    if not np.any(before):
        raise InputError(f"trial '{step_trial.trial_id}': no samples in the {pre_ms} ms before the step")
    f_before = float(np.median(f[before]))
    after = (t >= t_on) & (t <= t_end + post_ms)
    fa = f[after]
    if fa.size >= 3:
        fa = np.convolve(fa, np.ones(3) / 3.0, mode="valid")
    f_min = float(np.min(fa))
    drop = f_before - f_min
    if f_min <= 0.02 * f_before:
        raise InputError(f"trial '{step_trial.trial_id}': the force falls to ~0 during the step (slack): use a "
                         "smaller step or a higher force")
    kse = drop / step / P0
    return StageResult("KSE", {"KSE": kse}, {"force_drop_N": drop, "step_mm": step,
                                             "ramp_ms": float(t_end - t_on), "force_before_N": f_before},
                       [step_trial.trial_id],
                       ["direct estimate (Kim et al. 2015, 2.2.2); CE shortening during a finite ramp biases it low"])


def kse_from_steps(steps: Sequence[Trial], P0: float) -> StageResult:
    """The KSE stage (1/mm) from one or more step-shortening trials at P0 (N): :func:`calibrate_kse` of each, the
    mean, and the spread between trials."""
    rs = [calibrate_kse(t, P0) for t in steps]
    values = [r.values["KSE"] for r in rs]
    return StageResult("KSE", {"KSE": float(np.mean(values))},
                       {**rs[0].errors, "n_trials": float(len(rs)), "spread": float(np.ptp(values))},
                       [t.trial_id for t in steps], rs[0].notes + (["mean over trials"] if len(rs) > 1 else []))


def calibrate_force_length(lengths_mm: Sequence[float], forces_N: Sequence[float], *,
                           fix_P0: float | None = None) -> StageResult:
    """g1 (mm, optimum), g2 (mm, Gaussian width) and P0 (N) by least squares on isometric force-length points
    at full activation (any consistent units work, e.g. L0 and F0).  fix_P0 holds P0 at that value."""
    from scipy.optimize import curve_fit

    x, y = _pairs("force-length points", lengths_mm, forces_N)
    n_free = 2 if fix_P0 is not None else 3
    if x.size < n_free + 1 or np.unique(x).size < n_free:
        raise InputError(f"force-length: need at least {n_free + 1} points at {n_free} distinct lengths, "
                         f"got {x.size}")
    i = int(np.argmax(y))
    p_start = [x[i], max(np.ptp(x), 1e-9)] + ([] if fix_P0 is not None else [y[i]])
    fn = ((lambda xx, g1, g2: gaussian_force_length(xx, g1, g2, fix_P0)) if fix_P0 is not None
          else gaussian_force_length)
    try:
        popt, pcov = curve_fit(fn, x, y, p0=p_start, maxfev=20000)
    except RuntimeError as exc:
        raise InputError(f"force-length: least squares did not converge ({exc})") from None
    names = ["g1", "g2"] + ([] if fix_P0 is not None else ["P0"])
    values = {n: float(v) for n, v in zip(names, popt)}
    values["g2"] = abs(values["g2"])
    if fix_P0 is not None:
        values["P0"] = float(fix_P0)
    resid = y - gaussian_force_length(x, values["g1"], values["g2"], values["P0"])
    errors = {"rms": float(np.sqrt(np.mean(resid ** 2))), "max_abs": float(np.max(np.abs(resid))),
              "rms_over_P0": float(np.sqrt(np.mean(resid ** 2)) / values["P0"]), "n_points": float(x.size)}
    se = np.sqrt(np.abs(np.diag(pcov))) if np.all(np.isfinite(pcov)) else np.full(len(names), np.inf)
    errors.update({f"se_{n}": float(s) for n, s in zip(names, se)})
    return StageResult("force-length", values, errors, [f"{x.size} force-length points"])


def _admissible_force_velocity(values: dict[str, float], P0: float) -> bool:
    """Whether Hill/Mashima coefficients lie in eq 10-11's range: a0, b0, d0 > 0 and -P0 < c0 <= 0."""
    return (all(np.isfinite(values[k]) and values[k] > 0 for k in ("a0", "b0", "d0"))
            and -C0_OVER_P0_MIN * P0 <= values["c0"] <= 0.0)


def calibrate_force_velocity(velocities_mm_s: Sequence[float], tensions_N: Sequence[float],
                             P0: float) -> StageResult:
    """a0 (N), b0 (mm/s), c0 (N), d0 (mm/s) from velocity-tension points at full activation and the optimum.

    Two shortening and two lengthening points: closed form (eqs 13-16, exact).  More: least squares per
    branch (see the module docstring).  Any consistent units work (e.g. L0/s and F0 with P0 = 1)."""
    from scipy.optimize import least_squares

    v, T = _pairs("force-velocity points", velocities_mm_s, tensions_N)
    if not (np.isfinite(P0) and P0 > 0):
        raise InputError(f"P0 must be finite and > 0, got {P0}")
    s, l_ = v < 0, v > 0
    if s.sum() < 2 or l_.sum() < 2:
        raise InputError(f"force-velocity: need >= 2 shortening and >= 2 lengthening points, got {int(s.sum())} "
                         f"and {int(l_.sum())}")
    notes = []
    values = {}
    if s.sum() == 2 and l_.sum() == 2:
        values = hill_mashima_coefficients(list(zip(v[s | l_], T[s | l_])), P0)
        notes.append("closed form from four points (eqs 13-16)")
        if not _admissible_force_velocity(values, P0):
            notes[-1] = ("the closed form from four points (eqs 13-16) lies outside eq 11's range (a0, b0, d0 > 0, "
                         "-P0 < c0 <= 0): bounded least squares instead")
            values = {}
    if not values:
        # linear starts: V a0 + b0 (P0 - T) = -V T;  V c0 + d0 (P0 - T) = -V (2 P0 - T)
        vs, ts, vl, tl = v[s], T[s], v[l_], T[l_]
        a_s, b_s = np.linalg.lstsq(np.column_stack([vs, P0 - ts]), -vs * ts, rcond=None)[0]
        c_s, d_s = np.linalg.lstsq(np.column_stack([vl, P0 - tl]), -vl * (2 * P0 - tl), rcond=None)[0]
        span = max(np.max(np.abs(v)), 1e-12)
        a_s, b_s = (a_s if a_s > 0 else 0.2 * P0), (b_s if b_s > 0 else span)
        d_s = d_s if d_s > 0 else span
        c_lo = -C0_OVER_P0_MIN * P0  # eq 11's asymptote (2 + c0/P0) Fc above Fc; c0 <= 0 (its range)
        c_s = float(np.clip(c_s, c_lo, 0.0))
        rs = least_squares(lambda p: hill_tension(vs, p[0], p[1], P0) - ts, [a_s, b_s],
                           bounds=([1e-9 * P0, 1e-9 * span], [np.inf, np.inf]))
        rl = least_squares(lambda p: mashima_tension(vl, p[0], p[1], P0) - tl, [c_s, d_s],
                           bounds=([c_lo, 1e-9 * span], [0.0, np.inf]))
        values = {"a0": float(rs.x[0]), "b0": float(rs.x[1]), "c0": float(rl.x[0]), "d0": float(rl.x[1])}
        notes.append(f"least squares through {int(s.sum())} shortening and {int(l_.sum())} lengthening points "
                     "(c0 within (-P0, 0])")
    res_s = hill_tension(v[s], values["a0"], values["b0"], P0) - T[s]
    res_l = mashima_tension(v[l_], values["c0"], values["d0"], P0) - T[l_]
    allr = np.concatenate([res_s, res_l])
    errors = {"rms": float(np.sqrt(np.mean(allr ** 2))), "rms_shortening": float(np.sqrt(np.mean(res_s ** 2))),
              "rms_lengthening": float(np.sqrt(np.mean(res_l ** 2))), "rms_over_P0":
              float(np.sqrt(np.mean(allr ** 2)) / P0), "vmax": values["b0"] * P0 / values["a0"],
              "lengthening_asymptote_over_P0": 2.0 + values["c0"] / P0}
    if np.any(v == 0):
        notes.append(f"{int(np.sum(v == 0))} point(s) at V = 0 not used")
    return StageResult("force-velocity", values, errors, [f"{int(s.sum() + l_.sum())} velocity-tension points"],
                       notes)
