"""Run one pool on any number of MPI ranks; rank 0 writes the result (HDF5) and prints a JSON report.

    mpiexec -n 2 python -m neuromuscle.pool.run_mpi --units 6 --duration-ms 300 --drive poisson --out pool.h5
    python -m neuromuscle.pool.run_mpi --units 6 --duration-ms 300 --drive synaptic --json     # one rank

The units are placed round robin (gid % ranks); every rank simulates its own, spikes cross ranks by
ParallelContext's exchange every ``min(axon delay)``, forces and spikes are gathered to every rank, and only rank
0 writes.  Bad input (more ranks than units, an existing --out without --overwrite, impossible values) stops every
rank before anything is built or written, with one message and exit code 2.

``--engine coreneuron`` integrates in CoreNEURON (fixed step; its mechanisms compile on first use), its cells'
compartments interleaved (``--cell-permute 1``, bit-identical to NEURON's order 0).

The JSON report: n_units, ranks, duration_ms, dt_ms, method, secondorder, engine, cell_permute, drive, startup_s
(interpreter, NEURON, mechanisms), build_s (cells, units, drive), sim_s (integration, slowest rank), wall_s (build +
integration + gathering), s_per_unit_s (sim_s per simulated unit-second), spikes (motoneuron spikes, all units),
mean_rate_hz (spikes per unit-second), max_rate_hz and min_rate_hz (the largest and smallest of the units' rates at
the end of the run, each from its last three interspike intervals), recruited (how many units fired more than three
spikes), peak_rss_mib (largest rank) and peak_rss_mib_per_rank, pool_force_peak_N, the units' discharges
(``discharge_summary``: median rates, paired-unit Delta F when the drive falls back, interspike-interval variation
while it is held at its peak), and ``out`` when a file was written. Drives: ``synaptic`` (a common synaptic
conductance rising linearly to --synaptic-peak-us over the run: every unit recruited, rates within those of human
motor units), ``ramp`` (a common current to --ramp-peak-na; at the default 40 nA the largest cells end near 190 Hz,
at 20 nA within 20-40 Hz), ``poisson`` (independent Poisson excitation). Units: s, ms, MiB, N, uS, nA, Hz. """

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from dataclasses import dataclass
from typing import Any, Callable, Sequence

from ..sim.simulator import ENGINES
from .definition import MUSCLE_MODELS
from .motoneuron import CHANNELS, PROFILES, motoneuron_profile
from .mpi import finish_mpi

_START = time.perf_counter()


@dataclass(frozen=True)
class PoolRun:
    """What to run: a PoolDefinition's size and spread, the drive and the integrator.  Units: ms, Hz, uS, nA, N."""

    n_units: int = 6
    params: str = "CT09"
    duration_ms: float = 300.0
    dt_ms: float = 0.025
    method: str = "fixed"
    atol: float = 1e-3
    local_dt: bool = False
    drive: str = "poisson"
    rate_hz: float = 400.0
    weight_uS: float = 0.15
    seed: int = 0
    ramp_peak_nA: float = 40.0
    synaptic_peak_uS: float = 0.6
    smallest_p0_N: float = 0.2
    p0_range: float = 20.0
    length_mm: float = -8.0
    record_dt_ms: float = 1.0
    muscle: str = "modules"
    substeps: int = 1
    nthread: int = 1
    channels: str = "fused"
    engine: str = "neuron"
    cell_permute: int = 1
    secondorder: int = 0
    pic_substeps: int = 1
    motoneurons: str = "default"
    synaptic_noise_uS: float = 0.0


def parser() -> argparse.ArgumentParser:
    """Command-line arguments (one per PoolRun field, plus --out, --overwrite, --json)."""
    d = PoolRun()
    ap = argparse.ArgumentParser(prog="python -m neuromuscle.pool.run_mpi", description=__doc__.split("\n")[0])
    ap.add_argument("--units", type=int, default=d.n_units, help="motor units (gids 0..N-1)")
    ap.add_argument("--params", default=d.params, help="base muscle parameter set")
    ap.add_argument("--duration-ms", type=float, default=d.duration_ms)
    ap.add_argument("--dt-ms", type=float, default=d.dt_ms, help="fixed step (ms)")
    ap.add_argument("--method", choices=("fixed", "cvode"), default=d.method)
    ap.add_argument("--atol", type=float, default=d.atol, help="CVODE absolute tolerance")
    ap.add_argument("--local-dt", action="store_true",
                    help="with --method cvode: NEURON's local variable time step, each unit on its own section")
    ap.add_argument("--drive", choices=("poisson", "ramp", "synaptic"), default=d.drive,
                    help="poisson: independent Poisson excitation per motoneuron; ramp: common current 0 -> "
                         "--ramp-peak-na over the run; synaptic: common synaptic conductance 0 -> "
                         "--synaptic-peak-us over the run")
    ap.add_argument("--rate-hz", type=float, default=d.rate_hz, help="Poisson rate per motoneuron (Hz)")
    ap.add_argument("--weight-us", type=float, default=d.weight_uS, help="Poisson synaptic weight (uS)")
    ap.add_argument("--seed", type=int, default=d.seed, help="Poisson seed (Random123 stream seed, gid)")
    ap.add_argument("--ramp-peak-na", type=float, default=d.ramp_peak_nA)
    ap.add_argument("--synaptic-peak-us", type=float, default=d.synaptic_peak_uS,
                    help="peak of the synaptic drive (uS, each cell's total conductance)")
    ap.add_argument("--smallest-p0-n", type=float, default=d.smallest_p0_N)
    ap.add_argument("--p0-range", type=float, default=d.p0_range)
    ap.add_argument("--length-mm", type=float, default=d.length_mm)
    ap.add_argument("--record-dt-ms", type=float, default=d.record_dt_ms)
    ap.add_argument("--muscle", choices=MUSCLE_MODELS, default=d.muscle,
                    help="modules: KimCa, KimAct, KimForce per unit; fused: one KimUnit per unit (same numbers); "
                         "fused_fixed: one KimUnitFixed per unit (KimUnit's numbers, the fixed step only)")
    ap.add_argument("--substeps", type=int, default=d.substeps,
                    help="with a fused muscle: the muscle advances every k membrane steps (step k dt)")
    ap.add_argument("--pic-substeps", type=int, default=d.pic_substeps,
                    help="with fused channels: the PIC's gate (time constant 60 ms) advances every k membrane steps")
    ap.add_argument("--nthread", type=int, default=d.nthread, help="NEURON threads per rank")
    ap.add_argument("--motoneurons", choices=tuple(PROFILES), default=d.motoneurons,
                    help="the reduced cells' profile (neuromuscle.pool.motoneuron.PROFILES)")
    ap.add_argument("--synaptic-noise-us", type=float, default=d.synaptic_noise_uS,
                    help="each cell's own synaptic noise (uS at a drive of 1 uS; --drive synaptic and the fixed step)")
    ap.add_argument("--channels", choices=CHANNELS, default=d.channels,
                    help="motoneuron channels: fused (mn_soma + mn_pic), fused_fixed (mn_soma_fixed + mn_pic_fixed, "
                         "the fixed step only) or separate (one mechanism each)")
    ap.add_argument("--engine", choices=ENGINES, default=d.engine,
                    help="neuron, or coreneuron (NEURON's compute engine; fixed step only)")
    ap.add_argument("--cell-permute", type=int, choices=(0, 1), default=d.cell_permute,
                    help="with --engine coreneuron: 1 interleaves the cells' compartments (bit-identical, faster), "
                         "0 keeps NEURON's order")
    ap.add_argument("--secondorder", type=int, choices=(0, 1, 2), default=d.secondorder,
                    help="NEURON's fixed-step scheme for the membrane: 0 backward Euler, 2 Crank-Nicolson (the "
                         "muscle gives the same numbers under each)")
    ap.add_argument("--out", default=None, help="HDF5 result (written by rank 0)")
    ap.add_argument("--overwrite", action="store_true")
    ap.add_argument("--json", action="store_true", help="print the JSON report (rank 0)")
    return ap


def _config(args: argparse.Namespace) -> PoolRun:
    return PoolRun(n_units=args.units, params=args.params, duration_ms=args.duration_ms, dt_ms=args.dt_ms,
                   method=args.method, atol=args.atol, local_dt=args.local_dt, drive=args.drive,
                   rate_hz=args.rate_hz, weight_uS=args.weight_us, seed=args.seed, ramp_peak_nA=args.ramp_peak_na,
                   synaptic_peak_uS=args.synaptic_peak_us,
                   smallest_p0_N=args.smallest_p0_n, p0_range=args.p0_range, length_mm=args.length_mm,
                   record_dt_ms=args.record_dt_ms, muscle=args.muscle, substeps=args.substeps,
                   nthread=args.nthread, channels=args.channels, engine=args.engine,
                   cell_permute=args.cell_permute, secondorder=args.secondorder, pic_substeps=args.pic_substeps,
                   motoneurons=args.motoneurons, synaptic_noise_uS=args.synaptic_noise_us)


def peak_rss_mib() -> float:
    """This process's peak resident memory (MiB; Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run_pool(cfg: PoolRun, nhost: int = 1) -> tuple[Any, dict[str, Any]]:
    """Build and run the pool described by ``cfg`` on this rank (MPI started by the caller); returns the gathered
    PoolResult (on every rank) and the timing report.  Raises InputError before building anything when
    there are more ranks (``nhost``) than units, or synaptic noise without the fixed step and the synaptic drive."""
    from ..errors import InputError
    from ..parameters import load_parameters
    from ..sim import Simulator
    from .definition import PoolDefinition
    from .drives import Drive

    if nhost > cfg.n_units:
        raise InputError(f"{nhost} MPI ranks for a pool of {cfg.n_units} units: use at most one rank per unit")
    definition = PoolDefinition(cfg.n_units, load_parameters(cfg.params), smallest_p0_N=cfg.smallest_p0_N,
                                p0_range=cfg.p0_range, muscle_model=cfg.muscle, muscle_substeps=cfg.substeps,
                                motoneuron_channels=cfg.channels, pic_substeps=cfg.pic_substeps,
                                **{**motoneuron_profile(cfg.motoneurons).pool_options(),
                                   "synaptic_noise_uS": cfg.synaptic_noise_uS})
    if cfg.synaptic_noise_uS > 0.0 and (cfg.method != "fixed" or cfg.drive != "synaptic"):
        raise InputError("--synaptic-noise-us needs --method fixed and --drive synaptic (the noise rides on the common "
                         "synaptic drive and is drawn at fixed intervals of the fixed step)")
    sim = Simulator(method=cfg.method, dt_ms=cfg.dt_ms, atol=cfg.atol, v_init_mV=-70.0, max_wall_s=None,
                    local_dt=cfg.local_dt, nthread=cfg.nthread, label=f"pool of {cfg.n_units} units",
                    engine=cfg.engine, cell_permute=cfg.cell_permute, secondorder=cfg.secondorder)
    if cfg.drive == "poisson":
        drive = Drive("poisson", rate_hz=cfg.rate_hz, weight_uS=cfg.weight_uS, seed=cfg.seed)
    elif cfg.drive == "synaptic":
        drive = Drive.rise("synaptic", cfg.synaptic_peak_uS, cfg.duration_ms)
    else:
        drive = Drive.rise("current", cfg.ramp_peak_nA, cfg.duration_ms)
    result, report = run_definition(definition, drive, sim, cfg.duration_ms, nhost, length=cfg.length_mm,
                                    record_dt_ms=cfg.record_dt_ms)
    report.update({"muscle": cfg.muscle, "substeps": cfg.substeps, "nthread": cfg.nthread,
                   "channels": cfg.channels, "drive": cfg.drive, "motoneurons": cfg.motoneurons,
                   "synaptic_noise_uS": cfg.synaptic_noise_uS})
    return result, report


def run_definition(definition: Any, drive: Any, sim: Any, duration_ms: float, nhost: int = 1, *,
                   length: Any = -8.0, record_dt_ms: float = 1.0, recordings: tuple[Any, Any] | None = None,
                   progress: Callable[[float], None] | None = None, cells: Any = None,
                   reflex: Any = None) -> tuple[Any, dict[str, Any]]:
    """Build the pool of ``definition`` on this rank, give it ``drive`` (a pool.drives.Drive), record
    ``recordings`` ((variable names, unit indices): ``Pool.record``), run it for ``duration_ms`` (ms) with the
    Simulator ``sim`` and gather the PoolResult on every rank; ``progress(t_ms)`` is called as the run advances
    (fixed step); ``cells``: the motoneurons' factory (``pool.cells``; None: the reduced cells); ``reflex``: a
    ReflexDefinition whose afferents are attached before the drive (None: none), their spike counts and mean
    rates (Hz) by kind reported as ``afferents``.  Returns the result and the timing report (module docstring;
    units s, ms, MiB, N, Hz)."""
    from ..errors import InputError
    from ..model.mechanisms import coreneuron_library, load_mechanisms
    from .pool import Pool, parallel_context
    from .reflex import attach_reflex

    if nhost > definition.n_units:
        raise InputError(f"{nhost} MPI ranks for a pool of {definition.n_units} units: use at most one rank per unit")
    definition.units()
    load_mechanisms()
    if sim.engine == "coreneuron":
        coreneuron_library()  # compiled (or found) before the clock starts
    pc = parallel_context()
    pc.barrier()
    startup = time.perf_counter() - _START
    t0 = time.perf_counter()
    afferents = None
    with Pool(definition, length=length, per_unit_section=sim.local_dt, engine=sim.engine, cells=cells) as pool:
        loop = attach_reflex(pool, reflex) if reflex is not None else None
        drive.apply(pool)
        if recordings is not None:
            pool.record(*recordings)
        build = max(pc.py_allgather(time.perf_counter() - t0))
        result = pool.run(duration_ms, sim, record_dt_ms=record_dt_ms, progress=progress)
        if loop is not None:
            trains = loop.spikes()
            afferents = {kind: {"afferents": len(s), "spikes": int(sum(x.size for x in s)),
                                "mean_rate_hz": round(float(sum(x.size for x in s)) / len(s) * 1000.0 / duration_ms, 2)
                                if s else 0.0} for kind, s in trains.items()}
            loop.destroy()
    wall = time.perf_counter() - t0
    rss = [float(x) for x in pc.py_allgather(peak_rss_mib())]
    n = definition.n_units
    unit_s = n * duration_ms / 1000.0
    spikes = int(sum(s.size for s in result.spikes_ms))
    final = final_rates_hz(result.spikes_ms)
    report = {"n_units": n, "ranks": nhost, "duration_ms": duration_ms,
              "dt_ms": sim.dt_ms if sim.method == "fixed" else None, "method": sim.method,
              "secondorder": sim.secondorder, "engine": sim.engine,
              "cell_permute": sim.cell_permute if sim.engine == "coreneuron" else None,
              "muscle": definition.muscle_model, "substeps": int(definition.muscle_substeps),
              "pic_substeps": int(definition.pic_substeps),
              "nthread": sim.nthread, "channels": definition.motoneuron_channels, "local_dt": sim.local_dt,
              "drive": drive.kind, "startup_s": startup, "build_s": build, "sim_s": result.wall_s, "wall_s": wall,
              "s_per_unit_s": result.wall_s / unit_s, "spikes": spikes, "mean_rate_hz": spikes / unit_s,
              "max_rate_hz": float(final.max()) if final.size else 0.0,
              "min_rate_hz": float(final.min()) if final.size else 0.0, "recruited": int(final.size),
              **discharge_summary(result.spikes_ms, drive),
              "peak_rss_mib": max(rss), "peak_rss_mib_per_rank": rss,
              "pool_force_peak_N": float(result.pool_force_N.max())}
    if afferents is not None:
        report["afferents"] = afferents
    return result, report


def median_rates(spikes_ms: Sequence[Any]) -> dict[str, Any]:
    """The units' median instantaneous rates (Hz; ``discharge_stats.unit_rates``): their 5th, 50th and 95th
    percentiles over the units that fired twice or more, and the share of those units whose median lies within the
    range of recorded human units (``discharge_stats.HUMAN_MEDIAN_RATES_HZ``)."""
    import numpy as np

    from .discharge_stats import inside_human_range, unit_rates

    rates = unit_rates([s for s in spikes_ms if len(s) > 1])
    m = rates.median_hz[np.isfinite(rates.median_hz)]
    return {"median_rates_p5_p50_p95_hz": [float(x) for x in np.percentile(m, [5, 50, 95])] if m.size else None,
            "medians_inside_human_range": inside_human_range(rates) if m.size else None}


#: References per test unit in a run's Delta F: the ones recruited closest before it (all of them in a pool of up to
#: 21 units); the cost then grows with the units, not with their square (10-20 ms a unit for a 20-s run).
DELTA_F_REFERENCES = 20


def discharge_summary(spikes_ms: Sequence[Any], drive: Any) -> dict[str, Any]:
    """``median_rates``, and what a motor-unit physiologist reads next on a run with ``drive`` (a
    pool.drives.Drive): the paired-unit Delta F (``discharge_stats.delta_f`` against up to DELTA_F_REFERENCES
    references a test unit: median and quartiles in Hz, test units, pairs) when the drive falls back after rising
    (None otherwise), and the interspike-interval coefficients of variation (1) while it is held at its peak
    (``discharge_stats.isi_cv``: 5th, 50th and 95th percentiles over the units; None when it is never held or no
    unit has enough intervals there).  ``spikes_ms``: each unit's discharge times (ms)."""
    import numpy as np

    from .discharge_stats import delta_f, isi_cv

    trains = [np.asarray(s, float) for s in spikes_ms]
    out = median_rates(trains)
    df = delta_f(trains, DELTA_F_REFERENCES).summary() if drive.falls_back() else None
    out["delta_f"] = df if df is None or df["pairs"] else {**df, "median_hz": None}     # no pair: no value
    held = drive.held_at_peak_ms()
    cv = isi_cv(trains, held) if held is not None else np.array([])
    cv = cv[np.isfinite(cv)]
    out["isi_cv_p5_p50_p95"] = [float(x) for x in np.percentile(cv, [5, 50, 95])] if cv.size else None
    return out


def final_rates_hz(spikes_ms: Sequence[Any], intervals: int = 3) -> Any:
    """Each unit's discharge rate at the end of the run (Hz): ``intervals`` over the time (ms) its last
    ``intervals`` interspike intervals span, for the units with more than ``intervals`` spikes (an array)."""
    import numpy as np

    return np.array([1000.0 * intervals / (s[-1] - s[-1 - intervals]) for s in spikes_ms if len(s) > intervals])


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point (every rank runs it); exit code 0, or 2 on bad input (one message, from rank 0)."""
    args = parser().parse_args(argv)
    from ..errors import NeuromuscleError
    from ..reports.outdir import refuse_existing_file
    from .mpi import init_mpi

    rank = 0
    try:
        rank, nhost = init_mpi()
        out = refuse_existing_file(args.out, args.overwrite) if args.out else None  # every rank: same answer
        result, report = run_pool(_config(args), nhost)
    except NeuromuscleError as exc:
        if rank == 0:
            print(f"neuromuscle: error: {exc}", file=sys.stderr, flush=True)
        return 2
    if rank == 0:
        if out is not None:
            result.save(out, overwrite=args.overwrite)
            report["out"] = str(out)
        if args.json:
            print(json.dumps(report, indent=1), flush=True)
    return 0


if __name__ == "__main__":
    finish_mpi(main())
