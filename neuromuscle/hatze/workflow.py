"""The seed's "from twitch to tetanus" workflow (seed 000) in one reproducible call: ``run_twitch_to_tetanus``.

Steps (all SI: s, rad, N m):

(a) The twitch to fit: a CSV file (columns ``time_s``, ``moment_nm``; extra columns ignored; one stimulus at
    ``stim_time_s``), or - without a file - a *synthetic* isometric twitch of the chosen subject made with Table 2's
    theta, sampled at 1 kHz for 0.8 s, plus Gaussian noise of ``noise_nm`` (N m) from ``numpy.random.default_rng(seed)``.
(b) Fit of theta by Levenberg-Marquardt with the sensitivity-equation Jacobian (``fitting.fit_twitch``). theta1 is
    frozen at Table 2 by default: the twitch carries no information on it (fitting.py docstring); theta2..theta5
    start from Table 2 times ``start_factors`` (default 2, 0.5, 0.5, 2) so that the fit has to find them. Reported:
    estimates, 95 % intervals, identifiability flags, VIFs, and the singular values of dM/d ln theta (all five) at
    the estimate.
(c) Isometric predictions for 1 s trains at 4, 8, 12, 16, 24 Hz (peak moment, and moment at the end of the train
    over the peak, the model's answer to the measured negative staircase), with our theta and with Table 2's.
(d) Trend function (eq 10) fitted to gamma(t) of eqs 6-7 at 100 Hz over a train of ``trend_window_s`` (default 5 s;
    m depends on the window, see ``excitation.fit_trend_to_full_model``), for each subject with Table 3 beside.
    gamma does not involve the contraction parameters, and the seed publishes theta only for subject 3, so the
    rows of subjects 1, 2, 4 are computed with subject 3's theta and are *not* reproductions. c is reported on the
    raw scale of gamma in eqs 6-7 (s^4) and as x = theta5 c (dimensionless, the argument of eq 9 at xi = 1).
(e) Rise times (10-90 % of the maximum): of the moment under q = 1 for each subject (``moment_rise_time_s``), and of
    the trend model's active state, averaged over a low (nu = 0.2, 20 Hz) and a high (nu = 1, 100 Hz) level - the
    seed does not state its levels. For subject 3 the trend model is our fit; for the others, whose theta is
    unpublished, Table 3's m with x(nu = 1) = K c_Table3, K = x_3 / c_3,Table3 taken from subject 3 (assumes one
    conversion from mol/L to the dimensionless x for all subjects).
(f) Figures (matplotlib, Agg): ``twitch_fit.png``, ``trains.png``, ``trend_fit.png``, ``rise_times.png``.
(g) ``report.json`` (all numbers, the seed's beside ours, provenance) and ``report.md`` (table
    "quantity | ours | seed | note").

Bad inputs raise ``InputError`` naming the culprit; an existing report in ``out_dir`` is never replaced unless
``overwrite=True``.
"""

from __future__ import annotations

import csv
import datetime as _dt
import hashlib
import json
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..provenance import versions
from .contraction import DEFAULT_STEP_S, moment_rise_time_s, simulate_active_state_drive
from .excitation import (NU_REFERENCE_RATE_HZ, excitation_states, fit_trend_to_full_model, train_times,
                         trend_active_state_rise_time_s, trend_gamma)
from .twitch_fit import SEED_TRAIN_RATES_HZ, TwitchFit, fit_twitch, predict_trains, twitch_moment
from .parameters import (THETA_NAMES, THETA_UNITS, ActiveStateConstants, ExcitationTheta, Subject, check_positive,
                         load_subject, load_subjects, load_theta, load_theta_intervals, load_trend_table)

#: Columns a twitch CSV must have.
CSV_COLUMNS: tuple[str, str] = ("time_s", "moment_nm")
#: Files written into ``out_dir``.
REPORT_FILES: tuple[str, ...] = ("report.json", "report.md")
FIGURES: tuple[str, ...] = ("twitch_fit.png", "trains.png", "trend_fit.png", "rise_times.png")
#: Seed 3.3: mean rise time of moment under q = 1 (s) and of the trend model's active state (s).
SEED_MOMENT_RISE_TIME_S: float = 0.200
SEED_ACTIVE_STATE_RISE_TIME_S: float = 0.142
#: Normalised stimulation levels (nu = rate / 100 Hz) over which the active-state rise time is averaged (our choice).
ACTIVE_STATE_LEVELS_NU: tuple[float, float] = (0.2, 1.0)


# ------------------------------------------------------------------------------------------- inputs

def read_twitch_csv(path: str | Path) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Read a measured twitch: a CSV with a header holding ``time_s`` (s) and ``moment_nm`` (N m).

    Raises InputError naming the file and the missing column, or the row and column of a bad value.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"twitch CSV {str(path)!r} does not exist")
    with p.open(newline="") as fh:
        reader = csv.DictReader(fh)
        header = [h.strip() for h in (reader.fieldnames or [])]
        missing = [c for c in CSV_COLUMNS if c not in header]
        if missing:
            raise InputError(f"{path}: missing column(s) {', '.join(map(repr, missing))} "
                             f"(found: {', '.join(map(repr, header)) or 'no header'})")
        reader.fieldnames = header
        cols: dict[str, list[float]] = {c: [] for c in CSV_COLUMNS}
        for row_no, row in enumerate(reader, start=2):
            for c in CSV_COLUMNS:
                raw = row.get(c)
                try:
                    v = float(str(raw).strip())
                except ValueError:
                    raise InputError(f"{path}: row {row_no}, column {c!r}: not a number ({raw!r})") from None
                if not math.isfinite(v):
                    raise InputError(f"{path}: row {row_no}, column {c!r}: non-finite value ({raw!r})")
                cols[c].append(v)
    t, m = (np.asarray(cols[c], dtype=float) for c in CSV_COLUMNS)
    if t.size < 6:
        raise InputError(f"{path}: need at least 6 samples, got {t.size}")
    if np.any(np.diff(t) <= 0.0):
        raise InputError(f"{path}: column 'time_s' must increase strictly")
    if t[0] < 0.0:
        raise InputError(f"{path}: column 'time_s' must be >= 0 (got {t[0]})")
    return t, m


def synthetic_twitch(subject: Subject, theta: ExcitationTheta, noise_nm: float, seed: int,
                     stim_time_s: float = 0.02, duration_s: float = 0.8, sample_interval_s: float = 1e-3,
                     step_s: float = DEFAULT_STEP_S) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                              NDArray[np.float64]]:
    """Isometric twitch (N m) of ``subject`` under ``theta`` sampled every ``sample_interval_s`` for ``duration_s``
    (s), plus N(0, noise_nm^2) noise from ``default_rng(seed)``. Returns t (s), noisy moment, clean moment."""
    n = int(round(duration_s / sample_interval_s))
    t = np.arange(n + 1) * sample_interval_s
    clean = twitch_moment(t, [stim_time_s], subject, theta, step_s)[0]
    noisy = clean + np.random.default_rng(seed).normal(0.0, noise_nm, clean.size)
    return t, noisy, clean


def _check_out_dir(out_dir: str | Path, overwrite: bool) -> Path:
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"out_dir {str(out)!r} exists and is not a directory")
    existing = [f for f in REPORT_FILES if (out / f).exists()]
    if existing and not overwrite:
        raise InputError(f"out_dir {str(out)!r} already holds {', '.join(existing)}; "
                         "pass overwrite=True (--overwrite) to replace it")
    return out


# ------------------------------------------------------------------------------------------- helpers

def _num(x: Any) -> Any:
    """JSON-safe: numpy scalars/arrays to Python, non-finite floats to None."""
    if isinstance(x, dict):
        return {str(k): _num(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_num(v) for v in x]
    if isinstance(x, np.ndarray):
        return _num(x.tolist())
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    if isinstance(x, (np.floating, float)):
        return float(x) if math.isfinite(float(x)) else None
    return x


def _slow_roots(theta: ExcitationTheta) -> list[float]:
    return sorted(float(abs(np.roots([1.0, a, b])).min())
                  for a, b in ((theta.theta1, theta.theta2), (theta.theta3, theta.theta4)))


def _gain(theta: ExcitationTheta) -> float:
    return theta.theta5 / (theta.theta2 * theta.theta4)


def _fit_section(fit: TwitchFit, t: NDArray, m: NDArray, stim: float, subject: Subject, step_s: float,
                 table2: ExcitationTheta) -> tuple[dict, NDArray]:
    intervals = load_theta_intervals()
    model, dm = twitch_moment(t, [stim], subject, fit.theta, step_s, sensitivities=True)
    sv = np.linalg.svd(dm * fit.theta.as_array()[None, :], compute_uv=False)   # dM/d ln theta, N m
    params = {}
    for n in THETA_NAMES:
        iv = intervals[n]
        est = float(getattr(fit.theta, n))
        params[n] = {"unit": THETA_UNITS[n], "estimate": est, "lower": fit.lower[n], "upper": fit.upper[n],
                     "frozen": n in fit.frozen, "poorly_identified": fit.poorly_identified[n], "vif": fit.vif[n],
                     "seed": {"value": iv.value, "lower": iv.lower, "upper": iv.upper},
                     "inside_seed_interval": iv.contains(est)}
    sec = {"method": "Levenberg-Marquardt in ln theta, Jacobian from sensitivity equations (fitting.fit_twitch)",
           "parameters": params, "rms_residual_nm": fit.rms_nm, "n_evaluations": fit.n_evaluations,
           "stop_message": fit.message, "frozen": list(fit.frozen),
           "singular_values_dM_dlntheta_nm": sv,
           "identifiable_combinations": {
               "mean_slow_rate_per_s": {"ours": float(np.mean(_slow_roots(fit.theta))),
                                        "table2": float(np.mean(_slow_roots(table2)))},
               "gain_theta5_over_theta2_theta4": {"ours": _gain(fit.theta), "table2": _gain(table2)}},
           "peak_moment_nm": {"data": float(np.max(m)), "model": float(np.max(model))}}
    return sec, model


def _train_summary(preds, train_s: float) -> list[dict]:
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


# ------------------------------------------------------------------------------------------- the workflow

def run_twitch_to_tetanus(out_dir: str | Path, subject: str | int = "3", twitch_csv: str | Path | None = None,
                          noise_nm: float = 0.05, seed: int = 0, trend_window_s: float = 5.0, *,
                          stim_time_s: float = 0.02, overwrite: bool = False, frozen: Sequence[str] = ("theta1",),
                          start_factors: Sequence[float] = (1.0, 2.0, 0.5, 0.5, 2.0), max_evaluations: int = 200,
                          step_s: float = DEFAULT_STEP_S, trend_dt_s: float = 1e-3, train_duration_s: float = 1.0,
                          train_t_end_s: float = 1.5, figures: bool = True) -> dict[str, Any]:
    """Run steps (a)-(g) of the module docstring; write report.json, report.md and figures into ``out_dir``.

    ``subject``: Table 1 subject ("1".."4") whose contraction dynamics the twitch is fitted with (Table 2 is subject
    3's); ``twitch_csv``: measured twitch (``time_s`` s, ``moment_nm`` N m, times multiples of ``step_s``) with its
    stimulus at ``stim_time_s`` (s), or None for the synthetic twitch with ``noise_nm`` (N m) and ``seed``;
    ``trend_window_s``: 100 Hz train length (s) the trend function is fitted over; ``trend_dt_s`` its grid (s).
    Returns the report (the content of report.json).
    """
    out = _check_out_dir(out_dir, overwrite)
    subj = load_subject(subject)                           # InputError for unknown subjects
    noise = check_positive("noise_nm", noise_nm, allow_zero=True)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    window = check_positive("trend_window_s", trend_window_s)
    stim = check_positive("stim_time_s", stim_time_s, allow_zero=True)
    factors = np.asarray(start_factors, dtype=float)
    if factors.shape != (5,) or not np.all(np.isfinite(factors)) or np.any(factors <= 0):
        raise InputError(f"start_factors must be five finite numbers > 0, got {start_factors!r}")
    table2 = load_theta()

    # (a) the twitch
    if twitch_csv is not None:
        t, m_data = read_twitch_csv(twitch_csv)
        if not t[0] <= stim < t[-1]:
            raise InputError(f"stim_time_s = {stim} s lies outside the CSV's time_s range [{t[0]}, {t[-1]}] s")
        digest = hashlib.sha256(Path(twitch_csv).read_bytes()).hexdigest()
        twitch_info = {"source": "csv", "path": str(Path(twitch_csv).resolve()), "sha256": digest}
        clean = None
    else:
        t, m_data, clean = synthetic_twitch(subj, table2, noise, int(seed), stim, step_s=step_s)
        twitch_info = {"source": "synthetic", "theta": "Table 2 (subject 3)", "noise_nm": noise, "seed": int(seed),
                       "rng": "numpy.random.default_rng(seed).normal", "sample_interval_s": 1e-3,
                       "duration_s": float(t[-1])}
    twitch_info.update({"subject": subj.name, "stim_time_s": stim, "n_samples": int(t.size),
                        "peak_moment_nm": float(np.max(m_data))})

    # (b) fit
    start = ExcitationTheta.from_array(table2.as_array() * factors)
    fit = fit_twitch(t, m_data, [stim], subj, start, step_s=step_s, frozen=tuple(frozen),
                     max_evaluations=max_evaluations)
    fit_sec, model = _fit_section(fit, t, m_data, stim, subj, step_s, table2)
    fit_sec["start"] = {"theta": dict(zip(THETA_NAMES, start.as_array())), "factors_on_table2": factors}

    # (c) trains
    preds = predict_trains(fit.theta, subj, SEED_TRAIN_RATES_HZ, train_duration_s, train_t_end_s, step_s)
    preds_t2 = predict_trains(table2, subj, SEED_TRAIN_RATES_HZ, train_duration_s, train_t_end_s, step_s)
    ours_rows, t2_rows = _train_summary(preds, train_duration_s), _train_summary(preds_t2, train_duration_s)
    for r, r2 in zip(ours_rows, t2_rows):
        r["peak_moment_table2_theta_nm"] = r2["peak_moment_nm"]
    trains = {"subject": subj.name, "duration_s": train_duration_s, "rows": ours_rows,
              "mean_peak_moment_nm": float(np.mean([r["peak_moment_nm"] for r in ours_rows])),
              "seed": "Fig 8: mean measured vs model peaks (no numbers); the model underestimates high-rate "
                      "moments, relaxes slower than measured, and shows no negative staircase"}

    # (d) trend functions at 100 Hz
    trend_t2 = fit_trend_to_full_model(table2, NU_REFERENCE_RATE_HZ, window, dt_s=trend_dt_s)
    trend_t2_1s = fit_trend_to_full_model(table2, NU_REFERENCE_RATE_HZ, 1.0, dt_s=min(trend_dt_s, 5e-4))
    trend_ours = fit_trend_to_full_model(fit.theta, NU_REFERENCE_RATE_HZ, window, dt_s=trend_dt_s)
    table3 = load_trend_table()
    trend_rows = {}
    for name in load_subjects():
        seed_row = table3.get(name)
        trend_rows[name] = {
            "theta_source": "Table 2 (subject 3's theta; the seed publishes no other)",
            "reproduction": name == "3",
            "m_per_s": trend_t2.params.m, "m_ci": trend_t2.m_ci,
            "c_raw_s4": trend_t2.params.c, "x_theta5_c": table2.theta5 * trend_t2.params.c,
            "seed": None if seed_row is None else {
                "m_per_s": seed_row["m"].value, "m_ci": (seed_row["m"].lower, seed_row["m"].upper),
                "c_mol_per_L": seed_row["c"].value, "c_ci": (seed_row["c"].lower, seed_row["c"].upper)}}
    trend = {"rate_hz": NU_REFERENCE_RATE_HZ, "window_s": window, "dt_s": trend_dt_s,
             "c_convention": "c_raw in s^4 (raw gamma of eqs 6-7); x = theta5 c_raw is the dimensionless "
                             "argument of eq 9 at xi = 1 and nu = 1; Table 3 gives c in mol/L",
             "subjects": trend_rows,
             "table2_theta_1s_window": {"m_per_s": trend_t2_1s.params.m, "c_raw_s4": trend_t2_1s.params.c},
             "fitted_theta": {"subject": subj.name, "m_per_s": trend_ours.params.m, "m_ci": trend_ours.m_ci,
                              "c_raw_s4": trend_ours.params.c,
                              "x_theta5_c": fit.theta.theta5 * trend_ours.params.c}}

    # (e) rise times
    subjects = load_subjects()
    moment_rt = {k: moment_rise_time_s(s, step_s=step_s) for k, s in subjects.items()}
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
    rt_fit = [trend_active_state_rise_time_s(trend_ours.params.m, fit.theta.theta5 * trend_ours.params.c * nu)
              for nu in ACTIVE_STATE_LEVELS_NU]
    rise = {"definition": "10 % to 90 % of the maximum (seed 3.3)",
            "moment_q1_s": moment_rt, "moment_q1_mean_s": float(np.mean(list(moment_rt.values()))),
            "moment_q1_mean_seed_s": SEED_MOMENT_RISE_TIME_S,
            "active_state_levels_nu": ACTIVE_STATE_LEVELS_NU, "active_state_trend": as_rt,
            "active_state_trend_mean_s": float(np.mean([v["mean_s"] for v in as_rt.values()])),
            "active_state_trend_mean_seed_s": SEED_ACTIVE_STATE_RISE_TIME_S,
            "active_state_fitted_theta_mean_s": float(np.mean(rt_fit)),
            "k_conversion_L_per_mol": k_conv}

    report: dict[str, Any] = {
        "workflow": "seed 000 'from twitch to tetanus' (neuromuscle.hatze.workflow.run_twitch_to_tetanus)",
        "twitch": twitch_info, "fit": fit_sec, "trains": trains, "trend": trend, "rise_times": rise,
        "provenance": {"versions": {**versions(), "matplotlib": _mpl_version()},
                       "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                       "inputs": {"subject": subj.name, "twitch_csv": None if twitch_csv is None else str(twitch_csv),
                                  "noise_nm": noise, "seed": int(seed), "stim_time_s": stim,
                                  "trend_window_s": window, "trend_dt_s": trend_dt_s, "step_s": step_s,
                                  "frozen": list(frozen), "start_factors": factors,
                                  "max_evaluations": max_evaluations, "train_duration_s": train_duration_s,
                                  "train_t_end_s": train_t_end_s},
                       "seed_document": "/work/shared/seeds/000_637b96e18aae2ab4.txt (Tables 1-4, section 3)"},
    }
    report = _num(report)

    out.mkdir(parents=True, exist_ok=True)
    written = []
    if figures:
        written = _figures(out, t, m_data, clean, model, stim, preds, table2, trend_t2, window, trend_dt_s,
                           subjects, step_s, as_rt)
    report["files"] = [*REPORT_FILES, *written]
    (out / "report.json").write_text(json.dumps(report, indent=2))
    (out / "report.md").write_text(render_markdown(report))
    return report


def _mpl_version() -> str:
    try:
        import matplotlib
        return str(matplotlib.__version__)
    except ImportError:  # pragma: no cover
        return "not installed"


# ------------------------------------------------------------------------------------------- figures

def _figures(out: Path, t, m_data, clean, model, stim, preds, table2, trend_fit, window, dt, subjects, step_s,
             as_rt) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 5), gridspec_kw={"height_ratios": [3, 1]})
    ax[0].plot(t, m_data, ".", ms=2, color="0.5", label="twitch (data)")
    if clean is not None:
        ax[0].plot(t, clean, "C2", lw=0.8, label="noise-free (Table 2 theta)")
    ax[0].plot(t, model, "C3", label="fit")
    ax[0].axvline(stim, color="k", lw=0.5, ls=":")
    ax[0].set_ylabel("moment (N m)")
    ax[0].legend(fontsize=8)
    ax[1].plot(t, m_data - model, "k", lw=0.6)
    ax[1].set_ylabel("residual (N m)")
    ax[1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(out / "twitch_fit.png", dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4))
    for p in preds:
        ax.plot(p.trace.t_s, p.trace.moment_nm, label=f"{p.rate_hz:g} Hz (peak {p.peak_moment_nm:.1f} N m)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("moment (N m)")
    ax.set_title("predicted isometric moment, 1 s trains (fitted theta)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "trains.png", dpi=100)
    plt.close(fig)

    st = excitation_states(train_times(NU_REFERENCE_RATE_HZ, window), window, table2, dt)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(st.t_s, st.z[:, 2], "0.5", lw=0.6, label="gamma, eqs 6-7 (Table 2 theta), 100 Hz")
    ax.plot(st.t_s, trend_gamma(st.t_s, trend_fit.params.m, trend_fit.params.c), "C3",
            label=f"trend eq 10: m = {trend_fit.params.m:.2f} 1/s, c = {trend_fit.params.c:.3g} s^4")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("gamma (s^4)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "trend_fit.png", dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    q0 = ActiveStateConstants().q0
    for k, s in subjects.items():
        sol = simulate_active_state_drive(s, 1.0, 1.0, 0.0, step_s, q_initial=q0)
        ax[0].plot(sol.t_s, sol.moment_nm / sol.moment_nm.max(), label=f"subject {k}")
    tt = np.linspace(0.0, 1.0, 2001)
    from .excitation import active_state_of_x
    for k, v in as_rt.items():
        for nu, ls in zip(ACTIVE_STATE_LEVELS_NU, ("--", "-")):
            ax[1].plot(tt, active_state_of_x(trend_gamma(tt, v["m_per_s"], v["x_at_nu1"] * nu)), ls,
                       color=f"C{int(k) - 1}", label=f"subject {k}, nu = {nu:g}")
    for a, title in zip(ax, ("moment under q = 1 (normalised)", "trend model active state q")):
        for lev in (0.1, 0.9):
            a.axhline(lev, color="k", lw=0.5, ls=":")
        a.set_xlabel("time (s)")
        a.set_title(title, fontsize=9)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "rise_times.png", dpi=100)
    plt.close(fig)
    return list(FIGURES)


# ------------------------------------------------------------------------------------------- markdown

def _g(x: Any, digits: int = 3) -> str:
    return "n/a" if x is None else f"{x:.{digits}g}"


def render_markdown(rep: dict[str, Any]) -> str:
    """The human-readable report: inputs, then the table quantity | ours | seed | note."""
    tw, fit, tr, trend, rise = rep["twitch"], rep["fit"], rep["trains"], rep["trend"], rep["rise_times"]
    prov = rep["provenance"]
    if tw["source"] == "synthetic":
        src = (f"**synthetic** twitch of subject {tw['subject']} made with Table 2's theta, plus Gaussian noise "
               f"{tw['noise_nm']} N m (seed {tw['seed']}); not measured data")
    else:
        src = f"CSV `{tw['path']}` (sha256 {tw['sha256'][:12]}...), subject {tw['subject']}"
    lines = ["# From twitch to tetanus (seed 000): workflow report", "",
             f"- Twitch: {src}; stimulus at {tw['stim_time_s']} s; {tw['n_samples']} samples.",
             f"- Fit: {fit['method']}; frozen: {', '.join(fit['frozen']) or 'none'}; "
             f"{fit['n_evaluations']} evaluations ({fit['stop_message']}); RMS residual "
             f"{fit['rms_residual_nm']:.4f} N m.",
             "- Singular values of dM/d ln theta at the estimate (N m): "
             + ", ".join(_g(v, 2) for v in fit["singular_values_dM_dlntheta_nm"])
             + ". Only the mean slow root and the gain theta5/(theta2 theta4) are well determined; theta1 leaves no "
             "trace in a twitch, and under noise of a few 0.01 N m theta2..theta5 drift along a flat valley, so "
             "whether they land inside the seed's (much narrower) intervals depends on the noise draw.",
             f"- Created {prov['created_utc']}; neuromuscle {prov['versions'].get('neuromuscle')}, numpy "
             f"{prov['versions'].get('numpy')}, scipy {prov['versions'].get('scipy')}.", "",
             "| quantity | ours | seed | note |", "|---|---|---|---|"]
    for n, p in fit["parameters"].items():
        s = p["seed"]
        if p["frozen"]:
            note = "frozen at Table 2 (not identifiable from a twitch)"
        else:
            note = ("estimate inside" if p["inside_seed_interval"] else "estimate OUTSIDE") + " seed interval"
            note += "; flagged poorly identified" if p["poorly_identified"] else ""
        lines.append(f"| {n} ({p['unit']}) | {_g(p['estimate'])} ({_g(p['lower'], 2)}-{_g(p['upper'], 2)}) | "
                     f"{_g(s['value'])} ({_g(s['lower'], 2)}-{_g(s['upper'], 2)}) | {note} |")
    ic = fit["identifiable_combinations"]
    lines.append(f"| mean slow root (1/s) | {_g(ic['mean_slow_rate_per_s']['ours'], 4)} | "
                 f"{_g(ic['mean_slow_rate_per_s']['table2'], 4)} | seed column computed from Table 2; well determined |")
    lines.append(f"| gain theta5/(theta2 theta4) | {_g(ic['gain_theta5_over_theta2_theta4']['ours'], 4)} | "
                 f"{_g(ic['gain_theta5_over_theta2_theta4']['table2'], 4)} | seed column computed from Table 2; well determined |")
    for r in tr["rows"]:
        lines.append(f"| peak moment {r['rate_hz']:g} Hz, subject {tr['subject']} (N m) | "
                     f"{r['peak_moment_nm']:.2f} | n/a (Fig 8) | Table 2 theta: "
                     f"{r['peak_moment_table2_theta_nm']:.2f}; last period / peak "
                     f"{r['last_period_max_over_peak']:.3f} (no negative staircase) |")
    lines.append(f"| mean peak moment 4-24 Hz (N m) | {tr['mean_peak_moment_nm']:.2f} | n/a (Fig 8) | "
                 "seed: model underestimates high rates |")
    for k, row in trend["subjects"].items():
        sd = row["seed"] or {}
        note = (f"window {trend['window_s']:g} s" if row["reproduction"] else
                "NOT a reproduction: subject's theta unpublished, computed with subject 3's Table 2 theta")
        lines.append(f"| trend m, subject {k} (1/s) | {row['m_per_s']:.2f} | {_g(sd.get('m_per_s'))} "
                     f"({_g(sd.get('m_ci', [None])[0])}-{_g(sd.get('m_ci', [None, None])[1])}) | {note} |")
        lines.append(f"| trend c, subject {k} | {_g(row['c_raw_s4'])} s^4 (x = theta5 c = "
                     f"{row['x_theta5_c']:.2f}) | {_g(sd.get('c_mol_per_L'))} mol/L | conventions differ by a "
                     "constant |")
    lines.append(f"| trend m, 1 s window, Table 2 theta (1/s) | {trend['table2_theta_1s_window']['m_per_s']:.2f} | "
                 "7.94 | m depends on the window; seed's value is met with 3-10 s |")
    ft = trend["fitted_theta"]
    lines.append(f"| trend m from our fitted theta (1/s) | {ft['m_per_s']:.2f} | 7.94 | subject {ft['subject']} |")
    for k, v in rise["moment_q1_s"].items():
        lines.append(f"| moment rise time q = 1, subject {k} (ms) | {1e3 * v:.0f} | n/a | 10-90 % |")
    lines.append(f"| moment rise time q = 1, mean (ms) | {1e3 * rise['moment_q1_mean_s']:.0f} | "
                 f"{1e3 * rise['moment_q1_mean_seed_s']:.0f} | seed 3.3 'on average' |")
    lv = rise["active_state_levels_nu"]
    for k, v in rise["active_state_trend"].items():
        per = ", ".join(f"{1e3 * x:.0f}" for x in v["rise_time_s_by_nu"].values())
        lines.append(f"| active-state rise time, subject {k} (ms) | {1e3 * v['mean_s']:.0f} | n/a | mean of nu = "
                     f"{', '.join(map(str, lv))}: {per} ms; {v['source']} |")
    lines.append(f"| active-state rise time, mean (ms) | {1e3 * rise['active_state_trend_mean_s']:.0f} | "
                 f"{1e3 * rise['active_state_trend_mean_seed_s']:.0f} | seed's low/high levels unstated; ours "
                 f"nu = {', '.join(map(str, lv))} |")
    lines += ["", "Figures: " + ", ".join(f"`{f}`" for f in rep.get("files", []) if f.endswith(".png")), ""]
    return "\n".join(lines)
