"""``neuromuscle simulate``: one unit, a built-in or file protocol -> HDF5 with provenance and a PNG."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .. import protocols
from ..errors import InputError
from ..protocols import LengthTrace
from ..reports.outdir import refuse_existing_file


def add_parser(sub: argparse._SubParsersAction) -> None:
    s = sub.add_parser("simulate", help="simulate one unit; write HDF5 with provenance and a PNG")
    s.add_argument("--params", default="CT09", help="built-in set (CT09, CT95) or parameter file (JSON)")
    s.add_argument("--protocol", default="twitch", help="twitch | train | random-train | FILE of spike times (ms)")
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
    s.add_argument("--no-length-compensation", action="store_true", help="switch eq 18 off (Kim excitation)")
    s.add_argument("--movement-compensation", action="store_true", help="switch eqs 19-20 on (Kim excitation)")
    s.add_argument("--excitation", default="kim", choices=["kim", "hatze"],
                   help="excitation model in front of Module 3: Kim Modules 1-2, or Hatze (van Zandwijk et al. 1998, "
                        "Table 2)")
    s.add_argument("--extension", action="append", default=[], metavar="NAME[:PARAM=VALUE,...]",
                   help="switch a model extension on (repeatable), e.g. --extension fatigue")
    s.add_argument("--out", default="out/simulation.h5", help="output HDF5 file")
    s.add_argument("--png", default=None, help="figure (default: next to --out)")
    s.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    s.set_defaults(func=run)


def read_spike_file(path: str) -> np.ndarray:
    """Spike times (ms) from a text file, one per line ('#' comments allowed); InputError naming the line."""
    times = []
    for i, line in enumerate(Path(path).read_text().splitlines(), start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        try:
            times.append(float(text))
        except ValueError:
            raise InputError(f"{path}, line {i}: {text!r} is not a spike time in ms (one number per line)") from None
    return np.array(times, dtype=float)


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
    if not Path(args.protocol).is_file():
        raise InputError(f"--protocol {args.protocol!r}: neither twitch, train, random-train nor a file of spike "
                         "times (ms, one per line)")
    return read_spike_file(args.protocol), {"protocol": "file", "path": args.protocol}


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


def parse_assignments(text: str, bad: Callable[[str], str]) -> dict[str, float]:
    """``"KEY=NUMBER,KEY=NUMBER"`` -> {key: number}; InputError with ``bad(piece)`` for a piece that is not one."""
    out: dict[str, float] = {}
    for piece in filter(str.strip, text.split(",")):
        key, eq, value = piece.partition("=")
        try:
            out[key.strip()] = float(value)
        except ValueError:
            raise InputError(bad(piece)) from None
        if not eq:
            raise InputError(bad(piece))
    return out


def parse_extensions(items: list[str]) -> dict[str, dict[str, float]]:
    """``["fatigue", "staircase:k=0.2,tau=500"]`` -> {name: {param: value}}; InputError on bad syntax."""
    out: dict[str, dict[str, float]] = {}
    for item in items:
        name, _, rest = item.partition(":")
        bad = f"--extension {item!r}: expected NAME[:PARAM=VALUE,...]"
        out[name.strip()] = parse_assignments(rest, lambda _, bad=bad: bad)
    return out


def _plot(result, path: Path, title: str) -> None:
    from ..reports.figures import label_axes, new_figure, save_figure, set_title

    panels = [(result.force_N, "force (N)" if result.output == "force.F" else "moment (N m)", "k"),
              (result.A, "activation A (1)", "C0"), (result.length_mm, "length Xm (mm)", "C1")]
    fig, axes = new_figure(len(panels), sharex=True)
    for i, (ax, (y, label, colour)) in enumerate(zip(axes, panels)):
        ax.plot(result.t_ms, y, colour)
        label_axes(ax, x="time (ms)" if i == len(panels) - 1 else None, y=label)
    set_title(axes[0], title)
    save_figure(fig, path)


def run(args: argparse.Namespace) -> int:
    from ..model import hatze_excitation, kim_excitation
    from ..parameters import load_parameters
    from ..sim import simulate

    params = load_parameters(args.params)
    spikes, proto = _stimulus(args)
    length, lproto = _length(args)
    out = refuse_existing_file(args.out, args.overwrite)  # before the run: a refusal costs nothing
    excitation = kim_excitation(not args.no_length_compensation, args.movement_compensation) \
        if args.excitation == "kim" else hatze_excitation()
    result = simulate(params, spikes, length, args.duration_ms, dt_ms=args.dt_ms, method=args.method,
                      record_dt_ms=args.record_dt_ms, excitation=excitation,
                      extensions=parse_extensions(args.extension),
                      provenance_extra={"protocol": proto, "length_protocol": lproto,
                                        "command": " ".join(sys.argv)})
    out.parent.mkdir(parents=True, exist_ok=True)
    result.save(out, overwrite=args.overwrite)
    png = Path(args.png) if args.png else out.with_suffix(".png")
    what = {"train": f"{args.rate_hz:g} Hz train", "random-train": f"random train, mean {args.rate_hz:g} Hz",
            "twitch": "twitch", "file": f"spikes from {Path(args.protocol).name}"}[proto["protocol"]]
    where = {"isometric": f"isometric at {args.xm_mm:g} mm", "step": f"{args.step_mm:g} mm step shortening",
             "ramp": f"{args.ramp_mm:+g} mm ramp at {args.velocity_mm_s:g} mm/s",
             "random": f"random length (seed {args.seed})"}[lproto["length"]]
    title = f"{params.name}: {what}, {where}"
    _plot(result, png, title)
    peak = float(result.force_N.max())
    print(f"{params.name}: {proto['protocol']} at {lproto['length']}, {result.t_ms[-1]:.0f} ms, "
          f"{result.settings['n_spikes']} spikes: peak force {peak:.3f} N ({peak / params['P0']:.3f} P0)")
    for w in result.warnings:
        print(f"warning: {w}")
    print(f"wrote {out} and {png}")
    return 0
