"""``neuromuscle data check FILE``: validate a measured-data file and summarise its trials.
``neuromuscle data example OUT``: write a copy of the package's example file (``neuromuscle.measured.example``)."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction) -> None:
    d = sub.add_parser("data", help="measured data files")
    dsub = d.add_subparsers(dest="what", required=True)
    dc = dsub.add_parser("check", help="validate a measured-data HDF5 file and summarise its trials")
    dc.add_argument("file")
    dc.set_defaults(func=run)
    de = dsub.add_parser("example", help="write a copy of the example file: a synthetic cat soleus unit made "
                                         "from stated parameters (they are in its /provenance attributes)")
    de.add_argument("out", help="the HDF5 file to write")
    de.add_argument("--overwrite", action="store_true", help="replace an existing file")
    de.set_defaults(func=run_example)


def run(args: argparse.Namespace) -> int:
    from ..measured import check_file

    print(check_file(args.file))
    return 0


def run_example(args: argparse.Namespace) -> int:
    from ..measured import example_path, read_measured, write_measured

    print(f"wrote {write_measured(args.out, read_measured(example_path()), overwrite=args.overwrite)}")
    return 0
