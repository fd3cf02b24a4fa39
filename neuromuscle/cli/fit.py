"""``neuromuscle fit DATA.h5 --out DIR``: fit a measured-data file; params.json, fit.json, summary.md, figures."""

from __future__ import annotations

import argparse

from ..errors import InputError


def add_parser(sub: argparse._SubParsersAction) -> None:
    fp = sub.add_parser("fit", help="fit a measured-data file; write params.json, fit.json, summary.md, figures")
    fp.add_argument("data", help="measured-data HDF5 file (neuromuscle.measured/1)")
    fp.add_argument("--out", required=True, help="output directory")
    fp.add_argument("--params", default="CT09", help="start set: built-in (CT09, CT95) or parameter file")
    fp.add_argument("--free", default=None,
                    help="comma-separated free parameters (default C1,C2,C3,alpha; with --staged: of the Module 2 "
                         "stage)")
    fp.add_argument("--trials", default=None,
                    help="comma-separated trial ids (default: stimulated N/mm trials; not with --staged)")
    fp.add_argument("--workers", type=int, default=1, help="parallel simulation processes (>= 1)")
    fp.add_argument("--staged", action="store_true",
                    help="seed staged calibration: Module 3 -> Module 2 (--free) -> length compensation")
    fp.add_argument("--dt-ms", type=float, default=0.05, help="fixed step (ms)")
    fp.add_argument("--record-dt-ms", type=float, default=0.5, help="recording interval (ms)")
    fp.add_argument("--settle-ms", type=float, default=300.0, help="settling before each trial (ms)")
    fp.add_argument("--max-iterations", type=int, default=30, help="optimiser iterations")
    fp.add_argument("--intervals", default="hac+integrator",
                    help="how the 95 %% intervals are made: hac+integrator (default: HAC covariance plus the "
                         "integrator's error), hac, or iid (the textbook s^2 (J^T J)^-1); not with --staged")
    fp.add_argument("--quiet", action="store_true", help="no per-iteration progress")
    fp.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    fp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..calibration.report import run_fit

    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    free = [n.strip() for n in args.free.split(",") if n.strip()] if args.free else None
    trials = [n.strip() for n in args.trials.split(",") if n.strip()] if args.trials else None
    doc = run_fit(args.data, args.out, params=args.params, free=free, trials=trials, workers=args.workers,
                  staged=args.staged, dt_ms=args.dt_ms, record_dt_ms=args.record_dt_ms, settle_ms=args.settle_ms,
                  max_iterations=args.max_iterations, intervals=args.intervals, progress=not args.quiet,
                  overwrite=args.overwrite)
    for n, v in doc.get("fit", {}).get("estimates", {}).items():
        lo, hi = doc["fit"]["ci95"][n]
        print(f"{n:7s} = {v:.6g}  95% [{lo:.6g}, {hi:.6g}]")
    for tid, v in doc["nrmse_percent"].items():
        print(f"NRMSE {tid}: {v:.3f} %")
    print(f"wrote {args.out}/params.json, fit.json, summary.md and figures/")
    return 0
