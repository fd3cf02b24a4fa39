"""Command line: ``neuromuscle simulate | pool | fit | diagnose | data check | data example | synth |
twitch-to-tetanus | discharges | bench ... | info``.

One module per command, each with ``add_parser(subparsers)`` and ``run(args) -> exit code``.  A NeuromuscleError
becomes a one-line message on stderr and exit code 2.
"""

from __future__ import annotations

import argparse
import sys

from ..errors import NeuromuscleError
from . import bench, data, diagnose, discharges, fit, info, pool, simulate, synth, twitch_to_tetanus

COMMANDS = (simulate, pool, fit, diagnose, data, synth, twitch_to_tetanus, discharges, bench, info)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    ap = argparse.ArgumentParser(prog="neuromuscle", description="Muscle inside NEURON: " + ", ".join(
        c.__name__.rsplit(".", 1)[1].replace("_", "-") for c in COMMANDS))
    sub = ap.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.add_parser(sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``neuromuscle`` command."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except NeuromuscleError as exc:
        print(f"neuromuscle: error: {exc}", file=sys.stderr)
        return 2
