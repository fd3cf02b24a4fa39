"""``neuromuscle info``: versions, the compiled-mechanism cache and hash, MPI availability."""

from __future__ import annotations

import argparse
import json


def add_parser(sub: argparse._SubParsersAction) -> None:
    i = sub.add_parser("info", help="versions, mechanism cache path and hash, MPI availability")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=run)


def describe() -> dict:
    """What this installation is: versions, mod folder, mechanism hash and cache, MPI."""
    import importlib.util

    from ..model.mechanisms import cache_root, mechanism_hash, mod_dir
    from ..sim.provenance import versions

    return {"versions": versions(), "mod_dir": str(mod_dir()), "mechanism_sha256": mechanism_hash(),
            "mechanism_cache": str(cache_root()),
            "mpi4py_installed": importlib.util.find_spec("mpi4py") is not None}


def run(args: argparse.Namespace) -> int:
    doc = describe()
    if args.json:
        print(json.dumps(doc, indent=2))
    else:
        for k, v in doc.pop("versions").items():
            print(f"{k:18s} {v}")
        for k, v in doc.items():
            print(f"{k:18s} {v}")
    return 0
