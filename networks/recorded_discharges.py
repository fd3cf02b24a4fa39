"""Force from recorded discharges: decomposed HD-EMG discharge times of human tibialis anterior units (Caillet et
al. 2023, PLoS Comput Biol 19:e1011606; data ../shared/real_data/human_mu_spike_trains_caillet, used by path)
drive one CT09 muscle unit each; the unit forces are calibrated to the recorded force and the prediction is
compared with it on held-out time.

Calibration (neuromuscle.pool.force_calibration): the units are ranked by recruitment threshold (recorded force at
their first discharge); P0_i = scale * range_ratio ** rank_i (Fuglevand et al. 1993).  Fitted by least squares on
the calibration window (the first ``--calibration-fraction`` of the trial): scale (% MVC per unit of P0),
range_ratio (1..1000) and a constant delay (0..200 ms by 10 ms).  Fixed: CT09, isometric at -8 mm, the twitch speed
(``--speed``; ``--full`` picks the best of 0.75, 1.0, 1.5 on the calibration window).  Reported: NRMSE (eq 17, %
of the recorded range) on the held-out window (the rest of the trial), which the fit never sees.  The recorded
units are a sample of the pool: the fitted forces stand for the unrecorded units too.

Run: python networks/recorded_discharges.py --out DIR [--file S1_30_256.mat] [--full] [--overwrite]
Default: S1_30_36L (17 units, 33 s), speed 1.0, dt 0.05 ms.  --full: S1_30_256 (84 units), dt 0.025 ms.
Writes DIR/recorded_discharges.h5 (schema neuromuscle.pool_force_fit/1, provenance) and .png; prints the fit.
Units: ms, % MVC.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from neuromuscle import load_parameters
from neuromuscle.pool.discharges import load_caillet
from neuromuscle.pool.force_calibration import fit_unit_forces, save_fit, unit_force_basis
from neuromuscle.reports.figures import label_axes, legend, measured_vs_simulated, new_figure, residual_panel
from neuromuscle.reports.figures import save_figure, set_title
from neuromuscle.reports.outdir import prepare_out_dir

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"
FILES = ("recorded_discharges.h5", "recorded_discharges.png")
DELAYS_MS = tuple(np.arange(0.0, 201.0, 10.0))
LENGTH_MM = -8.0


def run(path: Path, speeds: tuple[float, ...], dt_ms: float, calibration_fraction: float) -> dict:
    """Load, build the unit-force basis for each speed, calibrate; returns everything the outputs need."""
    trial = load_caillet(path).trial(pad_ms=1000.0)
    muscle = load_parameters("CT09")
    rank = np.arange(len(trial.discharges_ms)) / max(len(trial.discharges_ms) - 1, 1)
    split = calibration_fraction * trial.duration_ms
    best = None
    for speed in speeds:
        t, g = unit_force_basis(trial.discharges_ms, trial.duration_ms, muscle, speed=speed, length_mm=LENGTH_MM,
                                dt_ms=dt_ms)
        y = trial.force_at(t)
        fit = fit_unit_forces(t, g, rank, y, calibration_ms=(0.0, split), heldout_ms=(split, t[-1] + 1.0),
                              delays_ms=DELAYS_MS)
        print(f"speed {speed:g}: NRMSE calibration {fit.nrmse_calibration_percent:.2f} %, "
              f"held-out {fit.nrmse_heldout_percent:.2f} %", file=sys.stderr)
        if best is None or fit.nrmse_calibration_percent < best["fit"].nrmse_calibration_percent:
            best = {"fit": fit, "speed": speed, "t": t, "y": y}
    assert best is not None
    return {**best, "trial": trial, "split": split}


def figure(out: Path, res: dict, name: str) -> None:
    """Raster (recruitment order), recorded vs predicted force with the windows, residual."""
    fit, t, y, trial = res["fit"], res["t"] / 1000.0, res["y"], res["trial"]
    fig, axes = new_figure(3, height_ratios=[1.6, 2.2, 1.0], sharex=True)
    for i, d in enumerate(trial.discharges_ms):
        axes[0].plot(d / 1000.0, np.full(d.size, i), "|", ms=1.5, color="k")
    label_axes(axes[0], x=None, y="unit (threshold order)")
    set_title(axes[0], f"{name}: {len(trial.discharges_ms)} decomposed units drive CT09 units "
                       f"(speed x{res['speed']:g}, delay {fit.delay_ms:g} ms)")
    measured_vs_simulated(axes[1], t, y, fit.predicted, measured_label="recorded", simulated_label="predicted")
    axes[1].axvspan(0.0, res["split"] / 1000.0, color="C0", alpha=0.08, label="calibration window")
    axes[1].text(0.99, 0.04, f"NRMSE held-out {fit.nrmse_heldout_percent:.1f} %, calibration "
                             f"{fit.nrmse_calibration_percent:.1f} %", transform=axes[1].transAxes, ha="right",
                 fontsize=8)
    legend(axes[1], small=True)
    label_axes(axes[1], x=None, y="force (% MVC)")
    residual_panel(axes[2], t, fit.predicted - y, x="time (s)", y="predicted - recorded (% MVC)")
    save_figure(fig, out)


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns the fit summary."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--file", help="a Caillet .mat file (default S1_30_36L, --full S1_30_256, in --data-dir)")
    ap.add_argument("--data-dir", default=str(DATA), help="folder of the Caillet files")
    ap.add_argument("--full", action="store_true", help="84 units, dt 0.025 ms, twitch speed chosen of 0.75, 1, 1.5")
    ap.add_argument("--speed", type=float, default=1.0, help="twitch speed factor (default run)")
    ap.add_argument("--calibration-fraction", type=float, default=0.5, help="share of the trial fitted on")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    out = prepare_out_dir(a.out, a.overwrite, FILES)
    path = Path(a.file) if a.file and Path(a.file).is_file() else Path(a.data_dir) / (
        a.file or ("S1_30_256.mat" if a.full else "S1_30_36L.mat"))
    speeds = (0.75, 1.0, 1.5) if a.full else (a.speed,)
    dt = 0.025 if a.full else 0.05
    t0 = time.time()
    res = run(path, speeds, dt, a.calibration_fraction)
    fit = res["fit"]
    summary = {"file": path.name, "units": len(res["trial"].discharges_ms), "speed": res["speed"], "dt_ms": dt,
               **{k: v for k, v in fit.summary().items() if k != "p0"}, "wall_s": round(time.time() - t0, 1)}
    save_fit(out / FILES[0], res["t"], res["y"], fit, res["trial"].discharges_ms, force_unit="% MVC",
             overwrite=a.overwrite, data_file=str(path), trial_start_ms=res["trial"].start_ms, dt_ms=dt,
             speeds_tried=list(speeds), speed=res["speed"], muscle_set="CT09", length_mm=LENGTH_MM,
             delays_ms=list(DELAYS_MS), calibration_fraction=a.calibration_fraction)
    figure(out / FILES[1], res, path.stem)
    print(json.dumps(summary, indent=1))
    return summary


if __name__ == "__main__":
    main()
