"""The numbers of each section of the twitch-to-tetanus workflow's report, steps (b)-(e) of ``workflow``."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from .contraction import moment_rise_time_s
from .data import Twitch
from .excitation import NU_REFERENCE_RATE_HZ, TrendFit, fit_trend_to_full_model, trend_active_state_rise_time_s
from .twitch_fit import SEED_TRAIN_RATES_HZ, TrainPrediction, TwitchFit, fit_twitch, predict_trains, twitch_moment
from ..model.hatze_parameters import (THETA_NAMES, THETA_UNITS, ExcitationTheta, Subject, load_subjects,
                                      load_theta_intervals,
                         load_trend_table)

#: Seed 3.3: mean rise time of moment under q = 1 (s) and of the trend model's active state (s).
SEED_MOMENT_RISE_TIME_S: float = 0.200
SEED_ACTIVE_STATE_RISE_TIME_S: float = 0.142
#: Normalised stimulation levels (nu = rate / 100 Hz) over which the active-state rise time is averaged (our choice).
ACTIVE_STATE_LEVELS_NU: tuple[float, float] = (0.2, 1.0)


def _slow_roots(theta: ExcitationTheta) -> list[float]:
    return sorted(float(abs(np.roots([1.0, a, b])).min())
                  for a, b in ((theta.theta1, theta.theta2), (theta.theta3, theta.theta4)))


def _gain(theta: ExcitationTheta) -> float:
    return theta.theta5 / (theta.theta2 * theta.theta4)


def fit_section(twitch: Twitch, subj: Subject, table2: ExcitationTheta, start_factors: Sequence[float], *,
                frozen: Sequence[str], max_evaluations: int, step_s: float
                ) -> tuple[TwitchFit, dict[str, Any], NDArray[np.float64]]:
    """(b) Fit of ``twitch`` from Table 2 times ``start_factors`` (contraction step ``step_s``, s): the fit, its
    report section and the fitted moment (N m)."""
    start = ExcitationTheta.from_array(table2.as_array() * np.asarray(start_factors))
    stim = twitch.info["stim_time_s"]
    fit = fit_twitch(twitch.t_s, twitch.moment_nm, [stim], subj, start, step_s=step_s, frozen=tuple(frozen),
                     max_evaluations=max_evaluations)
    intervals = load_theta_intervals()
    model, dm = twitch_moment(twitch.t_s, [stim], subj, fit.theta, step_s, sensitivities=True)
    sv = np.linalg.svd(dm * fit.theta.as_array()[None, :], compute_uv=False)   # dM/d ln theta, N m
    params = {}
    for n in THETA_NAMES:
        iv = intervals[n]
        est = float(getattr(fit.theta, n))
        params[n] = {"unit": THETA_UNITS[n], "estimate": est, "lower": fit.lower[n], "upper": fit.upper[n],
                     "frozen": n in fit.frozen, "poorly_identified": fit.poorly_identified[n], "vif": fit.vif[n],
                     "seed": {"value": iv.value, "lower": iv.lower, "upper": iv.upper},
                     "inside_seed_interval": iv.contains(est)}
    sec = {"method": "Levenberg-Marquardt in ln theta, Jacobian from sensitivity equations (twitch_fit.fit_twitch)",
           "parameters": params, "rms_residual_nm": fit.rms_nm, "n_evaluations": fit.n_evaluations,
           "stop_message": fit.message, "frozen": list(fit.frozen),
           "singular_values_dM_dlntheta_nm": sv,
           "identifiable_combinations": {
               "mean_slow_rate_per_s": {"ours": float(np.mean(_slow_roots(fit.theta))),
                                        "table2": float(np.mean(_slow_roots(table2)))},
               "gain_theta5_over_theta2_theta4": {"ours": _gain(fit.theta), "table2": _gain(table2)}},
           "peak_moment_nm": {"data": float(np.max(twitch.moment_nm)), "model": float(np.max(model))},
           "start": {"theta": dict(zip(THETA_NAMES, start.as_array())), "factors_on_table2": start_factors}}
    return fit, sec, model


def train_section(theta: ExcitationTheta, subj: Subject, table2: ExcitationTheta, *, duration_s: float,
                  t_end_s: float, step_s: float) -> tuple[list[TrainPrediction], dict[str, Any]]:
    """(c) Isometric trains of ``duration_s`` (s, simulated to ``t_end_s``) at the paper's rates with ``theta``,
    Table 2's peaks beside: the predictions and the section."""
    dur = duration_s
    preds = predict_trains(theta, subj, SEED_TRAIN_RATES_HZ, dur, t_end_s, step_s)
    preds_t2 = predict_trains(table2, subj, SEED_TRAIN_RATES_HZ, dur, t_end_s, step_s)
    rows = _train_summary(preds, dur)
    for r, r2 in zip(rows, _train_summary(preds_t2, dur)):
        r["peak_moment_table2_theta_nm"] = r2["peak_moment_nm"]
    return preds, {"subject": subj.name, "duration_s": dur, "rows": rows,
                   "mean_peak_moment_nm": float(np.mean([r["peak_moment_nm"] for r in rows])),
                   "seed": "Fig 8: mean measured vs model peaks (no numbers); the model underestimates high-rate "
                           "moments, relaxes slower than measured, and shows no negative staircase"}


def _train_summary(preds: Sequence[TrainPrediction], train_s: float) -> list[dict[str, float]]:
    rows = []
    for p in preds:
        tr = p.trace
        k_end = int(np.searchsorted(tr.t_s, train_s, side="right")) - 1
        # the last stimulus period before the end of the train: its maximum versus the peak (staircase)
        last = (tr.t_s > train_s - 1.0 / p.rate_hz) & (tr.t_s <= train_s + 1.0 / p.rate_hz)
        rows.append({"rate_hz": p.rate_hz, "peak_moment_nm": p.peak_moment_nm,
                     "last_period_max_over_peak": float(tr.moment_nm[last].max() / p.peak_moment_nm),
                     "moment_at_train_end_nm": float(tr.moment_nm[k_end])})
    return rows


def trend_section(theta: ExcitationTheta, table2: ExcitationTheta, subj: Subject, *, window_s: float,
                  dt_s: float) -> tuple[TrendFit, dict[str, Any]]:
    """(d) Trend functions fitted at 100 Hz over ``window_s`` (grid ``dt_s``, s) for Table 2's theta and
    ``theta``, Table 3 beside: Table 2's trend fit and the section."""
    window, dt = window_s, dt_s
    trend_t2 = fit_trend_to_full_model(table2, NU_REFERENCE_RATE_HZ, window, dt_s=dt)
    trend_t2_1s = fit_trend_to_full_model(table2, NU_REFERENCE_RATE_HZ, 1.0, dt_s=min(dt, 5e-4))
    trend_ours = fit_trend_to_full_model(theta, NU_REFERENCE_RATE_HZ, window, dt_s=dt)
    table3 = load_trend_table()
    rows = {}
    for name in load_subjects():
        seed_row = table3.get(name)
        rows[name] = {
            "theta_source": "Table 2 (subject 3's theta; the paper publishes no other)",
            "reproduction": name == "3",
            "m_per_s": trend_t2.params.m, "m_ci": trend_t2.m_ci,
            "c_raw_s4": trend_t2.params.c, "x_theta5_c": table2.theta5 * trend_t2.params.c,
            "seed": None if seed_row is None else {
                "m_per_s": seed_row["m"].value, "m_ci": (seed_row["m"].lower, seed_row["m"].upper),
                "c_mol_per_L": seed_row["c"].value, "c_ci": (seed_row["c"].lower, seed_row["c"].upper)}}
    return trend_t2, {
        "rate_hz": NU_REFERENCE_RATE_HZ, "window_s": window, "dt_s": dt,
        "c_convention": "c_raw in s^4 (raw gamma of eqs 6-7); x = theta5 c_raw is the dimensionless "
                        "argument of eq 9 at xi = 1 and nu = 1; Table 3 gives c in mol/L",
        "subjects": rows,
        "table2_theta_1s_window": {"m_per_s": trend_t2_1s.params.m, "c_raw_s4": trend_t2_1s.params.c},
        "fitted_theta": {"subject": subj.name, "m_per_s": trend_ours.params.m, "m_ci": trend_ours.m_ci,
                         "c_raw_s4": trend_ours.params.c, "x_theta5_c": theta.theta5 * trend_ours.params.c}}


def rise_time_section(subjects: dict[str, Subject], trend_t2: TrendFit, table2: ExcitationTheta, *, m_fit: float,
                      x_fit: float, step_s: float) -> dict[str, Any]:
    """(e) Rise times (s) of the moment under q = 1 and of the trend model's active state, per subject, and of
    the fitted theta's trend (``m_fit``, 1/s; ``x_fit`` at nu = 1): the section."""
    moment_rt = {k: moment_rise_time_s(s, step_s=step_s) for k, s in subjects.items()}
    table3 = load_trend_table()
    x3 = table2.theta5 * trend_t2.params.c
    k_conv = x3 / table3["3"]["c"].value                   # L/mol, from subject 3
    as_rt = {}
    for k in subjects:
        if k == "3":
            m_k, x_k, src = trend_t2.params.m, x3, "our trend fit (Table 2 theta)"
        else:
            m_k, x_k = table3[k]["m"].value, k_conv * table3[k]["c"].value
            src = "Table 3 m; x = K c_Table3 with K from subject 3"
        rts = [trend_active_state_rise_time_s(m_k, x_k * nu) for nu in ACTIVE_STATE_LEVELS_NU]
        as_rt[k] = {"m_per_s": m_k, "x_at_nu1": x_k, "source": src,
                    "rise_time_s_by_nu": dict(zip(map(str, ACTIVE_STATE_LEVELS_NU), rts)),
                    "mean_s": float(np.mean(rts))}
    rt_fit = [trend_active_state_rise_time_s(m_fit, x_fit * nu) for nu in ACTIVE_STATE_LEVELS_NU]
    return {"definition": "10 % to 90 % of the maximum (the paper's section 3.3)",
            "moment_q1_s": moment_rt, "moment_q1_mean_s": float(np.mean(list(moment_rt.values()))),
            "moment_q1_mean_seed_s": SEED_MOMENT_RISE_TIME_S,
            "active_state_levels_nu": ACTIVE_STATE_LEVELS_NU, "active_state_trend": as_rt,
            "active_state_trend_mean_s": float(np.mean([v["mean_s"] for v in as_rt.values()])),
            "active_state_trend_mean_seed_s": SEED_ACTIVE_STATE_RISE_TIME_S,
            "active_state_fitted_theta_mean_s": float(np.mean(rt_fit)),
            "k_conversion_L_per_mol": k_conv}
