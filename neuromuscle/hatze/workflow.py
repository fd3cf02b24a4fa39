"""The "from twitch to tetanus" workflow of van Zandwijk et al. 1998 in one reproducible call:
``run_twitch_to_tetanus``.

Steps (all SI: s, rad, N m); (b)-(e) are computed in ``sections``:

(a) The twitch to fit (``data.load_twitch``): a CSV file (columns ``time_s``, ``moment_nm``; extra columns ignored;
    one stimulus at ``stim_time_s``), or - without a file - a *synthetic* isometric twitch of the chosen subject made
    with Table 2's theta, sampled at 1 kHz for 0.8 s, plus Gaussian noise of ``noise_nm`` (N m) from
    ``numpy.random.default_rng(seed)``.
(b) Fit of theta by Levenberg-Marquardt with the sensitivity-equation Jacobian (``fitting.fit_twitch``). theta1 is
    frozen at Table 2 by default: the twitch carries no information on it (fitting.py docstring); theta2..theta5
    start from Table 2 times ``start_factors`` (default 2, 0.5, 0.5, 2) so that the fit has to find them. Reported:
    estimates, 95 % intervals, identifiability flags, VIFs, and the singular values of dM/d ln theta (all five) at
    the estimate.
(c) Isometric predictions for 1 s trains at 4, 8, 12, 16, 24 Hz (peak moment, and moment at the end of the train
    over the peak, the model's answer to the measured negative staircase), with our theta and with Table 2's.
(d) Trend function (eq 10) fitted to gamma(t) of eqs 6-7 at 100 Hz over a train of ``trend_window_s`` (default 5 s;
    m depends on the window, see ``excitation.fit_trend_to_full_model``), for each subject with Table 3 beside.
    gamma does not involve the contraction parameters, and the paper publishes theta only for subject 3, so the
    rows of subjects 1, 2, 4 are computed with subject 3's theta and are *not* reproductions. c is reported on the
    raw scale of gamma in eqs 6-7 (s^4) and as x = theta5 c (dimensionless, the argument of eq 9 at xi = 1).
(e) Rise times (10-90 % of the maximum): of the moment under q = 1 for each subject (``moment_rise_time_s``), and of
    the trend model's active state, averaged over a low (nu = 0.2, 20 Hz) and a high (nu = 1, 100 Hz) level - the
    seed does not state its levels. For subject 3 the trend model is our fit; for the others, whose theta is
    unpublished, Table 3's m with x(nu = 1) = K c_Table3, K = x_3 / c_3,Table3 taken from subject 3 (assumes one
    conversion from mol/L to the dimensionless x for all subjects).
(f) Figures (``report.write_figures``): ``twitch_fit.png``, ``trains.png``, ``trend_fit.png``, ``rise_times.png``.
(g) ``report.json`` (all numbers, the paper's beside ours, provenance) and ``report.md`` (table
    "quantity | ours | seed | note", ``report.render_markdown``).

The inputs of (a)-(e) are one :class:`TwitchToTetanusOptions`. Bad inputs raise ``InputError`` naming the culprit;
an existing report in ``out_dir`` is never replaced unless ``overwrite=True`` (``--overwrite``).
"""

from __future__ import annotations

import datetime as _dt
import json
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Sequence

import matplotlib
import numpy as np

from ..errors import InputError
from ..sim.provenance import versions
from ..reports.outdir import check_out_dir, prepare_out_dir, write_text
from .contraction import DEFAULT_STEP_S
from .data import load_twitch
from ..model.hatze_parameters import Subject, check_positive, load_subject, load_subjects, load_theta
from .report import json_ready, render_markdown, write_figures
from .sections import fit_section, rise_time_section, train_section, trend_section

#: Files written into ``out_dir`` besides the figures; their presence means a report is there.
REPORT_FILES: tuple[str, ...] = ("report.json", "report.md")
#: The paper whose tables and workflow this follows (its equations and decoded tables: docs/reference/hatze.md).
PAPER: str = "van Zandwijk, Bobbert, Harlaar & Hof 1998, Biol Cybern 79:121-130 (Tables 1-4, section 3)"


@dataclass(frozen=True)
class TwitchToTetanusOptions:
    """Inputs of steps (a)-(e); checked on construction (InputError naming the field).

    ``subject``: Table 1 subject ("1".."4") whose contraction dynamics the twitch is fitted with (Table 2 is
    subject 3's); ``twitch_csv``: measured twitch (``time_s`` s, ``moment_nm`` N m, times multiples of ``step_s``)
    with its stimulus at ``stim_time_s`` (s), or None for the synthetic twitch with noise ``noise_nm`` (N m) drawn
    with ``seed``; ``trend_window_s``: 100 Hz train length (s) the trend function is fitted over, on a grid of
    ``trend_dt_s`` (s); ``frozen``, ``start_factors`` (on Table 2), ``max_evaluations``: the twitch fit;
    ``step_s``: contraction integration step (s); trains of ``train_duration_s`` simulated to ``train_t_end_s`` (s).
    """
    subject: str | int = "3"
    twitch_csv: str | Path | None = None
    noise_nm: float = 0.05
    seed: int = 0
    trend_window_s: float = 5.0
    stim_time_s: float = 0.02
    frozen: Sequence[str] = ("theta1",)
    start_factors: Sequence[float] = (1.0, 2.0, 0.5, 0.5, 2.0)
    max_evaluations: int = 200
    step_s: float = DEFAULT_STEP_S
    trend_dt_s: float = 1e-3
    train_duration_s: float = 1.0
    train_t_end_s: float = 1.5

    def __post_init__(self) -> None:
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise InputError(f"seed must be a non-negative integer, got {self.seed!r}")
        factors = np.asarray(self.start_factors, dtype=float)
        if factors.shape != (5,) or not np.all(np.isfinite(factors)) or np.any(factors <= 0):
            raise InputError(f"start_factors must be five finite numbers > 0, got {self.start_factors!r}")
        checked = {"noise_nm": check_positive("noise_nm", self.noise_nm, allow_zero=True),
                   "trend_window_s": check_positive("trend_window_s", self.trend_window_s),
                   "stim_time_s": check_positive("stim_time_s", self.stim_time_s, allow_zero=True),
                   "seed": int(self.seed), "frozen": tuple(self.frozen), "start_factors": tuple(factors.tolist())}
        for name, value in checked.items():
            object.__setattr__(self, name, value)


def run_twitch_to_tetanus(out_dir: str | Path, options: TwitchToTetanusOptions | None = None, *,
                          overwrite: bool = False, figures: bool = True, **option_values: Any) -> dict[str, Any]:
    """Run steps (a)-(g) of the module docstring; write report.json, report.md and figures into ``out_dir``.

    ``options`` (default :class:`TwitchToTetanusOptions`), with any of its fields replaced by ``option_values``
    (``run_twitch_to_tetanus(out, subject="2", seed=4)``). Returns the report (the content of report.json).
    """
    opts = replace(options or TwitchToTetanusOptions(), **option_values)
    check_out_dir(out_dir, overwrite, REPORT_FILES)
    subj = load_subject(opts.subject)                      # InputError for unknown subjects
    table2 = load_theta()
    twitch = load_twitch(opts.twitch_csv, subj, table2, opts.noise_nm, opts.seed, opts.stim_time_s, opts.step_s)
    fit, fit_sec, model = fit_section(twitch, subj, table2, opts.start_factors, frozen=opts.frozen,
                                      max_evaluations=opts.max_evaluations, step_s=opts.step_s)
    preds, trains = train_section(fit.theta, subj, table2, duration_s=opts.train_duration_s,
                                  t_end_s=opts.train_t_end_s, step_s=opts.step_s)
    trend_t2, trend = trend_section(fit.theta, table2, subj, window_s=opts.trend_window_s, dt_s=opts.trend_dt_s)
    subjects = load_subjects()
    rise = rise_time_section(subjects, trend_t2, table2, m_fit=trend["fitted_theta"]["m_per_s"],
                             x_fit=trend["fitted_theta"]["x_theta5_c"], step_s=opts.step_s)
    report = json_ready({
        "workflow": "'from twitch to tetanus' of van Zandwijk et al. 1998 "
                    "(neuromuscle.hatze.workflow.run_twitch_to_tetanus)",
        "twitch": twitch.info, "fit": fit_sec, "trains": trains, "trend": trend, "rise_times": rise,
        "provenance": _provenance(opts, subj)})
    out = prepare_out_dir(out_dir, overwrite, REPORT_FILES)
    written = write_figures(out, twitch, model, preds, table2, trend_t2, rise, subjects, window_s=opts.trend_window_s,
                            dt_s=opts.trend_dt_s, step_s=opts.step_s) if figures else []
    report["files"] = [*REPORT_FILES, *written]
    write_text(out / "report.json", json.dumps(report, indent=2))
    write_text(out / "report.md", render_markdown(report))
    return report


def _provenance(opts: TwitchToTetanusOptions, subj: Subject) -> dict[str, Any]:
    return {"versions": {**versions(), "matplotlib": matplotlib.__version__},
            "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "inputs": {"subject": subj.name, "twitch_csv": None if opts.twitch_csv is None else str(opts.twitch_csv),
                       "noise_nm": opts.noise_nm, "seed": opts.seed, "stim_time_s": opts.stim_time_s,
                       "trend_window_s": opts.trend_window_s, "trend_dt_s": opts.trend_dt_s, "step_s": opts.step_s,
                       "frozen": list(opts.frozen), "start_factors": opts.start_factors,
                       "max_evaluations": opts.max_evaluations, "train_duration_s": opts.train_duration_s,
                       "train_t_end_s": opts.train_t_end_s},
            "paper": PAPER}
