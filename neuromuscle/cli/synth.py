"""``neuromuscle synth --cause NAME|none --strength S --seed N --out FILE.h5 [--world W] [--also NAME=S,...]``:
write a synthetic preparation with hidden effects (``neuromuscle.synth``); ``--list`` lists the causes, their
strength ranges and the worlds."""

from __future__ import annotations

import argparse
import time

from ..errors import InputError


def _on_off(text: str) -> bool:
    if text not in ("on", "off"):
        raise argparse.ArgumentTypeError(f"expected 'on' or 'off', got {text!r}")
    return text == "on"


def add_parser(sub: argparse._SubParsersAction) -> None:
    sp = sub.add_parser("synth", help="write a synthetic measured-data file with hidden effects, in a chosen world")
    sp.add_argument("--list", action="store_true", help="list the causes, their hidden forms and strength ranges, "
                                                        "and the worlds")
    sp.add_argument("--cause", help="a canonical cause, an out-of-catalogue effect (see --list), or 'none'")
    sp.add_argument("--strength", type=float, default=0.5, help="0-1, mapped onto the cause's amplitude range")
    sp.add_argument("--also", default=None, metavar="CAUSE=STRENGTH[,...]",
                    help="further hidden effects played with the first (e.g. fatigue=0.6)")
    sp.add_argument("--seed", type=int, help="integer >= 0: the preparation, its noise and drift")
    sp.add_argument("--noise", type=float, default=1.5, help="AR(1) transducer noise sd, %% of the preparation's P0")
    sp.add_argument("--noise-tau-ms", type=float, default=5.0, help="noise correlation time (ms)")
    sp.add_argument("--variation", type=float, default=0.2,
                    help="log-sd of the per-parameter factors around the base set (0.2: about 20 %%)")
    sp.add_argument("--world", default="B", help="the world (see --list): base model, protocol set, sampling, "
                                                 "static points; the options below change one setting of it")
    sp.add_argument("--base", choices=("CT09", "CT95"), default=None, help="base parameter set")
    sp.add_argument("--eq18", type=_on_off, default=None, metavar="on|off",
                    help="length-dependent activation (eq 18) in the data's model")
    sp.add_argument("--eqs19-20", dest="eqs19_20", type=_on_off, default=None, metavar="on|off",
                    help="movement-induced depression and the lengthening divisor (eqs 19-20) in the data's model")
    sp.add_argument("--protocols", default=None, help="protocol set: extended, standard, reduced or ramps")
    sp.add_argument("--drop", default=None, metavar="PROTOCOL[,...]", help="protocols left out of the set")
    sp.add_argument("--sample-rate-hz", type=float, default=None, help="sampling rate (Hz, 100-20000)")
    sp.add_argument("--samples-per-trial", type=int, default=None,
                    help="keep this many uneven samples per trial (digitised data; 10-200)")
    sp.add_argument("--static-points", type=_on_off, default=None, metavar="on|off",
                    help="force-length and force-velocity points in the file")
    sp.add_argument("--workers", type=int, default=1, help="processes simulating trials")
    sp.add_argument("--out", help="the HDF5 file to write")
    sp.add_argument("--overwrite", action="store_true", help="replace an existing file")
    sp.set_defaults(func=run)


def list_text() -> str:
    """The text of --list: every cause, its amplitude range, the trials that show it and its hidden form; then the
    worlds."""
    from ..synth import ALL
    from ..synth.worlds import WORLDS

    lines = ["cause (strength 0 -> 1 maps linearly onto amplitude low -> high)"]
    for e in ALL.values():
        tag = "" if e.in_catalogue else "  [outside the catalogue: expect 'unexplained']"
        lines.append(f"{e.name}: amplitude {e.low:g} .. {e.high:g} ({e.unit}; {e.meaning}){tag}")
        lines.append(f"    shows in: {', '.join(e.shows_in)}")
        lines.append(f"    form: {e.form}")
    lines.append("none: no hidden effect (the null preparation)")
    lines += ["", "worlds"]
    for w in WORLDS.values():
        lines.append(f"{w.name}: {w.description}")
    return "\n".join(lines)


def parse_also(text: str | None) -> dict[str, float]:
    """``--also`` text, ``CAUSE=STRENGTH[,...]``, as {cause: strength}; InputError naming a malformed item."""
    from .simulate import parse_assignments

    return parse_assignments(text or "", lambda piece: f"--also {piece!r}: give CAUSE=STRENGTH, strength a number "
                                                       "in [0, 1]")


def world_from(args: argparse.Namespace):
    """The world of ``--world`` with the settings the other options change (a changed world is named after its
    base world with a '+' suffix)."""
    from ..synth.worlds import world

    w = world(args.world)
    changes = {k: v for k, v in (("base", args.base), ("length_dependence", args.eq18),
                                 ("movement_terms", args.eqs19_20), ("protocols", args.protocols),
                                 ("sample_rate_hz", args.sample_rate_hz),
                                 ("samples_per_trial", args.samples_per_trial),
                                 ("static_points", args.static_points)) if v is not None}
    if args.drop:
        changes["drop"] = tuple(p.strip() for p in args.drop.split(",") if p.strip())
    if args.samples_per_trial is not None and not 10 <= args.samples_per_trial <= 200:
        raise InputError(f"--samples-per-trial must be 10-200, got {args.samples_per_trial}")
    return w.with_settings(name=f"{w.name}+", **changes) if changes else w


def run(args: argparse.Namespace) -> int:
    from ..synth import write_dataset

    if args.list:
        print(list_text())
        return 0
    missing = [f"--{n}" for n in ("cause", "seed", "out") if getattr(args, n) is None]
    if missing:
        raise InputError(f"synth needs {', '.join(missing)} (or --list)")
    w = world_from(args)
    start = time.perf_counter()
    path = write_dataset(args.out, args.cause, args.strength, args.seed, overwrite=args.overwrite,
                         noise_pct=args.noise, noise_tau_ms=args.noise_tau_ms, variation=args.variation,
                         workers=args.workers, world=w, also=parse_also(args.also))
    print(f"wrote {path} ({time.perf_counter() - start:.1f} s, world {w.name}); the hidden truth is in its /synth "
          "group")
    return 0
