"""Diagnose the Herzog & Leonard (2002) cat soleus stretch recordings: what the model gets wrong on real data.

Run:  python networks/herzog_leonard_diagnosis.py --out hl2002_diagnosis [--workers 2] [--heldout-figure Figure7B]
          [--data hl2002.h5] [--png docs/figures/herzog_leonard_2002_diagnosis.png] [--overwrite]

Converts the recordings (networks/herzog_leonard_to_measured.py; or takes --data, an already converted file),
holds out one source figure (default Figure7B: the 9 mm/s stretches and their isometric references; the 3 and
27 mm/s figures calibrate), runs the diagnosis (``neuromuscle diagnose`` with that split) and writes its report
into --out plus one summary figure (--png): measured vs baseline vs the verdict's model for every held-out trial
and the held-out NRMSE before/after.  Prints the causes named, the held-out NRMSE before -> after, the test
statistics and the fitted extension parameters with their 95 % intervals.
Units: s, mm, N.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from neuromuscle.analysis.metrics import nrmse_percent
from neuromuscle.diagnose import Diagnosis, diagnose_data, write_report
from neuromuscle.diagnose.report import REPORT_FILES
from neuromuscle.errors import InputError
from neuromuscle.literature.herzog_leonard_measured import herzog_leonard_measured
from neuromuscle.measured import read_measured, write_measured
from neuromuscle.reports.figures import label_axes, legend, new_figure, save_figure, set_title
from neuromuscle.reports.outdir import check_out_dir, refuse_existing_file

REAL_DATA = Path(__file__).resolve().parents[1].parent / "shared" / "real_data"
FOLDER = "cat_soleus_herzog_leonard_2002"


def summary_figure(d: Diagnosis, png: Path) -> None:
    """Held-out trials: measured (grey), baseline (blue), the final model (red); last panel: NRMSE bars."""
    held = list(d.split.heldout)
    final = d.final.simulated
    baseline = {i: nrmse_percent(d.data.trials[i].force, d.baseline.simulated[i]) for i in held}
    label = " + ".join(d.causes) if d.causes else "baseline (no cause named)"
    fig, axes = new_figure(len(held) + 1, columns=False)
    for ax, i in zip(axes, held):
        t = d.data.trials[i]
        ax.plot(t.time_s, t.force, color="0.55", lw=1.0, label="measured (passive removed)")
        ax.plot(t.time_s, d.baseline.simulated[i], color="C0", lw=1.1, label="baseline")
        if d.causes:
            ax.plot(t.time_s, final[i], color="C3", lw=1.1, label=f"with {label}")
        label_axes(ax, x="time (s)", y="force (N)")
        set_title(ax, f"{i} ({t.protocol}, held out)",
                  f"NRMSE {baseline[i]:.1f} -> {nrmse_percent(t.force, final[i]):.1f} %")
    legend(axes[0], small=True)
    ax = axes[-1]
    x = np.arange(len(held))
    before = [baseline[i] for i in held]
    after = [nrmse_percent(d.data.trials[i].force, final[i]) for i in held]
    ax.bar(x - 0.2, before, 0.4, color="C0", label="baseline")
    ax.bar(x + 0.2, after, 0.4, color="C3", label=label)
    ax.set_xticks(x, [i.split("_")[-1] for i in held])
    label_axes(ax, x="held-out trial (source column)", y="NRMSE (%)")
    legend(ax, small=True)
    set_title(ax, "held-out error (eq 17)", f"mean {np.mean(before):.1f} -> {np.mean(after):.1f} %")
    save_figure(fig, png)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="report directory (diagnosis.json, report.md, figures/)")
    ap.add_argument("--data", default=None, help="converted file (default: convert into --out/hl2002.h5)")
    ap.add_argument("--real-data", default=str(REAL_DATA), help=f"the real-data folder holding {FOLDER}/")
    ap.add_argument("--heldout-figure", default="Figure7B", help="source figure whose trials are held out")
    ap.add_argument("--png", default=None, help="summary figure (default: --out/herzog_leonard_2002_diagnosis.png)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--overwrite", action="store_true", help="replace an existing report / figure")
    args = ap.parse_args(argv)
    out = Path(args.out)
    png = Path(args.png) if args.png else out / "herzog_leonard_2002_diagnosis.png"
    try:
        check_out_dir(out, args.overwrite, REPORT_FILES)
        refuse_existing_file(png, args.overwrite)
        if args.data is None:
            out.mkdir(parents=True, exist_ok=True)
            data_path = write_measured(out / "hl2002.h5", herzog_leonard_measured(Path(args.real_data) / FOLDER),
                                       overwrite=args.overwrite)
        else:
            data_path = Path(args.data)
        data = read_measured(data_path)
        heldout = [i for i, t in data.trials.items() if t.attrs.get("figure") == args.heldout_figure]
        if not heldout:
            raise InputError(f"--heldout-figure {args.heldout_figure}: no trial of {data_path} comes from it")
        d = diagnose_data(data, heldout=heldout, workers=args.workers, progress=True)
        doc = write_report(d, data_path, out, overwrite=args.overwrite)
        summary_figure(d, png)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"named: {', '.join(doc['named']) or 'none'}  (held out: {', '.join(d.split.heldout)})")
    for c in doc["causes"]:
        if not c.get("fitted"):
            continue
        tag = f"step {c['step']}, named" if c["named"] else f"step {c['step']}, not named"
        print(f"  {c['name']} ({tag}): held-out mean NRMSE {c['nrmse_heldout_before']:.2f} -> "
              f"{c['nrmse_heldout_after']:.2f} %")
        print(f"    {c['evidence']}")
        for q, p in c["parameters"].items():
            print(f"    {q} = {p['value']:.4g} {p['unit']}  95 % [{p['ci95'][0]:.4g}, {p['ci95'][1]:.4g}]")
    print(f"baseline: {', '.join(f'{k} {d.baseline.parameters[k]:.4g}' for k in d.baseline.free)}")
    print(f"wrote {out}/diagnosis.json, report.md, params.json, figures/ and {png}; {d.wall_time_s:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
