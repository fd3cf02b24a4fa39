"""Command line: ``neuromuscle simulate``, ``neuromuscle bench unit``, ``neuromuscle data check``,
``neuromuscle twitch-to-tetanus``, ``neuromuscle fit``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from . import protocols
from .errors import NeuromuscleError
from .length import LengthTrace


def _stimulus(args: argparse.Namespace) -> tuple[np.ndarray, dict]:
    start, dur = args.start_ms, args.train_ms
    if args.protocol == "twitch":
        return protocols.twitch(start), {"protocol": "twitch", "start_ms": start}
    if args.protocol == "train":
        return (protocols.constant_rate(args.rate_hz, dur, start_ms=start),
                {"protocol": "train", "rate_hz": args.rate_hz, "start_ms": start, "train_ms": dur})
    if args.protocol == "random-train":
        return (protocols.random_interval(1000.0 / args.rate_hz, dur, seed=args.seed, start_ms=start),
                {"protocol": "random-train", "mean_rate_hz": args.rate_hz, "seed": args.seed,
                 "start_ms": start, "train_ms": dur})
    spikes = np.loadtxt(args.protocol, ndmin=1) if Path(args.protocol).is_file() else None
    if spikes is None:
        raise NeuromuscleError(f"--protocol {args.protocol!r}: neither twitch, train, random-train nor a file "
                               "of spike times (ms, one per line)")
    return spikes, {"protocol": "file", "path": args.protocol}


def _length(args: argparse.Namespace) -> tuple[LengthTrace | float, dict]:
    kind, dur = args.length, args.duration_ms
    if kind == "random":
        return protocols.random_length(dur, seed=args.seed), {"length": "random", "seed": args.seed}
    if kind == "step":
        return (protocols.step_shortening(args.xm_mm, args.step_mm, args.start_ms + 300.0, dur),
                {"length": "step", "xm_mm": args.xm_mm, "step_mm": args.step_mm})
    if kind == "ramp":
        return (protocols.isokinetic_ramp(args.xm_mm, args.xm_mm + args.ramp_mm, args.velocity_mm_s,
                                          args.start_ms + 300.0, dur),
                {"length": "ramp", "xm_mm": args.xm_mm, "ramp_mm": args.ramp_mm,
                 "velocity_mm_s": args.velocity_mm_s})
    return args.xm_mm, {"length": "isometric", "xm_mm": args.xm_mm}


def _plot(result, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 6))
    axes[0].plot(result.t_ms, result.force_N, "k")
    axes[0].set_ylabel("force (N)")
    axes[1].plot(result.t_ms, result.A, "C0")
    axes[1].set_ylabel("activation A")
    axes[2].plot(result.t_ms, result.length_mm, "C1")
    axes[2].set_ylabel("length Xm (mm)")
    axes[2].set_xlabel("time (ms)")
    axes[0].set_title(f"{result.params.name}: {result.provenance.get('protocol', {})}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def cmd_simulate(args: argparse.Namespace) -> int:
    from .parameters import load_parameters
    from .unit import simulate

    params = load_parameters(args.params)
    spikes, proto = _stimulus(args)
    length, lproto = _length(args)
    result = simulate(params, spikes, length, args.duration_ms, dt_ms=args.dt_ms, method=args.method,
                      record_dt_ms=args.record_dt_ms, length_compensation=not args.no_length_compensation,
                      movement_compensation=args.movement_compensation, excitation=args.excitation,
                      provenance_extra={"protocol": proto, "length_protocol": lproto,
                                        "command": " ".join(sys.argv)})
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    result.save(str(out), overwrite=args.overwrite)
    png = Path(args.png) if args.png else out.with_suffix(".png")
    _plot(result, png)
    peak = float(result.force_N.max())
    print(f"{params.name}: {proto['protocol']} at {lproto['length']}, {result.t_ms[-1]:.0f} ms, "
          f"{result.settings['n_spikes']} spikes: peak force {peak:.3f} N ({peak / params['P0']:.3f} P0)")
    for w in result.warnings:
        print(f"warning: {w}")
    print(f"wrote {out} and {png}")
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    from .bench import bench_fit, bench_unit
    from .parameters import load_parameters

    if args.what == "fit":
        res = bench_fit(load_parameters(args.params))
    else:
        res = bench_unit(load_parameters(args.params), duration_ms=args.duration_ms, repeats=args.repeats,
                         pool_units=args.pool_units)
    if args.json:
        print(json.dumps(res, indent=2))
    else:
        for k, v in res.items():
            print(f"{k:45s} {v}")
    return 0


def cmd_data_check(args: argparse.Namespace) -> int:
    from .measured import check_file

    print(check_file(args.file))
    return 0


def cmd_twitch_to_tetanus(args: argparse.Namespace) -> int:
    from .hatze.workflow import run_twitch_to_tetanus

    rep = run_twitch_to_tetanus(args.out, subject=args.subject, twitch_csv=args.twitch_csv, noise_nm=args.noise_nm,
                                seed=args.seed, stim_time_s=args.stim_time_s, overwrite=args.overwrite,
                                max_evaluations=args.max_evaluations)
    fit = rep["fit"]
    print(f"twitch ({rep['twitch']['source']}, subject {rep['twitch']['subject']}): rms residual "
          f"{fit['rms_residual_nm']:.4f} N m after {fit['n_evaluations']} evaluations; trend m (subject 3) "
          f"{rep['trend']['subjects']['3']['m_per_s']:.2f} 1/s (Table 3: 7.94)")
    print(f"wrote {args.out}/report.json, report.md and figures")
    return 0


def cmd_fit(args: argparse.Namespace) -> int:
    from .reports.fit import run_fit

    free = [n.strip() for n in args.free.split(",") if n.strip()] if args.free else None
    trials = [n.strip() for n in args.trials.split(",") if n.strip()] if args.trials else None
    doc = run_fit(args.data, args.out, params=args.params, free=free, trials=trials, workers=args.workers,
                  staged=args.staged, dt_ms=args.dt_ms, record_dt_ms=args.record_dt_ms, settle_ms=args.settle_ms,
                  max_iterations=args.max_iterations, progress=not args.quiet, overwrite=args.overwrite)
    for n, v in doc.get("fit", {}).get("estimates", {}).items():
        lo, hi = doc["fit"]["ci95"][n]
        print(f"{n:7s} = {v:.6g}  95% [{lo:.6g}, {hi:.6g}]")
    for tid, v in doc["nrmse_percent"].items():
        print(f"NRMSE {tid}: {v:.3f} %")
    print(f"wrote {args.out}/params.json, fit.json, summary.md and figures/")
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="neuromuscle", description=__doc__)
    sub = ap.add_subparsers(dest="command", required=True)
    s = sub.add_parser("simulate", help="simulate one unit; write HDF5 with provenance and a PNG")
    s.add_argument("--params", default="CT09", help="built-in set (CT09, CT95) or parameter file (JSON)")
    s.add_argument("--protocol", default="twitch",
                   help="twitch | train | random-train | FILE of spike times (ms)")
    s.add_argument("--rate-hz", type=float, default=20.0, help="train rate or mean rate (Hz)")
    s.add_argument("--start-ms", type=float, default=500.0, help="first stimulus (ms)")
    s.add_argument("--train-ms", type=float, default=1000.0, help="train duration (ms)")
    s.add_argument("--length", default="isometric", choices=["isometric", "step", "ramp", "random"])
    s.add_argument("--xm-mm", type=float, default=-8.0, help="(initial) muscle length (mm)")
    s.add_argument("--step-mm", type=float, default=0.5, help="step shortening amplitude (mm)")
    s.add_argument("--ramp-mm", type=float, default=4.0, help="ramp amplitude (mm, + lengthening)")
    s.add_argument("--velocity-mm-s", type=float, default=20.0, help="ramp speed (mm/s)")
    s.add_argument("--duration-ms", type=float, default=1700.0, help="simulated time (ms)")
    s.add_argument("--dt-ms", type=float, default=0.025, help="fixed step (ms)")
    s.add_argument("--record-dt-ms", type=float, default=0.5, help="recording interval (ms)")
    s.add_argument("--method", default="fixed", choices=["fixed", "cvode"])
    s.add_argument("--seed", type=int, default=0, help="seed of random protocols")
    s.add_argument("--no-length-compensation", action="store_true", help="switch eq 18 off")
    s.add_argument("--movement-compensation", action="store_true", help="switch eqs 19-20 on")
    s.add_argument("--excitation", default="kim", choices=["kim", "hatze"],
                   help="excitation model in front of Module 3: Kim Modules 1-2, or Hatze (seed 000, Table 2)")
    s.add_argument("--out", default="out/simulation.h5", help="output HDF5 file")
    s.add_argument("--png", default=None, help="figure (default: next to --out)")
    s.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    s.set_defaults(func=cmd_simulate)
    b = sub.add_parser("bench", help="benchmarks")
    bsub = b.add_subparsers(dest="what", required=True)
    bu = bsub.add_parser("unit", help="wall time per unit-second at 1 and 100 Hz; speed-up over derivimplicit")
    bu.add_argument("--params", default="CT09")
    bu.add_argument("--duration-ms", type=float, default=10_000.0)
    bu.add_argument("--repeats", type=int, default=3)
    bu.add_argument("--pool-units", type=int, default=10, help="units sharing one section in the pool figure")
    bu.add_argument("--json", action="store_true")
    bu.set_defaults(func=cmd_bench)
    bf = bsub.add_parser("fit", help="Module 2 calibration on the standard synthetic set, serial and 2 workers")
    bf.add_argument("--params", default="CT09")
    bf.add_argument("--json", action="store_true")
    bf.set_defaults(func=cmd_bench)
    d = sub.add_parser("data", help="measured data files")
    dsub = d.add_subparsers(dest="what", required=True)
    dc = dsub.add_parser("check", help="validate a measured-data HDF5 file and summarise its trials")
    dc.add_argument("file")
    dc.set_defaults(func=cmd_data_check)
    tt = sub.add_parser("twitch-to-tetanus",
                        help="seed 000 workflow: fit theta to a twitch, predict trains, trend fits, rise times")
    tt.add_argument("--out", default="out/twitch_to_tetanus", help="output directory (report.json, report.md, PNGs)")
    tt.add_argument("--subject", default="3", help="Table 1 subject (1-4) of the twitch")
    tt.add_argument("--twitch-csv", default=None,
                    help="measured twitch: CSV with columns time_s, moment_nm (default: synthetic twitch)")
    tt.add_argument("--stim-time-s", type=float, default=0.02, help="stimulus time of the twitch (s)")
    tt.add_argument("--noise-nm", type=float, default=0.05, help="noise of the synthetic twitch (N m)")
    tt.add_argument("--seed", type=int, default=0, help="seed of the synthetic twitch's noise")
    tt.add_argument("--max-evaluations", type=int, default=200, help="Levenberg-Marquardt evaluations")
    tt.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    tt.set_defaults(func=cmd_twitch_to_tetanus)
    fp = sub.add_parser("fit", help="fit a measured-data file; write params.json, fit.json, summary.md, figures")
    fp.add_argument("data", help="measured-data HDF5 file (neuromuscle.measured/1)")
    fp.add_argument("--out", required=True, help="output directory")
    fp.add_argument("--params", default="CT09", help="start set: built-in (CT09, CT95) or parameter file")
    fp.add_argument("--free", default=None,
                    help="comma-separated free parameters (default C1,C2,C3,alpha; with --staged: of the Module 2 stage)")
    fp.add_argument("--trials", default=None, help="comma-separated trial ids (default: stimulated N/mm trials)")
    fp.add_argument("--workers", type=int, default=1, help="parallel simulation processes")
    fp.add_argument("--staged", action="store_true",
                    help="seed staged calibration: Module 3 -> Module 2 (--free) -> length compensation")
    fp.add_argument("--dt-ms", type=float, default=0.05, help="fixed step (ms)")
    fp.add_argument("--record-dt-ms", type=float, default=0.5, help="recording interval (ms)")
    fp.add_argument("--settle-ms", type=float, default=300.0, help="settling before each trial (ms)")
    fp.add_argument("--max-iterations", type=int, default=30, help="optimiser iterations")
    fp.add_argument("--quiet", action="store_true", help="no per-iteration progress")
    fp.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    fp.set_defaults(func=cmd_fit)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except NeuromuscleError as exc:
        print(f"neuromuscle: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
