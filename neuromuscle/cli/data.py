"""``neuromuscle data check FILE``: validate a measured-data file and summarise its trials."""

from __future__ import annotations

import argparse


def add_parser(sub: argparse._SubParsersAction) -> None:
    d = sub.add_parser("data", help="measured data files")
    dsub = d.add_subparsers(dest="what", required=True)
    dc = dsub.add_parser("check", help="validate a measured-data HDF5 file and summarise its trials")
    dc.add_argument("file")
    dc.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..measured import check_file

    print(check_file(args.file))
    return 0
