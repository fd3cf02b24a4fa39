"""``neuromuscle diagnose DATA.h5 --out DIR``: what the model gets wrong, the cause, the held-out gain."""

from __future__ import annotations

import argparse

from ..errors import InputError


def add_parser(sub: argparse._SubParsersAction) -> None:
    d = sub.add_parser("diagnose", help="diagnose a measured-data file: the causes of the model's misfit, named in "
                                        "order with their held-out gains; report.md, figures, params.json "
                                        "(progress on stderr)")
    d.add_argument("data", help="measured-data HDF5 file (neuromuscle.measured/1)")
    d.add_argument("--out", required=True, help="output directory")
    d.add_argument("--workers", type=int, default=1, help="parallel simulation processes (>= 1)")
    d.add_argument("--split", default=None, metavar="[heldout=]ID,ID,...",
                   help="held-out trial ids (default: automatic, by protocol)")
    d.add_argument("--quiet", action="store_true", help="no progress on stderr")
    d.add_argument("--overwrite", action="store_true", help="replace an existing report in --out")
    d.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..diagnose import run_diagnosis
    from ..diagnose.split import parse_split

    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    heldout = parse_split(args.split) if args.split is not None else None
    doc = run_diagnosis(args.data, args.out, heldout=heldout, workers=args.workers, overwrite=args.overwrite,
                        progress=not args.quiet)
    print(f"named: {', '.join(doc['named']) or 'none'}")
    for c in doc["causes"]:
        if c.get("named"):
            print(f"  step {c['step']}: {c['name']}: held-out NRMSE {c['nrmse_heldout_before']:.2f} -> "
                  f"{c['nrmse_heldout_after']:.2f} %; {c['evidence']}")
    print(f"wrote {args.out}/diagnosis.json, report.md, params.json and figures/")
    return 0
