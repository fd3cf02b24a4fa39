"""A motoneuron pool that follows a recorded human force, its discharges compared with the decomposed ones.

For each file of ../shared/real_data/human_mu_spike_trains_caillet (decomposed HD-EMG discharges and force of
human tibialis anterior (TA) and gastrocnemius medialis (GM), trapezoidal isometric contractions at 30-50 % MVC;
Caillet et al. 2022, 2023; read by path, never copied):
1. the muscle's pool (``neuromuscle.pool.follow_force.HUMAN_MUSCLES``: unit types, published recruitment
   thresholds, upper limit of recruitment 90 % MVC) runs one slow ramp of its common synaptic drive; the P0 spread
   whose thresholds come closest to the published ones and the MVC drive follow (calibration, once per muscle);
   with ``--p0-spread recording`` the spread is fitted to each file instead: the one whose units a decomposition
   would identify (step 4) have recruitment thresholds closest to the recorded ones, every unit whose threshold
   lies below the recording's largest force counted as active (``follow_force.fit_p0_spread_to_recording``;
   depths from seeds other than those reported);
2. the drive that makes the pool's force (% of its MVC) follow the recorded force is the ramp's force-drive
   relation inverted (rising branch, then falling branch after the plateau), corrected ``--corrections`` times by
   the remaining error, each correction from the best pass so far (``follow_force.follow``, which keeps the best
   pass); the trial starts 0.5 s before the recorded force leaves its baseline, so that the pool starts at rest
   as the muscle did;
3. the pool's discharges are compared with the recorded ones (``neuromuscle.pool.recorded_comparison``): per-unit
   median and peak rates, recruitment thresholds (KS distance), onion skin, paired-unit Delta F;
4. the same for the model units a decomposition of the recording would identify
   (``neuromuscle.pool.identification``: of the muscle's units, as many as the recording has, those of highest
   weight in the recording, from their P0, depths drawn from ``--seed`` and, with ``--activity-exponent``, their
   time discharging), beside the whole pool.
The units are not matched one to one.

Run: python networks/pool_vs_recorded.py --out DIR [--file F.mat ...] [--units N] [--corrections K] [--full]
                                          [--seed S] [--depth-attenuation A] [--activity-exponent E]
                                          [--selection ranked|sampled]
                                          [--motoneurons default|human]
                                          [--neuromodulation NM] [--noise-uS S]
                                          [--set NAME=VALUE ...] [--scale NAME=FACTOR ...]
                                          [--p0-spread published|recording]
Default: S1_30_36L.mat, 40 units, one correction, seed 0, the module's depth attenuation.  --full: every file, 80
units.  The depth attenuation was estimated on S1_30_256 with
``python -m neuromuscle.pool.identification DIR/S1_30_256.json`` (40 units).  Writes, per file,
DIR/<file>.png (force, rate against threshold, threshold distributions, rasters), DIR/<file>_pool.h5 (the pool
run, provenance) and DIR/<file>.json; DIR/pool_vs_recorded.json (all files) and DIR/pool_vs_recorded.md (the
table); prints the JSON.  Units: ms, Hz, % MVC, uS.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from neuromuscle.errors import InputError
from neuromuscle.pool.discharges import RecordedDischarges, load_caillet
from neuromuscle.pool.follow_force import (FIT_SEEDS, HUMAN_MUSCLES, Calibration, P0Spread, calibrate,
                                          fit_p0_spread_to_recording, run_drive)
from neuromuscle.pool.follow_force import follow as follow_force
from neuromuscle.pool.identification import (ACTIVITY_EXPONENT, DEFAULT_SEED, DEPTH_ATTENUATION, SELECTIONS,
                                              IdentificationModel)
from neuromuscle.pool.motoneuron import PROFILES, motoneuron_parameters, motoneuron_profile, parse_settings
from neuromuscle.pool.recorded_comparison import Comparison, compare_discharges
from neuromuscle.reports.figures import label_axes, legend, new_figure, save_figure, set_title
from neuromuscle.reports.outdir import prepare_out_dir

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"
ALL_FILES = ("S1_30_256.mat", "S1_30_64L.mat", "S1_30_36L.mat", "S1_50_256.mat", "S1_50_64L.mat", "TA_35_D.mat",
             "TA_35_H.mat", "GM_30.mat")
SUMMARY_FILES = ("pool_vs_recorded.json", "pool_vs_recorded.md")


def muscle_of(path: Path) -> str:
    """GM for the gastrocnemius files (name starting GM), TA otherwise."""
    return "GM" if path.stem.upper().startswith("GM") else "TA"


def lead_in_ms(rec: RecordedDischarges, baseline_percent: float = 1.0) -> float:
    """How long before the first discharge the trial starts: from 500 ms before the force last rose from its
    baseline (``baseline_percent``, % MVC), at least 1 s, so that the pool starts at rest as the muscle did."""
    first = min(d[0] for d in rec.discharges_ms)
    return max(1000.0, first - rec.rest_times_ms(baseline_percent)[0] + 500.0)


def calibrate_muscle(muscle: str, units: int, options: dict[str, Any], scales: dict[str, float], *, dt_ms: float,
                     top_uS: float, ramp_ms: float) -> Calibration:
    """The calibration ramp (``follow_force.calibrate``) of ``muscle``'s pool (TA or GM) of ``units`` units, its
    motoneurons given ``options`` (overrides, neuromodulation, noise) and size-dependent ``scales`` on top of the
    muscle's own."""
    muscle_scales = dict(HUMAN_MUSCLES[muscle].motoneuron_scales)
    for k, f in scales.items():
        muscle_scales[k] = muscle_scales.get(k, 1.0) * f
    return calibrate(HUMAN_MUSCLES[muscle].definition(units, motoneuron_scales=muscle_scales, **options),
                     dt_ms=dt_ms, top_uS=top_uS, ramp_ms=ramp_ms)


def follow(path: Path, cal: Calibration, spread: P0Spread, corrections: int, dt_ms: float,
           identification: IdentificationModel, motor_units: int) -> dict[str, Any]:
    """Drive the calibrated pool so that its force follows the file's force; compare the discharges, the whole
    pool's and those of the units a decomposition would identify (the muscle has ``motor_units``)."""
    rec = load_caillet(path)
    trial = rec.trial(pad_ms=lead_in_ms(rec))
    t, force = trial.force_t_ms, trial.force_percent_mvc
    from neuromuscle.pool.discharge_stats import plateau_window_ms

    plateau = plateau_window_ms(t, force)
    definition = spread.definition(cal)

    def report(k: int, nrmse: float) -> None:
        print(f"{path.name}: pass {k}, force NRMSE {nrmse:.2f} % of the recorded range", file=sys.stderr)

    best = follow_force(cal, spread, t, force, lambda times, drive: run_drive(definition, times, drive,
                        trial.duration_ms, dt_ms=dt_ms), corrections=corrections, descent_ms=plateau[1], report=report)
    times, drive, result, model, errors = (best.times_ms, best.drive_uS, best.result, best.force_percent,
                                           list(best.nrmse_passes))
    cmp = compare_discharges(trial, result.spikes_ms, result.t_ms, model, p0_N=spread.p0_N(cal.rank),
                             motor_units=motor_units, identification=identification)
    return {"trial": trial, "result": result, "model_force": model, "times": times, "drive": drive,
            "comparison": cmp, "nrmse_percent": errors, "nrmse_best": best.nrmse_percent}


def unit_table(cmp: Comparison, p0_N: np.ndarray) -> dict[str, list]:
    """Every model unit's P0 (N), whether it is active (in the comparison), its threshold (% MVC) and median rate
    (Hz) (None when inactive), its time discharging (s, first to last discharge) and its identified copies."""
    n = len(p0_N)
    thr: list[float | None] = [None] * n
    med: list[float | None] = [None] * n
    for k, u in enumerate(cmp.model_units):
        thr[u] = float(cmp.model.thresholds_percent[k])
        med[u] = float(cmp.model.rates.median_hz[k])
    found = [0] * n if cmp.identified is None else [int(x) for x in cmp.identified.identification.identified_copies]
    active = [False] * n
    for u in cmp.model_units:
        active[u] = True
    discharging = [0.0] * n if cmp.identified is None else [float(x) for x in cmp.identified.active_s]
    return {"p0_N": [float(x) for x in p0_N], "active": active, "threshold_percent_mvc": thr, "median_hz": med,
            "discharging_s": discharging, "identified_copies": found}


def figure(out: Path, name: str, run: dict[str, Any]) -> None:
    """Force and drive; median rate against threshold; threshold distributions; rasters."""
    trial, result, cmp = run["trial"], run["result"], run["comparison"]
    c: Comparison = cmp
    fig, axes = new_figure(4, height_ratios=[1.2, 1.2, 1.0, 1.6])
    ax = axes[0]
    ax.plot(trial.force_t_ms / 1000.0, trial.force_percent_mvc, color="k", lw=1.0, label="recorded force")
    ax.plot(result.t_ms / 1000.0, run["model_force"], color="C3", lw=0.8, label="pool force")
    ax2 = ax.twinx()
    ax2.plot(run["times"] / 1000.0, run["drive"], color="C0", lw=0.6)
    ax2.set_ylabel("drive (uS)", color="C0", fontsize=8)
    label_axes(ax, x="time (s)", y="force (% MVC)")
    legend(ax, small=True)
    set_title(ax, f"{name}: the pool follows the recorded force (NRMSE {run['nrmse_best']:.1f} %)")
    ax = axes[1]
    lo, hi = c.medians_range_hz
    ax.axhspan(lo, hi, color="0.85", label="recorded 5th-95th pct of medians")
    ax.plot(c.recorded.thresholds_percent, c.recorded.rates.median_hz, "o", ms=3, color="k", label="recorded units")
    ax.plot(c.model.thresholds_percent, c.model.rates.median_hz, "x", ms=4, color="C3", label="model units")
    if c.identified is not None:
        ax.plot(c.identified.stats.thresholds_percent, c.identified.stats.rates.median_hz, "s", ms=6, mfc="none",
                color="C0", label="model units identified")
    label_axes(ax, x="recruitment threshold (% MVC)", y="median rate (Hz)")
    legend(ax, small=True)
    ax = axes[2]
    crit = c.criteria()
    sets = [(c.recorded.thresholds_percent, None, "k", "recorded"), (c.model.thresholds_percent, None, "C3", "model")]
    text = f"KS {crit['thresholds_ks']['value']:.2f}"
    if c.identified is not None:
        sets.append((c.identified.stats.thresholds_percent, c.identified.identification.weights, "C0",
                     "model, identified"))
        text += f" (identified {c.identified_criteria()['thresholds_ks']['value']:.2f})"
    for v, w, col, lab in sets:
        w = np.ones(v.size) if w is None else np.asarray(w, float)
        keep = np.isfinite(v)
        order = np.argsort(v[keep])
        v, w = v[keep][order], w[keep][order]
        ax.step(v, np.cumsum(w) / w.sum(), where="post", color=col, label=lab)
    set_title(ax, f"recruitment thresholds: {text}")
    label_axes(ax, x="recruitment threshold (% MVC)", y="fraction of units (1)")
    legend(ax, small=True)
    ax = axes[3]
    rec = trial.discharges_ms
    for i, d in enumerate(rec):
        ax.plot(d / 1000.0, np.full(d.size, i), "|", ms=1.2, color="k")
    found = set() if c.identified is None else {int(u) for u in c.identified.identification.units}
    for j, u in enumerate(c.model_units):
        s = result.spikes_ms[u]
        ax.plot(s / 1000.0, np.full(s.size, len(rec) + 2 + j), "|", ms=1.2, color="C0" if u in found else "C3")
    label_axes(ax, x="time (s)", y="unit, rec. then model (index)")
    set_title(ax, "rasters: recorded (black), model (red), model identified (blue)")
    save_figure(fig, out)


def table(rows: list[dict[str, Any]]) -> list[str]:
    """The markdown table of the criteria, one row a file; the whole pool's active units ("pool") and those a
    decomposition would identify ("ident.") side by side."""
    lines = ["| file | units rec / pool / ident. | force NRMSE % | median of medians Hz rec / pool / ident. | "
             "medians inside rec 5-95 % pool / ident. | peak Hz rec max / pool max (ratio) | thresholds KS pool / "
             "ident. (ident. over 20 seeds: median, 5-95 %; all 20 seeds' units together [by chance: median, "
             "95 %]) | onion skin rho rec / pool / ident. | Delta F Hz rec / pool | plateau rate decline Hz rec / "
             "pool | plateau ISI CV median rec / pool |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s, c = r["summary"], r["summary"]["criteria"]
        rec, mod = s["recorded"], s["model"]
        idn = s.get("identified", {"units": 0, "median_of_medians_hz": float("nan"), "onion_skin_rho": float("nan")})
        ci = idn.get("criteria", {"medians_inside": {"value": "-"}, "thresholds_ks": {"value": float("nan")}})
        lo, hi = c["medians_inside"]["range_hz"]
        n_id = idn["identification"]["count"] if "identification" in idn else 0
        lines.append(
            f"| {r['file']} | {rec['units']} / {mod['units']} / {idn['units']} ({n_id}) | {r['nrmse_percent']:.1f} | "
            f"{rec['median_of_medians_hz']:.1f} / {mod['median_of_medians_hz']:.1f} / "
            f"{idn['median_of_medians_hz']:.1f} | "
            f"{c['medians_inside']['value']} / {ci['medians_inside']['value']} ({lo:.1f}-{hi:.1f}) | "
            f"{rec['peak_max_hz']:.1f} / {mod['peak_max_hz']:.1f} ({c['peak_ratio']['value']:.2f}) | "
            f"{c['thresholds_ks']['value']:.2f} / {ci['thresholds_ks']['value']:.2f}{_over_seeds(idn)} | "
            f"{rec['onion_skin_rho']:.2f} / {mod['onion_skin_rho']:.2f} / {idn['onion_skin_rho']:.2f} | "
            f"{c['delta_f_hz']['recorded']:.1f} / {c['delta_f_hz']['value']:.1f} | "
            f"{rec['plateau_rate_decline_hz']:.1f} / {mod['plateau_rate_decline_hz']:.1f} | "
            f"{_cv(rec)} / {_cv(mod)} |")
    return lines


def _cv(side: dict[str, Any]) -> str:
    """The median plateau ISI CV of one side's summary, or "-"."""
    cv = side.get("isi_cv_p5_p50_p95")
    return "-" if cv is None else f"{cv[1]:.2f}"


def _over_seeds(identified: dict[str, Any]) -> str:
    """" (median, 5th-95th percentile; all seeds [by chance: median, 95th percentile])" of the identified units'
    KS distance over seeds, or ""."""
    if "over_seeds" not in identified:
        return ""
    over = identified["over_seeds"]
    m, lo, hi = over["thresholds_ks_median_p5_p95"]
    text = f" ({m:.2f}, {lo:.2f}-{hi:.2f}"
    if "thresholds_ks_expected" in over:
        e = over["thresholds_ks_expected"]
        c50, c95 = e["by_chance_p50_p95"]
        text += f"; {e['value']:.2f} [{c50:.2f}, {c95:.2f}]"
    return text + ")"


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Command line (module docstring); returns the summary of every file."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--file", action="append", help="a Caillet .mat file (repeatable; default S1_30_36L.mat)")
    ap.add_argument("--data-dir", default=str(DATA), help="folder of the Caillet files")
    ap.add_argument("--units", type=int, default=None, help="model units (default 40, --full 80)")
    ap.add_argument("--corrections", type=int, default=1, help="drive corrections after the inverted one")
    ap.add_argument("--dt-ms", type=float, default=0.025, help="fixed step (ms)")
    ap.add_argument("--full", action="store_true", help="every file, 80 units")
    ap.add_argument("--seed", type=int, default=DEFAULT_SEED, help="seed of the identification's unit depths")
    ap.add_argument("--activity-exponent", type=float, default=ACTIVITY_EXPONENT,
                    help="exponent of a unit's time discharging in its weight in the recording (identification; "
                         "default 0: size and depth alone)")
    ap.add_argument("--selection", choices=SELECTIONS, default="ranked",
                    help="how the identification chooses among the active units: those of highest weight (ranked) "
                         "or drawn in proportion to their weights (sampled)")
    ap.add_argument("--depth-attenuation", type=float, default=DEPTH_ATTENUATION,
                    help="ln of a unit's surface-energy ratio, muscle surface / deep face (identification)")
    ap.add_argument("--motoneurons", choices=tuple(PROFILES), default="default",
                    help="the reduced cells' profile (neuromuscle.pool.motoneuron.PROFILES); --neuromodulation, --set "
                         "and --scale act on top of it")
    ap.add_argument("--neuromodulation", type=float, default=None,
                    help="the motoneurons' PIC strength (default: the profile's)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a motoneuron parameter replaced in every cell, e.g. g_ks_S_per_cm2=0.03 (repeatable)")
    ap.add_argument("--scale", action="append", default=[], metavar="NAME=FACTOR",
                    help="a size-dependent motoneuron parameter multiplied in every cell, on top of the muscle's own "
                         "and the profile's scales, e.g. ca_decay_ms=1.5 (AHPs half as long again; repeatable)")
    ap.add_argument("--noise-uS", type=float, default=None,
                    help="each motoneuron's own synaptic noise (uS, its standard deviation at a drive of 1 uS; "
                         "default: the profile's)")
    ap.add_argument("--calibration-top-uS", type=float, default=1.2,
                    help="the calibration triangle's peak drive (uS): raise it for motoneurons that need more drive "
                         "to recruit the whole pool")
    ap.add_argument("--calibration-ramp-ms", type=float, default=10000.0,
                    help="the calibration triangle's rise (and fall) time (ms): a longer ramp rises at the pace of "
                         "the recorded contractions, so the units' force at a given drive is that of the trial")
    ap.add_argument("--p0-spread", choices=("published", "recording"), default="published",
                    help="fit the muscle units' P0 spread to the muscle's published thresholds (once per muscle) or "
                         "to each recording's thresholds as a decomposition would sample them")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    profile = motoneuron_profile(a.motoneurons)
    try:
        overrides = {**dict(profile.overrides), **parse_settings(a.set)}
    except InputError as e:
        ap.error(f"--set: {e}")
    try:
        scales = dict(profile.scales)
        for k, f in parse_settings(a.scale).items():
            scales[k] = scales.get(k, 1.0) * f
        motoneuron_parameters(0.0, scales=scales)
    except InputError as e:
        ap.error(f"--scale: {e}")
    if a.noise_uS is not None and not (np.isfinite(a.noise_uS) and a.noise_uS >= 0.0):
        ap.error(f"--noise-uS must be a number >= 0, got {a.noise_uS}")
    for flag, value in (("--calibration-top-uS", a.calibration_top_uS),
                        ("--calibration-ramp-ms", a.calibration_ramp_ms)):
        if not np.isfinite(value) or value <= 0.0:
            ap.error(f"{flag} must be a number > 0, got {value}")
    options: dict[str, Any] = {"motoneuron_overrides": overrides,
                               "neuromodulation": profile.neuromodulation if a.neuromodulation is None
                               else a.neuromodulation,
                               "synaptic_noise_uS": profile.synaptic_noise_uS if a.noise_uS is None else a.noise_uS}
    names = list(ALL_FILES) if a.full and not a.file else (a.file or ["S1_30_36L.mat"])
    paths = [Path(f) if Path(f).is_file() else Path(a.data_dir) / f for f in names]
    stems = [p.stem for p in paths]
    out = prepare_out_dir(a.out, a.overwrite, [*SUMMARY_FILES, *(f"{s}{x}" for s in stems
                                                                   for x in (".png", ".json", "_pool.h5"))])
    n = a.units or (80 if a.full else 40)
    ident_model = IdentificationModel(depth_attenuation=a.depth_attenuation, seed=a.seed,
                                      activity_exponent=a.activity_exponent, selection=a.selection)
    t0 = time.time()
    calibrations: dict[str, tuple[Calibration, P0Spread]] = {}
    rows = []
    for path in paths:
        m = muscle_of(path)
        if m not in calibrations:
            cal = calibrate_muscle(m, n, options, scales, dt_ms=a.dt_ms, top_uS=a.calibration_top_uS,
                                   ramp_ms=a.calibration_ramp_ms)
            calibrations[m] = (cal, cal.fit_p0_spread(HUMAN_MUSCLES[m]))
            sp = calibrations[m][1]
            print(f"{m}: P0 range {sp.range_ratio:.3g}, exponent {sp.exponent:.3g}, MVC drive "
                  f"{sp.mvc_drive_uS:.3g} uS, thresholds {sp.rms_error_percent:.2f} % MVC rms from the published",
                  file=sys.stderr)
        cal, spread = calibrations[m]
        fitted_to, distance, peak = "published thresholds", float("nan"), None
        if a.p0_spread == "recording":
            rec = load_caillet(path)
            peak = float(np.nanmax(rec.force_percent_mvc))
            spread, distance = fit_p0_spread_to_recording(cal, HUMAN_MUSCLES[m], rec.thresholds_percent_mvc(), peak,
                                                          model=ident_model,
                                                          recorded_force_percent=rec.force_percent_mvc,
                                                          force_sample_s=1.0 / rec.fsamp_hz)
            fitted_to = "recorded thresholds"
            print(f"{path.name}: P0 range {spread.range_ratio:.3g}, exponent {spread.exponent:.3g}, MVC drive "
                  f"{spread.mvc_drive_uS:.3g} uS, identified thresholds KS {distance:.2f} from the recorded "
                  f"(mean over seeds {FIT_SEEDS.start}-{FIT_SEEDS.stop - 1}), {spread.rms_error_percent:.1f} % MVC "
                  "rms from the published", file=sys.stderr)
        run = follow(path, cal, spread, a.corrections, a.dt_ms, ident_model, HUMAN_MUSCLES[m].motor_units)
        cmp: Comparison = run["comparison"]
        summary = cmp.summary()
        row = {"file": path.name, "muscle": m, "nrmse_percent": run["nrmse_best"],
               "nrmse_percent_passes": run["nrmse_percent"], "summary": summary,
               "pool": {"units": n, "p0_range": spread.range_ratio, "p0_exponent": spread.exponent,
                        "p0_spread_fitted_to": fitted_to, "identified_thresholds_ks_fit": distance,
                        "fit_active_below_percent_mvc": peak,
                        "fit_seeds": [FIT_SEEDS.start, FIT_SEEDS.stop - 1] if a.p0_spread == "recording" else None,
                        "mvc_drive_uS": spread.mvc_drive_uS, "thresholds_rms_percent": spread.rms_error_percent,
                        "neuromodulation": cal.definition.neuromodulation,
                        "motoneuron_overrides": dict(cal.definition.motoneuron_overrides),
                        "motoneurons": a.motoneurons, "motoneuron_scales": dict(cal.definition.motoneuron_scales),
                        "synaptic_noise_uS": cal.definition.synaptic_noise_uS,
                        "noise_seed": cal.definition.noise_seed,
                        "calibration_top_uS": a.calibration_top_uS,
                        "calibration_ramp_ms": a.calibration_ramp_ms},
               "identification": {**ident_model.provenance(), "motor_units": HUMAN_MUSCLES[m].motor_units},
               "units": unit_table(cmp, spread.p0_N(cal.rank)),
               "recorded_thresholds_percent_mvc": [float(x) for x in cmp.recorded.thresholds_percent]}
        run["result"].save(out / f"{path.stem}_pool.h5", overwrite=a.overwrite)
        figure(out / f"{path.stem}.png", path.stem, run)
        (out / f"{path.stem}.json").write_text(json.dumps(row, indent=1, default=float))
        rows.append(row)
    report = {"files": rows, "wall_s": round(time.time() - t0, 1)}
    (out / SUMMARY_FILES[0]).write_text(json.dumps(report, indent=1, default=float))
    (out / SUMMARY_FILES[1]).write_text("\n".join(table(rows)) + "\n")
    print(json.dumps(report, indent=1, default=float))
    return report


if __name__ == "__main__":
    main()
