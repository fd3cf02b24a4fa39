"""``neuromuscle bench unit | fit``: benchmarks; each default run takes about two minutes, ``--full`` longer."""

from __future__ import annotations

import argparse
import json


def add_parser(sub: argparse._SubParsersAction) -> None:
    b = sub.add_parser("bench", help="benchmarks (default run about two minutes; --full for the long form)")
    bsub = b.add_subparsers(dest="what", required=True)
    bu = bsub.add_parser("unit", help="wall time per unit-second at 1 and 100 Hz; speed-up over derivimplicit")
    bu.add_argument("--params", default="CT09")
    bu.add_argument("--duration-ms", type=float, default=None, help="simulated time (default 3000; --full 10000)")
    bu.add_argument("--repeats", type=int, default=None, help="best of N (default 2; --full 3)")
    bu.add_argument("--pool-units", type=int, default=10, help="units sharing one section in the pool figure")
    bu.add_argument("--full", action="store_true", help="the long form: 10 s, 3 repeats, authors' pool at 100 Hz")
    bu.add_argument("--json", action="store_true")
    bu.set_defaults(func=run)
    bf = bsub.add_parser("fit", help="Module 2 calibration on the standard synthetic set, serial and 2 workers")
    bf.add_argument("--params", default="CT09")
    bf.add_argument("--json", action="store_true")
    bf.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..parameters import load_parameters

    params = load_parameters(args.params)
    if args.what == "fit":
        from ..bench.fit import bench_fit

        res = bench_fit(params)
    else:
        from ..bench.unit import bench_unit

        duration = args.duration_ms if args.duration_ms is not None else (10_000.0 if args.full else 3000.0)
        repeats = args.repeats if args.repeats is not None else (3 if args.full else 2)
        res = bench_unit(params, duration_ms=duration, repeats=repeats, pool_units=args.pool_units,
                         full=args.full)
    if args.json:
        print(json.dumps(res, indent=2))
    else:
        for k, v in res.items():
            print(f"{k:45s} {v}")
    return 0
