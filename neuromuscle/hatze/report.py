"""Figures, Markdown and JSON form of the report of the twitch-to-tetanus workflow (van Zandwijk et al. 1998;
``workflow.run_twitch_to_tetanus``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray

from ..reports.figures import fit_figure, label_axes, legend, mark_times, new_figure, save_figure, set_title
from ..reports.markdown import fixed, in_ms, sig, table, value_range
from .contraction import simulate_active_state_drive
from .data import Twitch
from .excitation import (NU_REFERENCE_RATE_HZ, TrendFit, active_state_of_x, excitation_states, train_times,
                         trend_gamma)
from .twitch_fit import TrainPrediction
from ..model.hatze_parameters import ActiveStateConstants, ExcitationTheta, Subject

#: Figures written by :func:`write_figures`, in this order.
FIGURES: tuple[str, ...] = ("twitch_fit.png", "trains.png", "trend_fit.png", "rise_times.png")


def json_ready(x: Any) -> Any:
    """JSON-safe: numpy scalars/arrays to Python, tuples to lists, non-finite floats to None."""
    if isinstance(x, dict):
        return {str(k): json_ready(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_ready(v) for v in x]
    if isinstance(x, np.ndarray):
        return json_ready(x.tolist())
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(float(x)) else None
    return x


# ------------------------------------------------------------------------------------------- figures

def write_figures(out: Path, twitch: Twitch, model_nm: NDArray[np.float64], preds: Sequence[TrainPrediction],
                  table2: ExcitationTheta, trend_fit: TrendFit, rise: Mapping[str, Any],
                  subjects: Mapping[str, Subject], *, window_s: float, dt_s: float, step_s: float) -> list[str]:
    """Write :data:`FIGURES` into ``out``: the twitch fit, the predicted trains, the trend fit at 100 Hz over
    ``window_s`` (grid ``dt_s``, s) and the rise times (``rise``: the report's ``rise_times`` section; contraction
    step ``step_s``, s); returns their names."""
    figures = (_twitch_fit(twitch, model_nm), _trains(preds), _trend_fit(table2, trend_fit, window_s, dt_s),
               _rise_times(subjects, rise, step_s))
    for name, fig in zip(FIGURES, figures):
        save_figure(fig, out / name)
    return list(FIGURES)


def _twitch_fit(twitch: Twitch, model_nm: NDArray[np.float64]) -> Figure:
    fig, ax = fit_figure(twitch.t_s, twitch.moment_nm, model_nm, x="time (s)", y="moment (N m)",
                         residual_y="fit - data (N m)", points=True, measured_label="twitch (data)",
                         simulated_label="fit")
    if twitch.clean_nm is not None:
        ax[0].plot(twitch.t_s, twitch.clean_nm, "C2", lw=0.8, label="noise-free (Table 2 theta)")
    mark_times(ax[0], [twitch.info["stim_time_s"]])
    legend(ax[0])
    set_title(ax[0], f"twitch of subject {twitch.info['subject']} ({twitch.info['source']}) and the fit")
    return fig


def _trains(preds: Sequence[TrainPrediction]) -> Figure:
    fig, (ax,) = new_figure()
    for p in preds:
        ax.plot(p.trace.t_s, p.trace.moment_nm, label=f"{p.rate_hz:g} Hz (peak {p.peak_moment_nm:.1f} N m)")
    label_axes(ax, x="time (s)", y="moment (N m)")
    set_title(ax, "predicted isometric moment, 1 s trains (fitted theta)")
    legend(ax)
    return fig


def _trend_fit(table2: ExcitationTheta, trend_fit: TrendFit, window_s: float, dt_s: float) -> Figure:
    st = excitation_states(train_times(NU_REFERENCE_RATE_HZ, window_s), window_s, table2, dt_s)
    fig, (ax,) = new_figure()
    ax.plot(st.t_s, st.z[:, 2], "0.5", lw=0.6, label="gamma, eqs 6-7 (Table 2 theta), 100 Hz")
    ax.plot(st.t_s, trend_gamma(st.t_s, trend_fit.params.m, trend_fit.params.c), "C3",
            label=f"trend eq 10: m = {trend_fit.params.m:.2f} 1/s, c = {trend_fit.params.c:.3g} s^4")
    label_axes(ax, x="time (s)", y="gamma (s^4)")
    set_title(ax, "trend function fitted to the full model's gamma at 100 Hz")
    legend(ax)
    return fig


def _rise_times(subjects: Mapping[str, Subject], rise: Mapping[str, Any], step_s: float) -> Figure:
    fig, ax = new_figure(2, columns=True)
    q0 = ActiveStateConstants().q0
    for k, s in subjects.items():
        sol = simulate_active_state_drive(s, 1.0, 1.0, 0.0, step_s, q_initial=q0)
        ax[0].plot(sol.t_s, sol.moment_nm / sol.moment_nm.max(), label=f"subject {k}")
    tt = np.linspace(0.0, 1.0, 2001)
    for k, v in rise["active_state_trend"].items():
        for nu, ls in zip(rise["active_state_levels_nu"], ("--", "-")):
            ax[1].plot(tt, active_state_of_x(trend_gamma(tt, v["m_per_s"], v["x_at_nu1"] * nu)), ls,
                       color=f"C{int(k) - 1}", label=f"subject {k}, nu = {nu:g}")
    for a, y, title in zip(ax, ("moment / its maximum (dimensionless)", "active state q (dimensionless)"),
                           ("moment under q = 1", "trend model active state q")):
        for lev in (0.1, 0.9):
            a.axhline(lev, color="k", lw=0.5, ls=":")
        label_axes(a, x="time (s)", y=y)
        set_title(a, title, "10 % and 90 % dotted")
        legend(a, small=True)
    return fig


# ------------------------------------------------------------------------------------------- markdown

def render_markdown(rep: dict[str, Any]) -> str:
    """The human-readable report: inputs, then the table quantity | ours | paper | note."""
    fit = rep["fit"]
    lines = ["# From twitch to tetanus (van Zandwijk et al. 1998): workflow report", "", *_inputs(rep), ""]
    rows = [*_theta_rows(fit), *_train_rows(rep["trains"]), *_trend_rows(rep["trend"]),
            *_rise_rows(rep["rise_times"])]
    lines += table(("quantity", "ours", "paper", "note"), rows)
    lines += ["", "Figures: " + ", ".join(f"`{f}`" for f in rep.get("files", []) if f.endswith(".png")), ""]
    return "\n".join(lines)


def _inputs(rep: dict[str, Any]) -> list[str]:
    tw, fit, prov = rep["twitch"], rep["fit"], rep["provenance"]
    if tw["source"] == "synthetic":
        src = (f"**synthetic** twitch of subject {tw['subject']} made with Table 2's theta, plus Gaussian noise "
               f"{tw['noise_nm']} N m (seed {tw['seed']}); not measured data")
    else:
        src = f"CSV `{tw['path']}` (sha256 {tw['sha256'][:12]}...), subject {tw['subject']}"
    return [f"- Twitch: {src}; stimulus at {tw['stim_time_s']} s; {tw['n_samples']} samples.",
            f"- Fit: {fit['method']}; frozen: {', '.join(fit['frozen']) or 'none'}; "
            f"{fit['n_evaluations']} evaluations ({fit['stop_message']}); RMS residual "
            f"{fit['rms_residual_nm']:.4f} N m.",
            "- Singular values of dM/d ln theta at the estimate (N m): "
            + ", ".join(sig(v, 2) for v in fit["singular_values_dM_dlntheta_nm"])
            + ". Only the mean slow root and the gain theta5/(theta2 theta4) are well determined; theta1 leaves no "
            "trace in a twitch, and under noise of a few 0.01 N m theta2..theta5 drift along a flat valley, so "
            "whether they land inside the paper's (much narrower) intervals depends on the noise draw.",
            f"- Created {prov['created_utc']}; neuromuscle {prov['versions'].get('neuromuscle')}, numpy "
            f"{prov['versions'].get('numpy')}, scipy {prov['versions'].get('scipy')}."]


def _theta_rows(fit: dict[str, Any]) -> list[tuple[str, ...]]:
    rows = []
    for n, p in fit["parameters"].items():
        s = p["seed"]
        if p["frozen"]:
            note = "frozen at Table 2 (not identifiable from a twitch)"
        else:
            note = ("estimate inside" if p["inside_seed_interval"] else "estimate OUTSIDE") + " the paper's interval"
            note += "; flagged poorly identified" if p["poorly_identified"] else ""
        rows.append((f"{n} ({p['unit']})", value_range(p["estimate"], p["lower"], p["upper"]),
                     value_range(s["value"], s["lower"], s["upper"]), note))
    ic = fit["identifiable_combinations"]
    for quantity, key in (("mean slow root (1/s)", "mean_slow_rate_per_s"),
                          ("gain theta5/(theta2 theta4)", "gain_theta5_over_theta2_theta4")):
        rows.append((quantity, sig(ic[key]["ours"], 4), sig(ic[key]["table2"], 4),
                     "paper column computed from Table 2; well determined"))
    return rows


def _train_rows(tr: dict[str, Any]) -> list[tuple[str, ...]]:
    rows = [(f"peak moment {r['rate_hz']:g} Hz, subject {tr['subject']} (N m)", fixed(r["peak_moment_nm"]),
             "n/a (Fig 8)", f"Table 2 theta: {fixed(r['peak_moment_table2_theta_nm'])}; last period / peak "
             f"{fixed(r['last_period_max_over_peak'], 3)} (no negative staircase)") for r in tr["rows"]]
    rows.append(("mean peak moment 4-24 Hz (N m)", fixed(tr["mean_peak_moment_nm"]), "n/a (Fig 8)",
                 "the paper: the model underestimates high rates"))
    return rows


def _trend_rows(trend: dict[str, Any]) -> list[tuple[str, ...]]:
    rows = []
    for k, row in trend["subjects"].items():
        sd = row["seed"] or {}
        note = (f"window {trend['window_s']:g} s" if row["reproduction"] else
                "NOT a reproduction: subject's theta unpublished, computed with subject 3's Table 2 theta")
        m_ci = sd.get("m_ci", [None, None])
        rows.append((f"trend m, subject {k} (1/s)", fixed(row["m_per_s"]),
                     f"{sig(sd.get('m_per_s'))} ({sig(m_ci[0])}-{sig(m_ci[1])})", note))
        rows.append((f"trend c, subject {k}", f"{sig(row['c_raw_s4'])} s^4 (x = theta5 c = "
                     f"{fixed(row['x_theta5_c'])})", f"{sig(sd.get('c_mol_per_L'))} mol/L",
                     "conventions differ by a constant"))
    ft = trend["fitted_theta"]
    rows.append(("trend m, 1 s window, Table 2 theta (1/s)", fixed(trend["table2_theta_1s_window"]["m_per_s"]),
                 "7.94", "m depends on the window; the paper's value is met with 3-10 s"))
    rows.append(("trend m from our fitted theta (1/s)", fixed(ft["m_per_s"]), "7.94", f"subject {ft['subject']}"))
    return rows


def _rise_rows(rise: dict[str, Any]) -> list[tuple[str, ...]]:
    rows = [(f"moment rise time q = 1, subject {k} (ms)", in_ms(v), "n/a", "10-90 %")
            for k, v in rise["moment_q1_s"].items()]
    rows.append(("moment rise time q = 1, mean (ms)", in_ms(rise["moment_q1_mean_s"]),
                 in_ms(rise["moment_q1_mean_seed_s"]), "the paper's section 3.3, 'on average'"))
    levels = ", ".join(map(str, rise["active_state_levels_nu"]))
    for k, v in rise["active_state_trend"].items():
        per = ", ".join(in_ms(x) for x in v["rise_time_s_by_nu"].values())
        rows.append((f"active-state rise time, subject {k} (ms)", in_ms(v["mean_s"]), "n/a",
                     f"mean of nu = {levels}: {per} ms; {v['source']}"))
    rows.append(("active-state rise time, mean (ms)", in_ms(rise["active_state_trend_mean_s"]),
                 in_ms(rise["active_state_trend_mean_seed_s"]),
                 f"the paper's low/high levels unstated; ours nu = {levels}"))
    return rows
