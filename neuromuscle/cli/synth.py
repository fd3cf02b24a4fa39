"""``neuromuscle synth --cause NAME|none --strength S --seed N --noise PCT --out FILE.h5
[--protocols extended|standard] [--overwrite]``: write a synthetic preparation with one hidden effect
(``neuromuscle.synth``); ``neuromuscle synth --list`` lists the causes and their strength ranges."""

from __future__ import annotations

import argparse
import time

from ..errors import InputError


def add_parser(sub: argparse._SubParsersAction) -> None:
    sp = sub.add_parser("synth", help="write a synthetic measured-data file with one hidden effect (docs/synth.md)")
    sp.add_argument("--list", action="store_true", help="list the causes, their hidden forms and strength ranges")
    sp.add_argument("--cause", help="a canonical cause, an out-of-catalogue effect (see --list), or 'none'")
    sp.add_argument("--strength", type=float, default=0.5, help="0-1, mapped onto the cause's amplitude range")
    sp.add_argument("--seed", type=int, help="integer >= 0: the preparation, its noise and drift")
    sp.add_argument("--noise", type=float, default=1.5, help="AR(1) transducer noise sd, %% of the preparation's P0")
    sp.add_argument("--noise-tau-ms", type=float, default=5.0, help="noise correlation time (ms)")
    sp.add_argument("--variation", type=float, default=0.2,
                    help="log-sd of the per-parameter factors around CT09 (0.2: about 20 %%)")
    sp.add_argument("--workers", type=int, default=1, help="processes simulating trials")
    sp.add_argument("--protocols", default="extended",
                    help="the protocol set: extended (the default since stop 36: 36 trials since stop 39, ~127 s) or standard (its "
                         "first 28 trials, ~92 s: without the twitch series, post-tetanic probes and cyclic length)")
    sp.add_argument("--out", help="the HDF5 file to write")
    sp.add_argument("--overwrite", action="store_true", help="replace an existing file")
    sp.set_defaults(func=run)


def list_text() -> str:
    """The table of --list: every cause, its amplitude range, the trials that show it and its hidden form."""
    from ..synth import ALL

    lines = ["cause (strength 0 -> 1 maps linearly onto amplitude low -> high)"]
    for e in ALL.values():
        tag = "" if e.in_catalogue else "  [outside the catalogue: expect 'unexplained']"
        lines.append(f"{e.name}: amplitude {e.low:g} .. {e.high:g} ({e.unit}; {e.meaning}){tag}")
        lines.append(f"    shows in: {', '.join(e.shows_in)}")
        lines.append(f"    form: {e.form}")
    lines.append("none: no hidden effect (the null preparation)")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from ..synth import write_dataset

    if args.list:
        print(list_text())
        return 0
    missing = [f"--{n}" for n in ("cause", "seed", "out") if getattr(args, n) is None]
    if missing:
        raise InputError(f"synth needs {', '.join(missing)} (or --list)")
    start = time.perf_counter()
    path = write_dataset(args.out, args.cause, args.strength, args.seed, overwrite=args.overwrite,
                         noise_pct=args.noise, noise_tau_ms=args.noise_tau_ms, variation=args.variation,
                         workers=args.workers, protocols=args.protocols)
    print(f"wrote {path} ({time.perf_counter() - start:.1f} s); the hidden truth is in its /synth group")
    return 0
