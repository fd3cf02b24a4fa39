"""``neuromuscle bench unit | fit | diagnose | intervals | sweep | pool``: benchmarks; each default run takes about two
minutes, ``--full``
longer."""

from __future__ import annotations

import argparse
import json

from ..errors import InputError
from ..bench.pool import DEFAULT_DT_MS
from ..pool.definition import MUSCLE_MODELS
from ..pool.motoneuron import CHANNELS, PROFILES, describe_profiles


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
    bd = bsub.add_parser("diagnose", help="wall and CPU time of one full diagnosis of a synthetic file (a null, or "
                                          "one hiding --cause; the world --world, by default B: 36 trials) and of "
                                          "its baseline calibration alone")
    bd.add_argument("--workers", type=int, default=2)
    bd.add_argument("--world", default="B", help="the world of the single file (neuromuscle synth --list)")
    bd.add_argument("--cause", default=None, help="the single file's hidden cause (neuromuscle synth --list; "
                                                  "default: none, a null)")
    bd.add_argument("--strength", type=float, default=0.7, help="with --cause: its strength, 0-1 of its range")
    bd.add_argument("--suite", type=int, default=None, metavar="N",
                    help="instead: N synthetic preparations per cause and world (every canonical cause, the "
                         "out-of-catalogue effect, none) diagnosed blind; rates per cause and world (2-5 min a "
                         "preparation)")
    bd.add_argument("--worlds", default="B", help="with --suite: the worlds, comma separated")
    bd.add_argument("--two-effect", type=int, default=0, metavar="K",
                    help="with --suite: also K preparations per world with two hidden causes at once")
    bd.add_argument("--causes", default=None, help="with --suite: only these causes, comma separated")
    bd.add_argument("--seed", type=int, default=0, help="with --suite: the draws' seed")
    bd.add_argument("--journal", default=None, metavar="FILE",
                    help="with --suite: append each finished case to FILE as a JSON line")
    bd.add_argument("--first", type=int, default=1, metavar="K",
                    help="with --suite: start at case K (1-based, the order of the progress lines): resume a suite")
    bd.add_argument("--score", nargs="+", default=None, metavar="JOURNAL",
                    help="instead: score the finished cases of suite journals (several partial or parallel runs "
                         "as one; a name ending in .gz is read gzip-compressed), no diagnosis run")
    bd.add_argument("--reach", action="store_true",
                    help="with --suite: measure each candidate's held-out evidence from what the model before "
                         "and the candidate's model each reach within their calibration confidence region (an "
                         "option of the diagnosis, off by default; docs/validation/diagnosis.md)")
    bd.add_argument("--separability", action="store_true",
                    help="with --suite: instead of diagnosing, how far each case's hidden effect can be told from "
                         "calibration, to first order at the truth (about 1 min a case)")
    bd.add_argument("--json", action="store_true")
    bd.set_defaults(func=run_diagnose)
    bi = bsub.add_parser("intervals", help="coverage of the fit's 95 %% intervals on SciPy reference data with "
                                           "AR(1) noise, every interval method on the same draws")
    bi.add_argument("--params", default="CT09", help="base set: the fits start from it; the truth is it with the "
                                                    "example file's C1, C2, C3, alpha")
    bi.add_argument("--draws", type=int, default=None, help="noise draws, one fit each (default 8; --full 40)")
    bi.add_argument("--full", action="store_true", help="40 draws (tens of minutes on 2 cores)")
    bi.add_argument("--workers", type=int, default=2, help="draws fitted at a time")
    bi.add_argument("--noise-n", type=float, default=0.02, help="noise sd (N)")
    bi.add_argument("--tau-ms", type=float, default=10.0, help="noise correlation time (ms; 0: white)")
    bi.add_argument("--seed", type=int, default=0)
    bi.add_argument("--objective", default="nrmse", help="nrmse (the README's) or sse")
    bi.add_argument("--data", default="reference",
                    help="reference: the standard Module 2 set by the SciPy reference; example: the example file's "
                         "protocols made as it is made (NEURON)")
    bi.add_argument("--per-draw", action="store_true", help="with --json: every draw's estimates and intervals")
    bi.add_argument("--json", action="store_true")
    bi.set_defaults(func=run)
    bs = bsub.add_parser("sweep", help="random parameter sets around --params under the seeds' protocols, fixed "
                                       "step and CVODE: exceptions, hangs, non-finite or negative force, "
                                       "fixed-vs-CVODE difference; exit code 1 when a check fails")
    bs.add_argument("--params", default="CT09", help="the set the draws scatter around")
    bs.add_argument("--draws", type=int, default=10, help="parameter sets (default 10: about two minutes)")
    bs.add_argument("--seed", type=int, default=0)
    bs.add_argument("--workers", type=int, default=2, help="processes (spawned), one draw at a time each")
    bs.add_argument("--steps-per-ms", type=int, default=None,
                    help="CVODE step budget of one run per simulated ms (default 1000; CT09 needs at most 170)")
    bs.add_argument("--run-budget-s", type=float, default=None,
                    help="CVODE wall-time budget of one run (s; default 60)")
    bs.add_argument("--draw-timeout-s", type=float, default=None,
                    help="process-level timeout of one draw (s; default per protocol the run budget + 20 s)")
    bs.add_argument("--short", action="store_true", help="the protocols about half as long")
    bs.add_argument("--out", default=None, help="write the full report (summary, draws, every run) as JSON")
    bs.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    bs.add_argument("--journal", default=None,
                    help="append each finished draw to this file (JSON lines); if it exists, reuse its draws (resume)")
    bs.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    bs.add_argument("--json", action="store_true")
    bs.set_defaults(func=run_sweep)
    bp = bsub.add_parser("pool", help="motoneuron pools of N units on 1 and 2 MPI ranks: wall time, peak memory")
    bp.add_argument("--units", default=None, help="pool sizes, comma separated (default 50,100; --full "
                                                  "100,200,400,800)")
    bp.add_argument("--ranks", default="1,2", help="MPI rank counts, comma separated")
    bp.add_argument("--duration-ms", type=float, default=None, help="simulated time (default 1000; --full 5000)")
    bp.add_argument("--dt-ms", type=float, default=DEFAULT_DT_MS,
                    help="the membrane's fixed step (ms; default 1/30 under Crank-Nicolson, a quarter of backward "
                         "Euler's pool force error at 0.025: docs/validation/speed.md)")
    bp.add_argument("--muscle", choices=MUSCLE_MODELS, default="fused_fixed",
                    help="muscle model: modules (KimCa, KimAct, KimForce), fused (KimUnit: the same numbers) or "
                         "fused_fixed (KimUnitFixed: KimUnit's numbers at a lower cost, the fixed step only)")
    bp.add_argument("--substeps", type=int, default=None,
                    help="with a fused muscle: the muscle advances every k membrane steps (step k dt; default: "
                         "every 0.2 ms, k = round(0.2 / dt), and 1 with --muscle modules)")
    bp.add_argument("--channels", choices=CHANNELS, default="fused_fixed",
                    help="motoneuron channels: fused (mn_soma + mn_pic, tabulated), fused_fixed (mn_soma_fixed + "
                         "mn_pic_fixed: the same, cheaper, the fixed step only) or separate (the reference)")
    bp.add_argument("--pic-substeps", type=int, default=None,
                    help="with fused channels: the PIC's gate (time constant 60 ms) advances every k membrane steps "
                         "(default: as the muscle, every 0.2 ms)")
    bp.add_argument("--nthread", type=int, default=1, help="NEURON threads per rank")
    bp.add_argument("--drive", choices=("synaptic", "ramp", "poisson"), default="synaptic",
                    help="synaptic: common synaptic conductance rising over the run (to 1.0 uS with the human "
                         "motoneurons, 0.6 with the default ones: every unit's median rate within the recorded human "
                         "range); ramp: common current to 20 nA (about 150 Hz); poisson: independent Poisson input")
    bp.add_argument("--motoneurons", choices=tuple(PROFILES), default="human",
                    help=f"the reduced cells' profile ({describe_profiles()})")
    bp.add_argument("--engines", default="neuron",
                    help="engines, comma separated: neuron, coreneuron (both: their results compared)")
    bp.add_argument("--cell-permute", type=int, choices=(0, 1), default=1,
                    help="CoreNEURON's layout: 1 interleaves the cells' compartments (bit-identical, faster)")
    bp.add_argument("--secondorder", type=int, choices=(0, 1, 2), default=2,
                    help="NEURON's fixed-step scheme for the membrane: 0 backward Euler, 2 Crank-Nicolson (second "
                         "order, the default: its errors in docs/validation/speed.md)")
    bp.add_argument("--full", action="store_true", help="N = 100..800, 5 s (about half an hour on 2 cores)")
    bp.add_argument("--json", action="store_true")
    bp.set_defaults(func=run_pool)


def _int_list(flag: str, text: str) -> list[int]:
    try:
        return [int(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"{flag} must be integers separated by commas, got {text!r}") from None


def run_pool(args: argparse.Namespace) -> int:
    from ..bench.pool import (DEFAULT_DURATION_MS, DEFAULT_UNITS, FULL_DURATION_MS, FULL_UNITS, bench_pool,
                              table_lines)
    from ..validate import positive_number

    units = _int_list("--units", args.units) if args.units else list(FULL_UNITS if args.full else DEFAULT_UNITS)
    duration = args.duration_ms if args.duration_ms is not None else (
        FULL_DURATION_MS if args.full else DEFAULT_DURATION_MS)
    positive_number("--duration-ms", duration)
    positive_number("--dt-ms", args.dt_ms)
    res = bench_pool(units, _int_list("--ranks", args.ranks), duration, args.dt_ms, args.drive, args.full,
                     progress=True, muscle=args.muscle, substeps=args.substeps, nthread=args.nthread,
                     channels=args.channels, engines=[e.strip() for e in args.engines.split(",") if e.strip()],
                     cell_permute=args.cell_permute, secondorder=args.secondorder, pic_substeps=args.pic_substeps,
                     motoneurons=args.motoneurons)
    print(json.dumps(res, indent=1) if args.json else "\n".join(table_lines(res)))
    return 0


def run_diagnose(args: argparse.Namespace) -> int:
    from ..bench.diagnose import bench_diagnose
    from ..synth.worlds import world

    if args.workers < 1:
        raise InputError(f"--workers must be >= 1, got {args.workers}")
    if args.score is not None:
        suite_only = [f for f, given in (("--suite", args.suite is not None), ("--causes", args.causes is not None),
                                         ("--journal", args.journal is not None), ("--first", args.first != 1),
                                         ("--two-effect", bool(args.two_effect)), ("--reach", args.reach),
                                         ("--separability", args.separability)) if given]
        if suite_only:
            raise InputError(f"--score reads journals; it takes no {', '.join(suite_only)}")
        from ..bench.diagnose_suite import score_journals, table_lines

        res = score_journals(args.score)
        print(json.dumps(res, indent=2) if args.json else "\n".join(table_lines(res)))
        return 0
    if args.suite is not None:
        from ..bench.diagnose_suite import run_suite, suite_cases, table_lines

        causes = [c.strip() for c in args.causes.split(",") if c.strip()] if args.causes else None
        worlds = [w.strip() for w in args.worlds.split(",") if w.strip()]
        for w in worlds:
            world(w)
        suite_cases(args.suite, causes, args.seed, worlds, args.two_effect)  # bad input refused before any work
        if args.separability:
            from ..bench.separability import run_separability
            from ..bench.separability import table_lines as separability_lines

            rows = run_separability(args.suite, causes=causes, seed=args.seed, workers=args.workers,
                                    first=args.first, journal=args.journal, worlds=worlds)
            print(json.dumps([s.to_json() for s in rows], indent=2) if args.json else
                  "\n".join(separability_lines(rows)))
            return 0
        res = run_suite(args.suite, causes=causes, seed=args.seed, workers=args.workers, worlds=worlds,
                        two_effect=args.two_effect, progress=True, journal=args.journal, first=args.first,
                        reach=args.reach)
        print(json.dumps(res, indent=2) if args.json else "\n".join(table_lines(res)))
        return 0
    if args.causes is not None or args.journal is not None or args.first != 1 or args.separability or \
            args.two_effect or args.reach:
        raise InputError("--causes, --journal, --first, --two-effect, --reach and --separability need --suite")
    world(args.world)  # an unknown world refused before any work
    if args.cause is not None:
        from ..synth.dataset import hidden_effects

        hidden_effects(args.cause, args.strength)
    _print(bench_diagnose(args.workers, args.world, args.cause, args.strength), args.json)
    return 0


def run_sweep(args: argparse.Namespace) -> int:
    from ..bench.sweep import SweepSettings, sweep
    from ..bench.sweep_summary import markdown
    from ..reports.outdir import refuse_existing_file, write_text
    from ..validate import positive_number

    out = refuse_existing_file(args.out, args.overwrite) if args.out else None  # before the run
    if args.draws < 1 or args.workers < 1:
        raise InputError(f"--draws and --workers must be >= 1, got {args.draws} and {args.workers}")
    limits = {name: positive_number(f"--{name.replace('_', '-')}", getattr(args, name))
              for name in ("steps_per_ms", "run_budget_s", "draw_timeout_s") if getattr(args, name) is not None}
    settings = SweepSettings(n_draws=args.draws, seed=args.seed, base=args.params, short=args.short, **limits)
    report = sweep(settings, workers=args.workers, progress=not args.quiet, journal=args.journal)
    if out is not None:
        write_text(out, json.dumps(report, indent=1) + "\n")
    if args.json:
        _print(report["summary"], True)
    else:
        print("\n".join(markdown(report["summary"])))
    return 1 if report["summary"]["failures"] else 0


def _print(res: dict, as_json: bool) -> None:
    if as_json:
        print(json.dumps(res, indent=2))
    else:
        for k, v in res.items():
            print(f"{k:45s} {v}")


def run(args: argparse.Namespace) -> int:
    from ..parameters import load_parameters

    params = load_parameters(args.params)
    if args.what == "intervals":
        from ..bench.intervals import coverage_lines, coverage_study
        from ..measured.example import TRUE_VALUES

        draws = args.draws if args.draws is not None else (40 if args.full else 8)
        if draws < 2 or args.workers < 1:
            raise InputError(f"--draws must be >= 2 and --workers >= 1, got {draws} and {args.workers}")
        res = coverage_study(params, TRUE_VALUES, draws=draws, workers=args.workers, noise_N=args.noise_n,
                             tau_ms=args.tau_ms, seed=args.seed, objective=args.objective, data=args.data)
        if not args.per_draw:
            res.pop("per_draw")
        print(json.dumps(res, indent=1) if args.json else "\n".join(coverage_lines(res)))
        return 0
    if args.what == "fit":
        from ..bench.fit import bench_fit

        res = bench_fit(params)
    else:
        from ..bench.unit import bench_unit

        duration = args.duration_ms if args.duration_ms is not None else (10_000.0 if args.full else 3000.0)
        repeats = args.repeats if args.repeats is not None else (3 if args.full else 2)
        res = bench_unit(params, duration_ms=duration, repeats=repeats, pool_units=args.pool_units,
                         full=args.full)
    _print(res, args.json)
    return 0
