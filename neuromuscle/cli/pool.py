"""``neuromuscle pool [DEFINITION] --out DIR``: run a motor-unit pool from a definition file (TOML or JSON) or flags;
writes DIR/pool.h5 (with provenance), DIR/pool.nwb and DIR/pool.png; progress on stderr.

Under ``mpiexec -n N neuromuscle pool ...`` the units are spread over the ranks and rank 0 alone writes.  The
definition file's sections and defaults: ``neuromuscle.pool.pool_file``; a flag replaces the file's field.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

from ..errors import NeuromuscleError

#: The files written into --out.
FILES = ("pool.h5", "pool.nwb", "pool.png")

def _numbers(kind: type) -> Any:
    def parse(text: str) -> list:
        try:
            return [kind(x) for x in text.split(",") if x.strip()]
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected comma-separated {kind.__name__}s, got {text!r}") from None
    return parse


def _setting(text: str) -> dict[str, float]:
    """One ``--set NAME=VALUE``: a reduced cell's parameter and its number (``motoneuron.parse_settings``)."""
    from ..pool.motoneuron import parse_settings

    try:
        return parse_settings([text])
    except NeuromuscleError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def flag_table() -> list[tuple[str, list[tuple[str, str, dict[str, Any]]]]]:
    """The flags by group: (group title, [(flag, the definition file's field it sets, argparse options)])."""
    from ..pool.definition import MUSCLE_MODELS
    from ..pool.motoneuron import CHANNELS, PROFILES, describe_profiles
    from ..pool.pool_file import DRIVES
    from ..sim.simulator import ENGINES

    number = {"type": float}
    return [
        ("units (default: 20 units, 70/20/10 % S/FR/FF, P0s summing to 600 N over a 100-fold range, 900 mm axons, "
         "human motoneurons)", [
            ("--name", "name", {"help": "the pool's name"}),
            ("--units", "units.count", {"type": int, "help": "number of motor units"}),
            ("--params", "units.params", {"help": "base muscle parameter set (CT09, CT95 or a parameter file)"}),
            ("--types", "units.types", {"type": _numbers(float), "metavar": "S,FR,FF",
                                        "help": "type fractions (sum 1)"}),
            ("--total-p0-n", "units.total_p0_N", {**number, "help": "the unit P0s sum to this (N)"}),
            ("--smallest-p0-n", "units.smallest_p0_N",
             {**number, "help": "the smallest unit's P0 (N; instead of --total-p0-n)"}),
            ("--p0-range", "units.p0_range", {**number, "help": "largest / smallest P0"}),
            ("--max-size", "units.max_size",
             {**number, "help": "the largest cell's size index (0..1; the smallest cell's is 0)"}),
            ("--size-spacing", "units.size_spacing",
             {**number, "help": "how sizes spread over the ranks (1: uniform; K > 1: a K-fold property grows "
                                "linearly with rank)"}),
            ("--axon-length-mm", "units.axon_length_mm", {**number, "help": "axon length (mm)"}),
            ("--motoneurons", "units.motoneurons",
             {"choices": tuple(PROFILES), "help": f"the reduced cells' profile ({describe_profiles()})"}),
            ("--neuromodulation", "units.neuromodulation",
             {**number, "help": "PIC strength (0: none; 1: the decerebrate cat's; default: the profile's)"}),
            ("--synaptic-noise-us", "units.synaptic_noise_uS",
             {**number, "help": "each cell's own synaptic noise, its standard deviation at a synaptic drive of 1 "
                                "uS (uS; 0: none; the fixed step and synaptic drives only; default: the profile's)"}),
            ("--noise-seed", "units.noise_seed", {"type": int, "help": "seed of the cells' synaptic noise"}),
            ("--set", "units.set", {"action": "append", "type": _setting, "metavar": "NAME=VALUE", "help": (
                "a reduced cell's parameter replaced in every cell, over the profile's (repeatable; e.g. "
                "g_km_S_per_cm2=0, cal_vhalf_mV=-52)")}),
            ("--muscle", "units.muscle", {"choices": MUSCLE_MODELS, "help": "three Kim mechanisms, fused "
                                          "(KimUnit) or fused_fixed (KimUnitFixed: the fixed step only)"}),
            ("--channels", "units.channels", {"choices": CHANNELS, "help": "motoneuron channel mechanisms"})]),
        ("drive (default: ramp to 0.7 uS)", [
            ("--drive", "drive.kind", {"choices": DRIVES, "help": (
                "ramp: common synaptic conductance 0 -> --peak-us over the first half, held, back to 0; rise: 0 -> "
                "--peak-us over the run; current: common current 0 -> --peak-na over the run; poisson: independent "
                "Poisson excitation; synaptic: times and values from the file")}),
            ("--peak-us", "drive.peak_uS", {**number, "help": "peak synaptic conductance (uS, each cell's total)"}),
            ("--peak-na", "drive.peak_nA", {**number, "help": "peak common current (nA; --drive current)"}),
            ("--rate-hz", "drive.rate_hz", {**number, "help": "Poisson rate per motoneuron (Hz)"}),
            ("--weight-us", "drive.weight_uS", {**number, "help": "Poisson synaptic weight (uS)"}),
            ("--seed", "drive.seed", {"type": int, "help": "Poisson seed"})]),
        ("length and run (default: isometric at -8 mm, 500 ms, fixed step 0.025 ms)", [
            ("--length-mm", "length.mm", {**number, "help": "isometric muscle length (mm)"}),
            ("--duration-ms", "run.duration_ms", {**number, "help": "simulated time (ms)"}),
            ("--dt-ms", "run.dt_ms", {**number, "help": "fixed step (ms)"}),
            ("--record-dt-ms", "run.record_dt_ms",
             {**number, "help": "sampling interval of forces and recordings (ms)"}),
            ("--method", "run.method", {"choices": ("fixed", "cvode"), "help": "integrator"}),
            ("--engine", "run.engine", {"choices": ENGINES, "help": "compute engine (coreneuron: fixed step)"}),
            ("--secondorder", "run.secondorder", {"type": int, "choices": (0, 1, 2), "help": (
                "the fixed step's scheme for the membrane: 0 backward Euler, 2 Crank-Nicolson (second order)")}),
            ("--record", "record.variables", {"action": "append", "metavar": "VAR", "help": (
                "record a variable (repeatable): mn.v, mn.v_dend, mn.i_pic, mn.cai, or a muscle unit's (ca.CaSPT, "
                "act.A, force.F, ...)")}),
            ("--record-units", "record.units", {"type": _numbers(int), "metavar": "I,J,...",
                                                "help": "units to record (default: every unit)"})]),
    ]


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("pool", help="run a motor-unit pool (definition file or flags, MPI-ready); write "
                                    "pool.h5, pool.nwb and pool.png")
    p.add_argument("definition", nargs="?", default=None,
                   help="definition file (.toml or .json: sections units, drive, length, run, record, "
                        "motoneuron, reflex: the stretch-reflex loop, with a ramp-and-hold length); flags replace "
                        "its fields; without it the flags and the defaults (a human pool) define the run")
    p.add_argument("--out", required=True, help="output folder (pool.h5, pool.nwb, pool.png)")
    p.add_argument("--overwrite", action="store_true", help="replace those files in --out")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    for title, flags in flag_table():
        g = p.add_argument_group(title)
        for flag, _, options in flags:
            g.add_argument(flag, **options)
    p.set_defaults(func=run)


def flag_document(args: argparse.Namespace) -> tuple[dict[str, Any], dict[str, str]]:
    """The definition fields set by flags, as a document, and field -> flag (for error messages)."""
    doc: dict[str, Any] = {}
    flagged: dict[str, str] = {}
    for flag, name, _ in (f for _, flags in flag_table() for f in flags):
        value = getattr(args, flag[2:].replace("-", "_"), None)
        if value is None:
            continue
        if name == "units.set":          # one {name: value} a flag, in the order given
            value = {k: v for item in value for k, v in item.items()}
        section, _, key = name.partition(".")
        if key:
            doc.setdefault(section, {})[key] = value
        else:
            doc[section] = value
        flagged[name] = flag
    if "length.mm" in flagged:
        doc["length"]["kind"] = "isometric"
    return doc, flagged


def _say(quiet: bool, rank: int, text: str) -> None:
    if not quiet and rank == 0:
        print(text, file=sys.stderr, flush=True)


def _provenance(setup: Any, args: argparse.Namespace) -> dict[str, Any]:
    """What the run adds to the result's provenance: the whole definition (defaults filled in), the drive as
    played, the base muscle parameters and the command."""
    d = setup.definition
    return {"definition": setup.document, "definition_file": args.definition, "command": " ".join(sys.argv),
            "drive_detail": setup.drive.to_dict(), "muscle_parameters": d.muscle.to_json(),
            "axon_length_mm": d.axon_length_mm, "neuromodulation": d.neuromodulation,
            "synaptic_noise_uS": d.synaptic_noise_uS, "noise_seed": d.noise_seed,
            "motoneuron_overrides": dict(d.motoneuron_overrides), "motoneuron_scales": dict(d.motoneuron_scales)}


def _run(args: argparse.Namespace, rank: int, nhost: int) -> int:
    from ..pool.pool_file import merge, pool_setup, read_document
    from ..pool.run_mpi import run_definition
    from ..reports.outdir import check_out_dir, prepare_out_dir

    doc, flagged = flag_document(args)
    source = args.definition or "command line"
    if args.definition:
        doc = merge(read_document(args.definition), doc)
    setup = pool_setup(doc, source, flagged, Path(args.definition).parent if args.definition else None)
    out = check_out_dir(args.out, args.overwrite, FILES)  # every rank: the same answer, before the run
    d = setup.definition
    drive = setup.document["drive"]["kind"]
    r = setup.reflex
    loop = "" if r is None else (f", stretch reflex ({r.n_ia} Ia, {r.n_ii} II, {r.n_ib} Ib"
                                 f"{', dorsal roots cut' if r.cut_dorsal_roots else ''})")
    _say(args.quiet, rank, f"pool {d.name!r}: {d.n_units} units on {nhost} rank(s), {drive} drive{loop}, "
                           f"{setup.duration_ms:g} ms ({setup.simulator.method}, {setup.simulator.engine})")
    t0 = time.perf_counter()

    def progress(t_ms: float) -> None:
        _say(args.quiet, rank, f"  {t_ms:7.1f} of {setup.duration_ms:g} ms ({100.0 * t_ms / setup.duration_ms:3.0f} "
                               f"%), {time.perf_counter() - t0:.1f} s")

    result, report = run_definition(d, setup.drive, setup.simulator, setup.duration_ms, nhost, length=setup.length,
                                    record_dt_ms=setup.record_dt_ms, recordings=setup.recordings, progress=progress,
                                    cells=setup.cells, reflex=setup.reflex)
    if rank != 0:
        return 0
    result.provenance.update(_provenance(setup, args))
    if "afferents" in report:
        result.provenance["afferents"] = report["afferents"]
    folder = prepare_out_dir(out, args.overwrite, FILES)
    paths = [folder / f for f in FILES]
    result.save(paths[0], overwrite=args.overwrite)
    result.save_nwb(paths[1], overwrite=args.overwrite)
    result.figure(paths[2], title=f"pool {d.name!r}: {d.n_units} units, {drive} drive")
    summary = {"units": d.n_units, "ranks": nhost, "recruited": int(sum(s.size > 0 for s in result.spikes_ms)),
               "spikes": report["spikes"], "peak_pool_force_N": round(report["pool_force_peak_N"], 4),
               "sim_s": round(report["sim_s"], 2), "recorded": sorted(result.recordings),
               "median_rates_p5_p50_p95_hz": report["median_rates_p5_p50_p95_hz"],
               "medians_inside_human_range": report["medians_inside_human_range"],
               "delta_f": report["delta_f"], "isi_cv_p5_p50_p95": report["isi_cv_p5_p50_p95"],
               "files": [str(p) for p in paths]}
    if "afferents" in report:
        summary["afferents"] = report["afferents"]
    _say(args.quiet, rank, f"  done in {time.perf_counter() - t0:.1f} s")
    print(json.dumps(summary))
    return 0


def run(args: argparse.Namespace) -> int:
    """Run the command; under an MPI launcher every rank runs it, rank 0 reports errors and writes, and the
    process ends here (NEURON's MPI must be left on every rank)."""
    from ..pool.mpi import finish_mpi, init_mpi, launcher_size

    if launcher_size() is None:
        return _run(args, 0, 1)
    rank = 0
    try:
        rank, nhost = init_mpi()
        code = _run(args, rank, nhost)
    except NeuromuscleError as exc:
        if rank == 0:
            print(f"neuromuscle: error: {exc}", file=sys.stderr, flush=True)
        code = 2
    finish_mpi(code)
