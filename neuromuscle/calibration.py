"""Staged calibration of the three-module muscle (seed 001, section 2.2.2), each stage usable alone.

Order of the seed: Module 1 is adopted (Westerblad & Allen); Module 3 from three kinds of data
(KSE from a step shortening, g1/g2 (and P0) from isometric force-length points, a0..d0 from velocity-tension
points); then Module 2 (C1..C5, alpha) against twitches and sub-tetanic trains at the optimal length; finally
the length compensation phi1..phi4 (eq 18) from twitches at several lengths.

Every stage returns a :class:`StageResult`: fitted ``values`` (model units), ``errors`` (named numbers: RMS,
NRMSE, standard errors), the ``trials`` (or data points) used and ``notes``.  :func:`staged_calibration`
chains the stages on one :class:`~neuromuscle.measured.MeasuredData` and skips, with the reason, any stage
whose data are absent.

Where the point data live in a measured-data file (extra datasets, allowed by the layout):

* ``/calibration/force_length``   (n, 2): length Xm (mm), isometric tetanic force (N), at full activation.
* ``/calibration/force_velocity`` (n, 2): velocity (mm/s, + lengthening), tension (N), full activation at the
  optimum.

Decisions:

* KSE (:func:`calibrate_kse`): force just before the length step (median over ``pre_ms``) minus the minimum
  (3-sample running mean) within the step and ``post_ms`` after it, divided by the step (mm) and P0.  The CE
  shortens a little during a finite ramp, so this direct estimate is slightly low (a few % for a 1 ms,
  0.5 mm step on CT09); that is the seed's method and it is kept as is.
* Force-length: least squares of F = P0 exp(-((X - g1)/g2)^2) (scipy curve_fit); SEs from its covariance.
* Force-velocity: exactly two shortening + two lengthening points -> closed form (eqs 13-16); more points ->
  least squares of the tension residuals of T(V) = (b0 P0 + a0 V)/(b0 - V) (V < 0, Hill) and
  T(V) = (d0 P0 + (2 P0 + c0) V)/(d0 + V) (V > 0, Mashima), each branch separately, started from the
  linear least-squares solution of the rearranged equations.  Points at V = 0 belong to neither branch.
* Module 2: :class:`~neuromuscle.fitting.FitProblem` with the NRMSE objective (twitch and trains count alike),
  free C1, C2, C3, alpha by default (C4, C5 shape tau_A far from the operating range and trade off with C3).
* Length compensation: for each twitch at length X, phi (the K5 scale) such that the simulated twitch peak
  equals the measured one (brentq on phi with phi constant: phi1 = phi3 = 0, phi2 = phi4 = phi), then
  :func:`~neuromuscle.identification.length_compensation_coefficients` (split at g1 when both sides have two
  distinct lengths, one line otherwise).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .errors import InputError
from .fitting import FitProblem, FitResult, SimulationOptions, fit, trial_simulation
from .analysis.closed_form import hill_mashima_coefficients, length_compensation_coefficients
from .analysis.metrics import nrmse_percent
from .measured import MeasuredData, Trial
from .parameters import ParameterSet

FORCE_LENGTH_PATH = "/calibration/force_length"
FORCE_VELOCITY_PATH = "/calibration/force_velocity"
MODULE2_FREE = ("C1", "C2", "C3", "alpha")
#: Isometric trials within this distance (mm) of g1 count as "at the optimum".
OPTIMUM_TOLERANCE_MM = 0.5


@dataclass
class StageResult:
    """One calibration stage: fitted values (model units), named errors, what data it used, notes."""

    stage: str
    values: dict[str, float] = field(default_factory=dict)
    errors: dict[str, float] = field(default_factory=dict)
    trials: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    skipped: str | None = None
    fit: FitResult | None = None

    def summary(self) -> str:
        if self.skipped:
            return f"[{self.stage}] skipped: {self.skipped}"
        vals = ", ".join(f"{k} = {v:.6g}" for k, v in self.values.items())
        errs = ", ".join(f"{k} {v:.4g}" for k, v in self.errors.items())
        lines = [f"[{self.stage}] {vals}", f"    errors: {errs}", f"    data: {', '.join(self.trials)}"]
        lines += [f"    note: {n}" for n in self.notes]
        return "\n".join(lines)


# ------------------------------------------------------------------------------------------------ helpers


def _isometric_length(trial: Trial) -> float | None:
    """The trial's constant length (mm), or None when its length varies (> 1e-6 mm)."""
    if trial.length is None:
        return None if trial.length_const is None else float(trial.length_const)
    x = np.asarray(trial.length, dtype=float)
    return float(x[0]) if np.ptp(x) <= 1e-6 else None


def _model_units(trial: Trial) -> bool:
    return trial.force_unit == "N" and trial.length_unit == "mm"


def _pairs(name: str, x: Sequence[float], y: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    xa, ya = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
    if xa.size != ya.size:
        raise InputError(f"{name}: {xa.size} abscissae but {ya.size} forces")
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ya))):
        raise InputError(f"{name}: values must be finite")
    return xa, ya


# ------------------------------------------------------------------------------------------- Module 3: KSE


def calibrate_kse(step_trial: Trial, P0: float, *, pre_ms: float = 5.0, post_ms: float = 5.0) -> StageResult:
    """KSE (1/mm) = force drop (N) / length step (mm) / P0 (N) from a step-shortening trial (seed 2.2.2)."""
    if not _model_units(step_trial):
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
                       ["direct estimate (seed 2.2.2); CE shortening during a finite ramp biases it low"])


# ----------------------------------------------------------------------------------- Module 3: force-length


def gaussian_force_length(x: np.ndarray, g1: float, g2: float, P0: float) -> np.ndarray:
    """Eq 12 at full activation: P0 exp(-((x - g1)/g2)^2)."""
    return P0 * np.exp(-(((np.asarray(x, dtype=float) - g1) / g2) ** 2))


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


# --------------------------------------------------------------------------------- Module 3: force-velocity


def hill_tension(v: np.ndarray, a0: float, b0: float, P0: float) -> np.ndarray:
    """Eq 10 at Fc = P0 solved for the tension at shortening velocity v (< 0)."""
    return (b0 * P0 + a0 * v) / (b0 - v)


def mashima_tension(v: np.ndarray, c0: float, d0: float, P0: float) -> np.ndarray:
    """Eq 11 at Fc = P0 solved for the tension at lengthening velocity v (> 0)."""
    return (d0 * P0 + (2.0 * P0 + c0) * v) / (d0 + v)


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
    if s.sum() == 2 and l_.sum() == 2:
        values = hill_mashima_coefficients(list(zip(v[s | l_], T[s | l_])), P0)
        notes.append("closed form from four points (eqs 13-16)")
    else:
        # linear starts: V a0 + b0 (P0 - T) = -V T;  V c0 + d0 (P0 - T) = -V (2 P0 - T)
        vs, ts, vl, tl = v[s], T[s], v[l_], T[l_]
        a_s, b_s = np.linalg.lstsq(np.column_stack([vs, P0 - ts]), -vs * ts, rcond=None)[0]
        c_s, d_s = np.linalg.lstsq(np.column_stack([vl, P0 - tl]), -vl * (2 * P0 - tl), rcond=None)[0]
        span = max(np.max(np.abs(v)), 1e-12)
        a_s, b_s = (a_s if a_s > 0 else 0.2 * P0), (b_s if b_s > 0 else span)
        d_s = d_s if d_s > 0 else span
        rs = least_squares(lambda p: hill_tension(vs, p[0], p[1], P0) - ts, [a_s, b_s],
                           bounds=([1e-9 * P0, 1e-9 * span], [np.inf, np.inf]))
        rl = least_squares(lambda p: mashima_tension(vl, p[0], p[1], P0) - tl, [c_s, d_s],
                           bounds=([-np.inf, 1e-9 * span], [np.inf, np.inf]))
        values = {"a0": float(rs.x[0]), "b0": float(rs.x[1]), "c0": float(rl.x[0]), "d0": float(rl.x[1])}
        notes.append(f"least squares through {int(s.sum())} shortening and {int(l_.sum())} lengthening points")
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


# --------------------------------------------------------------------------------------------- Module 2


def module2_trials(data: MeasuredData | Sequence[Trial], g1: float,
                   tolerance_mm: float = OPTIMUM_TOLERANCE_MM) -> list[Trial]:
    """Isometric, stimulated trials in N/mm within tolerance_mm of the optimum g1 (mm)."""
    trials = list(data.trials.values()) if isinstance(data, MeasuredData) else list(data)
    out = []
    for t in trials:
        x = _isometric_length(t)
        if _model_units(t) and x is not None and abs(x - g1) <= tolerance_mm and np.size(t.stimulus_times_s):
            out.append(t)
    return out


def _select(data: MeasuredData, trials: Sequence[str] | None) -> list[Trial] | None:
    if trials is None:
        return None
    missing = [t for t in trials if t not in data.trials]
    if missing:
        raise InputError(f"trial(s) {missing} not in the data (have: {', '.join(data.trials)})")
    return [data.trials[t] for t in trials]


def calibrate_module2(data: MeasuredData, base_params: ParameterSet, trials: Sequence[str] | None = None, *,
                      free: Sequence[str] = MODULE2_FREE, options: SimulationOptions | None = None,
                      objective: str = "nrmse", workers: int = 1, max_iterations: int = 30,
                      progress: bool = False) -> StageResult:
    """Fit a Module 2 subset (default C1, C2, C3, alpha) to twitches and sub-tetanic trains at the optimum.

    trials: ids to use (default: every isometric stimulated trial within 0.5 mm of g1).  Flags of
    unidentifiable parameters (fitting's SVD / relative-SE test) are reported in ``notes``."""
    chosen = _select(data, trials)
    if chosen is None:
        chosen = module2_trials(data, base_params["g1"])
    if not chosen:
        raise InputError(f"Module 2: no isometric stimulated trial (N, mm) at the optimum g1 = "
                         f"{base_params['g1']:g} mm")
    opts = options or SimulationOptions(dt_ms=0.05, settle_ms=300.0)
    problem = FitProblem(chosen, base_params, list(free), objective=objective, options=opts)
    res = fit(problem, workers=workers, progress=progress, max_iterations=max_iterations)
    errors: dict[str, float] = {f"nrmse_{k}": v for k, v in res.nrmse_percent.items()}
    errors.update({f"se_{k}": v for k, v in res.std_errors.items()})
    notes = [f"{n} NOT IDENTIFIABLE: {why}" for n, why in res.flags.items()]
    notes.append(f"{res.n_iterations} iterations, {res.n_simulations} simulations, {res.wall_time_s:.1f} s: "
                 f"{res.message}")
    return StageResult("module2", dict(res.estimates), errors, [t.trial_id for t in chosen], notes, fit=res)


# ----------------------------------------------------------------------------------- length compensation


def twitch_trials(data: MeasuredData | Sequence[Trial]) -> list[Trial]:
    """Isometric single-stimulus trials in N/mm."""
    trials = list(data.trials.values()) if isinstance(data, MeasuredData) else list(data)
    return [t for t in trials if _model_units(t) and _isometric_length(t) is not None
            and np.size(t.stimulus_times_s) == 1]


def _with_constant_phi(params: ParameterSet, phi: float) -> ParameterSet:
    return params.with_values(phi1=0.0, phi2=phi, phi3=0.0, phi4=phi)


def calibrate_length_compensation(data: MeasuredData, params: ParameterSet, trials: Sequence[str] | None = None,
                                  *, options: SimulationOptions | None = None,
                                  phi_range: tuple[float, float] = (0.2, 4.0),
                                  xtol: float = 1e-4) -> StageResult:
    """phi1..phi4 (eq 18) from twitches at >= 2 lengths: per twitch, the constant phi whose simulated twitch
    peak equals the measured peak (brentq), then length_compensation_coefficients at x_opt = g1."""
    from scipy.optimize import brentq

    chosen = _select(data, trials)
    if chosen is None:
        chosen = twitch_trials(data)
    lengths = sorted({round(_isometric_length(t), 9) for t in chosen if _isometric_length(t) is not None})
    if len(lengths) < 2:
        raise InputError(f"length compensation: twitches at >= 2 lengths are needed, got lengths {lengths}")
    opts = options or SimulationOptions(dt_ms=0.05, settle_ms=300.0)

    def sim(p: ParameterSet, t: Trial) -> np.ndarray:
        return trial_simulation(p, t, opts.dt_ms, record_dt_ms=opts.record_dt_ms, settle_ms=opts.settle_ms,
                                length_compensation=True, movement_compensation=False)

    points, errors, notes = [], {}, []
    for t in chosen:
        x = float(_isometric_length(t))
        f = np.asarray(t.force, dtype=float)
        target = float(np.max(np.convolve(f, np.ones(3) / 3.0, mode="same"))) if f.size >= 3 else float(f.max())

        def gap(phi: float) -> float:
            return float(np.max(sim(_with_constant_phi(params, phi), t))) - target

        lo, hi = phi_range
        glo, ghi = gap(lo), gap(hi)
        if glo * ghi > 0:
            raise InputError(f"trial '{t.trial_id}': no phi in [{lo}, {hi}] matches the twitch peak "
                             f"{target:.4g} N (simulated peaks {glo + target:.4g} .. {ghi + target:.4g} N)")
        phi = float(brentq(gap, lo, hi, xtol=xtol))
        points.append((x, phi))
        errors[f"phi_at_{x:g}mm"] = phi
    # the split point: the twitch length nearest g1 when within OPTIMUM_TOLERANCE_MM (a fitted g1 is rarely
    # exactly the length of the optimum trials), else g1 itself
    near = min(lengths, key=lambda x: abs(x - params["g1"]))
    x_split = near if abs(near - params["g1"]) <= OPTIMUM_TOLERANCE_MM else params["g1"]
    split = (sum(1 for x in lengths if x <= x_split) >= 2 and sum(1 for x in lengths if x >= x_split) >= 2)
    coeffs = length_compensation_coefficients(points, x_split, split=split)
    if not split:
        notes.append("fewer than two lengths on one side of g1: one line through all points")
    final = params.with_values(**coeffs)
    for t in chosen:
        errors[f"nrmse_{t.trial_id}"] = nrmse_percent(t.force, sim(final, t))
    notes.append("phi per length makes the simulated twitch peak equal the measured one")
    return StageResult("length-compensation", coeffs, errors, [t.trial_id for t in chosen], notes)


# ------------------------------------------------------------------------------------------------ chained


@dataclass
class StagedCalibration:
    """All stages in order and the final parameter set."""

    parameters: ParameterSet
    stages: list[StageResult]

    def stage(self, name: str) -> StageResult:
        for s in self.stages:
            if s.stage == name:
                return s
        raise KeyError(name)

    def summary(self) -> str:
        return "\n".join(s.summary() for s in self.stages)


def _points_from(data: MeasuredData, path: str) -> np.ndarray | None:
    arr = data.extra_datasets.get(path)
    if arr is None:
        return None
    a = np.asarray(arr, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"{path}: expected an (n, 2) dataset, got shape {a.shape}")
    return a


def staged_calibration(data: MeasuredData, base_params: ParameterSet, *, module2_free: Sequence[str] = MODULE2_FREE,
                       options: SimulationOptions | None = None, workers: int = 1, max_iterations: int = 30,
                       progress: bool = False, name: str | None = None) -> StagedCalibration:
    """Module 3 (force-length, force-velocity, KSE) -> Module 2 -> length compensation, on whatever ``data``
    holds; a stage without its data is skipped with the reason (the base values stay)."""
    params = base_params
    stages: list[StageResult] = []
    fl = _points_from(data, FORCE_LENGTH_PATH)
    if fl is None:
        stages.append(StageResult("force-length", skipped=f"no {FORCE_LENGTH_PATH} points"))
    else:
        r = calibrate_force_length(fl[:, 0], fl[:, 1])
        params = params.with_values(**r.values)
        stages.append(r)
    fv = _points_from(data, FORCE_VELOCITY_PATH)
    if fv is None:
        stages.append(StageResult("force-velocity", skipped=f"no {FORCE_VELOCITY_PATH} points"))
    else:
        r = calibrate_force_velocity(fv[:, 0], fv[:, 1], params["P0"])
        params = params.with_values(**r.values)
        stages.append(r)
    steps = [t for t in data.trials.values() if t.protocol == "step" and t.length is not None and _model_units(t)]
    if not steps:
        stages.append(StageResult("KSE", skipped="no step-shortening trial (protocol 'step' with a length trace)"))
    else:
        rs = [calibrate_kse(t, params["P0"]) for t in steps]
        kse = float(np.mean([r.values["KSE"] for r in rs]))
        r = StageResult("KSE", {"KSE": kse}, {**rs[0].errors, "n_trials": float(len(rs)),
                                              "spread": float(np.ptp([r.values["KSE"] for r in rs]))},
                        [t.trial_id for t in steps], rs[0].notes + (["mean over trials"] if len(rs) > 1 else []))
        params = params.with_values(KSE=kse)
        stages.append(r)
    m2 = module2_trials(data, params["g1"])
    if not m2:
        stages.append(StageResult("module2", skipped=f"no isometric stimulated trial at g1 = {params['g1']:g} mm"))
    else:
        r = calibrate_module2(data, params, [t.trial_id for t in m2], free=module2_free, options=options,
                              workers=workers, max_iterations=max_iterations, progress=progress)
        params = params.with_values(**r.values)
        stages.append(r)
    tw = twitch_trials(data)
    n_len = len({round(_isometric_length(t), 9) for t in tw})
    if n_len < 2:
        stages.append(StageResult("length-compensation", skipped=f"twitches at {n_len} length(s); >= 2 needed"))
    else:
        r = calibrate_length_compensation(data, params, [t.trial_id for t in tw], options=options)
        params = params.with_values(**r.values)
        stages.append(r)
    final = ParameterSet(name or f"{base_params.name}-calibrated", params.values,
                         f"staged calibration from {base_params.name} on {data.path or 'data in memory'}")
    return StagedCalibration(final, stages)


# ----------------------------------------------------------------------------------------------- real data


def _plateau(force: np.ndarray, frac: float = 0.8) -> float:
    """Median of the middle half of the samples at or above frac * max (the tetanic plateau)."""
    idx = np.flatnonzero(force >= frac * np.max(force))
    a, b = idx[0], idx[-1]
    mid = force[a + (b - a) // 4: b - (b - a) // 4 + 1]
    return float(np.median(mid))


def real_data_calibration(real_data_dir: str | Path) -> dict[str, Any]:
    """Module 3 calibration against real cat soleus data (numbers only; no simulation).

    Scott, Brown & Loeb 1996 (cat_digitized_literature): g1 (L0), g2 (L0), P0 (F0) from the active tetanic
    force-length points of five specimens; a0 (F0), b0 (L0/s), c0 (F0), d0 (L0/s) by least squares through
    the force-velocity points with P0 = 1 F0 (normalised units; multiply by P0 (N) and L0 (mm) of a given
    muscle to get model units).  Errors: RMS and max |residual| in F0.

    Herzog & Leonard 2002 (cat_soleus_herzog_leonard_2002): isometric plateau forces at the paper's 0 and
    +9 mm, passive force at +9 mm, active force ratio F(9)/F(0), and the peak force at the end of the 0->9 mm
    stretches over the isometric force at 9 mm (force enhancement + velocity, per speed).  NOT calibratable
    from these traces: KSE (no step or quick release), Module 2 (stimulus times unknown, single supramaximal
    rate), g1/g2 in mm (two lengths only, and the paper's 0 mm is not the model's reference), c0/d0 (the force
    at the stretch end includes history-dependent enhancement that the model does not have)."""
    from .literature import load_herzog_leonard_2002, load_scott_brown_loeb_1996

    root = Path(real_data_dir)
    out: dict[str, Any] = {}
    sbl = load_scott_brown_loeb_1996(root / "cat_digitized_literature")
    fl = calibrate_force_length(sbl.active_length_L0, sbl.active_force_F0)
    fl1 = calibrate_force_length(sbl.active_length_L0, sbl.active_force_F0, fix_P0=1.0)
    fv = calibrate_force_velocity(sbl.velocity_L0_per_s, sbl.velocity_force_F0, 1.0)
    out["scott_brown_loeb_1996"] = {
        "force_length": {"g1_L0": fl.values["g1"], "g2_L0": fl.values["g2"], "P0_F0": fl.values["P0"],
                         "rms_F0": fl.errors["rms"], "max_abs_F0": fl.errors["max_abs"],
                         "n_points": int(fl.errors["n_points"]),
                         "P0_fixed_1": {"g1_L0": fl1.values["g1"], "g2_L0": fl1.values["g2"],
                                        "rms_F0": fl1.errors["rms"]}},
        "force_velocity": {"a0_F0": fv.values["a0"], "b0_L0_per_s": fv.values["b0"], "c0_F0": fv.values["c0"],
                           "d0_L0_per_s": fv.values["d0"], "rms_F0": fv.errors["rms"],
                           "rms_shortening_F0": fv.errors["rms_shortening"],
                           "rms_lengthening_F0": fv.errors["rms_lengthening"],
                           "vmax_L0_per_s": fv.errors["vmax"],
                           "lengthening_asymptote_F0": fv.errors["lengthening_asymptote_over_P0"],
                           "n_points": int(np.sum(sbl.velocity_L0_per_s != 0))},
        "notes": ["normalised units: lengths in L0, forces in F0, velocities in L0/s",
                  "CT09 for comparison (P0 = 23 N): a0/P0 = 0.102, c0/P0 = -0.32, asymptote 1.68 F0"],
    }
    hl = load_herzog_leonard_2002(root / "cat_soleus_herzog_leonard_2002")
    iso0_by = {t.trial_id: _plateau(t.force) for t in hl.trials.values() if t.protocol == "isometric"
               and t.attrs["start_length_mm"] == 0.0}
    iso0 = list(iso0_by.values())
    iso9 = {t.attrs["figure"]: _plateau(t.force) for t in hl.trials.values() if t.protocol == "isometric"
            and t.attrs["start_length_mm"] == 9.0}
    passive9 = [float(np.median(t.force[-100:])) for t in hl.trials.values() if t.protocol == "passive"]
    stretch = {}
    for t in hl.trials.values():
        if t.protocol == "stretch" and t.attrs["start_length_mm"] == 0.0 and t.attrs["figure"] in iso9:
            i_end = int(np.argmax(t.length >= 8.9))
            f_end = float(np.max(t.force[max(i_end - 5, 0): i_end + 5]))
            stretch[t.trial_id] = {
                "speed_mm_s": float(t.attrs.get("stretch_speed_nominal_mm_s", t.attrs["ramp_speed_estimated_mm_s"])),
                "peak_end_of_stretch_N": f_end, "over_isometric_9mm": f_end / iso9[t.attrs["figure"]]}
    p9 = float(np.mean(passive9))
    a0m, a9m = float(np.mean(iso0)), float(np.mean(list(iso9.values())))
    out["herzog_leonard_2002"] = {
        "isometric_0mm_N": {"mean": a0m, "sd": float(np.std(iso0)), "n": len(iso0), "per_trial": iso0_by},
        "isometric_9mm_N": {"mean": a9m, "sd": float(np.std(list(iso9.values()))), "n": len(iso9),
                            "per_figure": iso9},
        "passive_9mm_N": {"mean": p9, "n": len(passive9)},
        "active_ratio_9mm_over_0mm": (a9m - p9) / a0m,
        "stretch_0_to_9mm": stretch,
        "not_calibrated": ["KSE: no step shortening or quick release in the traces",
                           "Module 2: stimulus times unknown (constant supramaximal train, ~30 Hz unverified)",
                           "g1/g2 in mm: two lengths only, paper's 0 mm is not the model reference",
                           "c0/d0: stretch forces include force enhancement (history dependence not modelled)"],
        "P0_estimate_N": max(a0m, a9m - p9),
        "P0_note": "lower bound on P0 (largest active isometric plateau; the optimum may lie between 0 and 9 mm)",
    }
    return out
