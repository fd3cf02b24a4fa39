"""``neuromuscle bench pool``: wall time and peak memory of motoneuron pools of N units on 1 and 2 MPI ranks.

Each configuration runs in fresh processes (``python -m neuromuscle.pool.run_mpi --json``, under ``mpiexec -n R``
for R > 1), so its memory is its own: ``peak_rss_mib`` is the largest rank's peak resident memory, as the ranks
report it themselves.  The machine's 1-minute load average is recorded before and after each run: on a shared
machine it says how much the wall time can be trusted.  Units: s, MiB, ms.

Engines: each configuration runs under every engine asked for (``engines``: NEURON, CoreNEURON); the per-cell-step
cost (ns per motoneuron-and-muscle-unit step, per core) puts engines, sizes and rank counts side by side, and when
both engines ran a configuration their results are compared (``agreement``: spikes, pool force).

The machine's limit: before and after the runs the same host times the motoneuron's fixed-step arithmetic as one
scalar C loop (``machine_limit``; ``machine_limit_ns``), and each run's cost per cell-step is also given as a
multiple of it (``times_machine_limit``): on a shared host whose speed changes from hour to hour, that multiple
compares across days where the wall time does not.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import InputError, NeuromuscleError
from ..pool.mpi import mpi_available, mpiexec_command
from .machine_limit import PROBE, probe_ns
from ..pool.definition import FUSED_MUSCLE_MODELS, MUSCLE_MODELS
from ..pool.motoneuron import CHANNELS, FUSED_CHANNELS, PROFILES
from ..sim.simulator import ENGINES

#: Default run (about two minutes on two cores) and --full (N = 100 to 800).
DEFAULT_UNITS = (50, 100)
DEFAULT_DURATION_MS = 1000.0
FULL_UNITS = (100, 200, 400, 800)
FULL_DURATION_MS = 5000.0
RANKS = (1, 2)

#: Drives (``bench_pool``) and the synaptic drive's peak (uS, each cell's total conductance) for each motoneuron
#: profile (``pool.motoneuron.PROFILES``): the drive that recruits every unit of a 50-unit pool in 1 s with every
#: unit's median rate within the range of recorded human units (``discharge_stats.HUMAN_MEDIAN_RATES_HZ``).
DRIVES = ("synaptic", "ramp", "poisson")
SYNAPTIC_PEAK_US = {"default": 0.6, "human": 1.0}

#: The fused muscle's step (ms) when ``substeps`` is not given: every round(MUSCLE_STEP_MS / dt) membrane steps;
#: the fused channels' PIC gate likewise.
MUSCLE_STEP_MS = 0.2
#: The membrane's step (ms) by default, under Crank-Nicolson (``secondorder`` 2): a quarter of backward Euler's pool
#: force error at 0.025 ms against a fine reference, and a whole number of steps in the 1 ms force recording and the
#: 0.2 ms muscle step (docs/validation/speed.md, the avenues table; from 0.04 ms Crank-Nicolson's spikes begin to
#: fail to repolarise).
DEFAULT_DT_MS = 1.0 / 30.0

#: Keys every run's report carries (besides its configuration).
RUN_KEYS = ("n_units", "ranks", "wall_s", "peak_rss_mib", "build_s", "sim_s", "s_per_unit_s", "spikes",
            "mean_rate_hz", "max_rate_hz", "peak_rss_mib_per_rank", "startup_s", "load_1min_before",
            "load_1min_after", "engine", "ns_per_cell_step_per_core")


def _load() -> float:
    return float(os.getloadavg()[0])


def run_one(n_units: int, ranks: int, duration_ms: float, dt_ms: float, drive: str,
            extra: Sequence[str] = (), timeout_s: float = 3600.0, out: Path | None = None) -> dict[str, Any]:
    """One pool run of n_units on ``ranks`` MPI ranks (fresh processes); its report (run_mpi's JSON plus the
    load average before and after, and the cost per cell-step: ns of integration per motoneuron-and-muscle-unit
    step, per core).  ``out``: where run_mpi writes the result (HDF5).  Raises NeuromuscleError when the run
    fails."""
    args = ["-m", "neuromuscle.pool.run_mpi", "--json", "--units", str(n_units), "--duration-ms", str(duration_ms),
            "--dt-ms", str(dt_ms), "--drive", drive, *extra]
    if out is not None:
        args += ["--out", str(out), "--overwrite"]
    cmd = mpiexec_command(ranks, args) if ranks > 1 else [sys.executable, *args]
    # one core a rank: numpy's BLAS threads, idle-spinning beside the ranks, would take cores from them
    env = {**os.environ, **{k: os.environ.get(k, "1") for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}}
    before = _load()
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s, env=env)
    if proc.returncode != 0:
        raise NeuromuscleError(f"pool of {n_units} units on {ranks} ranks failed (exit {proc.returncode}): "
                               f"{proc.stderr.strip()[-1500:]}")
    report = json.loads(proc.stdout[proc.stdout.index("{"):])
    report["process_s"] = time.perf_counter() - start
    report["load_1min_before"], report["load_1min_after"] = before, _load()
    report.setdefault("engine", "neuron")
    report["ns_per_cell_step_per_core"] = cell_step_ns(report["sim_s"], ranks, n_units, duration_ms, dt_ms)
    return report


def cell_step_ns(sim_s: float, ranks: int, n_units: int, duration_ms: float, dt_ms: float) -> float:
    """Integration cost (ns) of one step of one cell (a motoneuron and its muscle unit) on one core: sim_s (s) of
    ``ranks`` cores spent on n_units cells over duration_ms / dt_ms steps."""
    return sim_s * ranks / (n_units * duration_ms / dt_ms) * 1e9


def agreement(a: Any, b: Any) -> dict[str, Any]:
    """How two results of the same pool differ (PoolResult a, b): spike counts and times (ms) unit by unit, and
    the pool force (its largest difference relative to a's peak)."""
    counts = [int(y.size) - int(x.size) for x, y in zip(a.spikes_ms, b.spikes_ms)]
    shifts = [float(np.max(np.abs(x - y))) for x, y in zip(a.spikes_ms, b.spikes_ms) if x.size == y.size and x.size]
    peak = float(a.pool_force_N.max())
    return {"spikes": int(sum(x.size for x in a.spikes_ms)),
            "spikes_identical": all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms)),
            "units_with_other_spike_count": int(sum(c != 0 for c in counts)),
            "max_spike_shift_ms": max(shifts, default=0.0),
            "forces_identical": bool(np.array_equal(a.unit_force_N, b.unit_force_N)),
            "pool_force_max_diff_of_peak": float(np.max(np.abs(a.pool_force_N - b.pool_force_N)) / peak)
            if peak > 0 else 0.0}


def bench_pool(units: Sequence[int] = DEFAULT_UNITS, ranks: Sequence[int] = RANKS,
               duration_ms: float = DEFAULT_DURATION_MS, dt_ms: float = DEFAULT_DT_MS, drive: str = "synaptic",
               full: bool = False, progress: bool = False, muscle: str = "fused_fixed", substeps: int | None = None,
               nthread: int = 1, channels: str = "fused_fixed", engines: Sequence[str] = ("neuron",),
               cell_permute: int = 1, secondorder: int = 2, pic_substeps: int | None = None,
               motoneurons: str = "human") -> dict[str, Any]:
    """Run every (N, ranks) pair and return {"runs": [report, ...], "skipped": [...], settings}; a rank count
    that cannot run here (no MPI) is listed under "skipped" with the reason.  The drive is a common synaptic
    conductance rising to the profile's SYNAPTIC_PEAK_US over the run ("synaptic", the default: every unit
    recruited, each unit's median rate within the range of recorded human units; ``median_rates_p5_p50_p95_hz``,
    ``medians_inside_human_range``, ``mean_rate_hz`` and ``max_rate_hz`` in each report), a common current ramp
    0 -> 20 nA ("ramp": the same recruitment by a current, about 150 Hz) or
    independent Poisson input ("poisson").  ``muscle``: "modules" (KimCa, KimAct, KimForce), "fused"
    (KimUnit) or "fused_fixed" (KimUnitFixed, the default); ``substeps`` k: the fused muscle advances every k
    membrane steps (None: every MUSCLE_STEP_MS, k = round(0.2 ms / dt)); ``pic_substeps``: the fused channels'
    PIC gate likewise (None: as the muscle's, 1 with the separate channels); ``nthread``: NEURON threads per
    rank; ``channels``: the motoneurons' ("fused_fixed", the default, "fused" or "separate").  The defaults are
    the fast path: Crank-Nicolson at dt 1/30 ms (DEFAULT_DT_MS), the fused channels with their PIC gate and the
    fused muscle every 0.2 ms, in their fixed-step forms; the errors of each against the reference are in
    docs/validation/speed.md.  ``engines``: "neuron", "coreneuron" or
    both; with both, "agreement" compares their results of each (N, ranks); ``cell_permute``: CoreNEURON's
    layout (1: compartments interleaved, bit-identical to 0 and faster); ``secondorder``: NEURON's fixed-step
    scheme for the membrane (0 backward Euler, 2 Crank-Nicolson); ``motoneurons``: the cells' profile
    (``pool.motoneuron.PROFILES``: "human", the default, or "default")."""
    if not units or any(isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in units):
        raise InputError(f"pool sizes must be integers >= 1, got {list(units)}")
    if not ranks or any(isinstance(r, bool) or not isinstance(r, int) or r < 1 for r in ranks):
        raise InputError(f"rank counts must be integers >= 1, got {list(ranks)}")
    too_many = [(n, r) for n in units for r in ranks if r > n]
    if too_many:
        raise InputError(f"more ranks than units in {too_many}: use at most one rank per unit")
    if drive not in DRIVES:
        raise InputError(f"drive must be one of {', '.join(DRIVES)}, got {drive!r}")
    if muscle not in MUSCLE_MODELS:
        raise InputError(f"muscle must be one of {', '.join(MUSCLE_MODELS)}, got {muscle!r}")
    if substeps is None:
        substeps = max(1, round(MUSCLE_STEP_MS / dt_ms)) if muscle in FUSED_MUSCLE_MODELS else 1
    if pic_substeps is None:
        pic_substeps = max(1, round(MUSCLE_STEP_MS / dt_ms)) if channels in FUSED_CHANNELS else 1
    if cell_permute not in (0, 1) or isinstance(cell_permute, bool):
        raise InputError(f"cell_permute must be 0 or 1, got {cell_permute!r}")
    for name, k in (("substeps", substeps), ("nthread", nthread), ("pic_substeps", pic_substeps)):
        if isinstance(k, bool) or not isinstance(k, int) or k < 1:
            raise InputError(f"{name} must be an integer >= 1, got {k!r}")
    if substeps > 1 and muscle not in FUSED_MUSCLE_MODELS:
        raise InputError(f"substeps = {substeps} needs muscle='fused' or 'fused_fixed'")
    if secondorder not in (0, 1, 2) or isinstance(secondorder, bool):
        raise InputError(f"secondorder must be 0, 1 or 2, got {secondorder!r}")
    if channels not in CHANNELS:
        raise InputError(f"channels must be one of {', '.join(CHANNELS)}, got {channels!r}")
    if pic_substeps > 1 and channels not in FUSED_CHANNELS:
        raise InputError(f"pic_substeps = {pic_substeps} needs channels='fused' or 'fused_fixed'")
    if motoneurons not in PROFILES:
        raise InputError(f"motoneurons must be one of {', '.join(PROFILES)}, got {motoneurons!r}")
    if not engines or any(e not in ENGINES for e in engines) or len(set(engines)) != len(engines):
        raise InputError(f"engines must be one or more of {', '.join(ENGINES)}, each once, got {list(engines)}")
    extra = {"ramp": ["--ramp-peak-na", "20"],
             "synaptic": ["--synaptic-peak-us", str(SYNAPTIC_PEAK_US[motoneurons])]}.get(drive, [])
    extra += ["--motoneurons", motoneurons, "--muscle", muscle, "--substeps", str(substeps), "--nthread",
              str(nthread), "--channels", channels, "--cell-permute", str(cell_permute), "--secondorder",
              str(secondorder), "--pic-substeps", str(pic_substeps)]
    out: dict[str, Any] = {"duration_ms": duration_ms, "dt_ms": dt_ms, "drive": drive, "full": full,
                           "muscle": muscle, "substeps": substeps, "nthread": nthread, "channels": channels,
                           "cpu_count": os.cpu_count(), "engines": list(engines), "cell_permute": cell_permute,
                           "secondorder": secondorder, "pic_substeps": pic_substeps, "motoneurons": motoneurons,
                           "runs": [], "skipped": []}
    if len(engines) > 1:
        out["agreement"] = []
    from ..pool.result import load_pool_result

    out["machine_limit_ns"] = [probe_ns()]   # the host's speed for the same arithmetic, before and after the runs
    with tempfile.TemporaryDirectory(prefix="neuromuscle-bench-pool.") as tmp:
        for n in units:
            for r in ranks:
                if r > 1 and not mpi_available():
                    out["skipped"].append({"n_units": n, "ranks": r, "reason": "no MPI: install the mpi extra"})
                    continue
                files = {}
                for engine in engines:
                    files[engine] = Path(tmp) / f"{engine}.h5"
                    rep = run_one(n, r, duration_ms, dt_ms, drive, [*extra, "--engine", engine],
                                  out=files[engine] if len(engines) > 1 else None)
                    if progress:
                        print(f"neuromuscle bench pool: N={n} ranks={r} {engine}: wall {rep['wall_s']:.1f} s, "
                              f"peak {rep['peak_rss_mib']:.0f} MiB, load {rep['load_1min_before']:.1f}",
                              file=sys.stderr, flush=True)
                    out["runs"].append(rep)
                if len(engines) > 1:
                    first, *others = (load_pool_result(files[e]) for e in engines)
                    for engine, other in zip(engines[1:], others):
                        out["agreement"].append({"n_units": n, "ranks": r, "engines": [engines[0], engine],
                                                 **agreement(first, other)})
    out["machine_limit_ns"].append(probe_ns())
    limits = [x for x in out["machine_limit_ns"] if x is not None]
    for rep in out["runs"]:
        rep["times_machine_limit"] = rep["ns_per_cell_step_per_core"] / float(np.mean(limits)) if limits else None
    return out


def _times(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.1f}"


def _medians(run: dict[str, Any]) -> str:
    p, share = run.get("median_rates_p5_p50_p95_hz"), run.get("medians_inside_human_range")
    return "n/a" if p is None or share is None else f"{p[0]:.1f}-{p[2]:.1f}, {share:.0%}"


def table_lines(res: dict[str, Any]) -> list[str]:
    """The result as a Markdown table (N x ranks: wall, sim, build, memory, spikes, mean and largest rate, the
    units' median rates, load)."""
    scheme = {0: "backward Euler", 1: "Crank-Nicolson (secondorder 1)", 2: "Crank-Nicolson"}[res.get("secondorder", 0)]
    lines = [f"pools, {res['duration_ms'] / 1000:g} s simulated at dt {res['dt_ms']} ms ({scheme}), {res['drive']} "
             f"drive, muscle {res.get('muscle', 'modules')} (substeps {res.get('substeps', 1)}), motoneuron channels "
             f"{res.get('channels', 'separate')} (PIC gate substeps {res.get('pic_substeps', 1)}), "
             f"{res.get('nthread', 1)} thread(s), {res.get('motoneurons', 'default')} motoneurons"]
    limits = res.get("machine_limit_ns") or []
    if any(x is not None for x in limits):
        lines.append(f"the machine's limit for the motoneuron's arithmetic (its fixed-step update as one scalar C "
                     f"loop, {PROBE['n']} cells, one core): "
                     + " before, ".join("n/a" if x is None else f"{x:.0f} ns per cell-step" for x in limits)
                     + " after the runs")
    lines += ["", "| N | ranks | engine | wall s | sim s | build s | s per unit-s | ns per cell-step per core | "
              "x the limit | peak MiB (largest rank) | spikes | mean / largest rate Hz | unit medians Hz (5-95 %), "
              "share in the human range | load |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res["runs"]:
        lines.append(f"| {r['n_units']} | {r['ranks']} | {r.get('engine', 'neuron')} | {r['wall_s']:.2f} | "
                     f"{r['sim_s']:.2f} | {r['build_s']:.2f} | {r['s_per_unit_s']:.4f} | "
                     f"{r['ns_per_cell_step_per_core']:.0f} | {_times(r.get('times_machine_limit'))} | "
                     f"{r['peak_rss_mib']:.0f} | {r['spikes']} | "
                     f"{r.get('mean_rate_hz', float('nan')):.1f} / {r.get('max_rate_hz', float('nan')):.1f} | "
                     f"{_medians(r)} | {r['load_1min_before']:.1f}-{r['load_1min_after']:.1f} |")
    for s in res["skipped"]:
        lines.append(f"| {s['n_units']} | {s['ranks']} | skipped: {s['reason']} | | | | | | | | | | | |")
    if res.get("agreement"):
        lines += ["", "| N | ranks | engines | spikes | identical spikes | units with another count | largest spike "
                      "shift ms | identical forces | pool force diff / peak |", "|---|---|---|---|---|---|---|---|---|"]
        for a in res["agreement"]:
            lines.append(f"| {a['n_units']} | {a['ranks']} | {' vs '.join(a['engines'])} | {a['spikes']} | "
                         f"{a['spikes_identical']} | {a['units_with_other_spike_count']} | "
                         f"{a['max_spike_shift_ms']:.3g} | {a['forces_identical']} | "
                         f"{a['pool_force_max_diff_of_peak']:.2e} |")
    return lines
