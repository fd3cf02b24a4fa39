"""``neuromuscle bench pool``: wall time and peak memory of motoneuron pools of N units on 1 and 2 MPI ranks.

Each configuration runs in fresh processes (``python -m neuromuscle.pool.run_mpi --json``, under ``mpiexec -n R``
for R > 1), so its memory is its own: ``peak_rss_mib`` is the largest rank's peak resident memory, as the ranks
report it themselves.  The machine's 1-minute load average is recorded before and after each run: on a shared
machine it says how much the wall time can be trusted.  Units: s, MiB, ms.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from typing import Any, Sequence

from ..errors import InputError, NeuromuscleError
from ..pool.mpi import mpi_available, mpiexec_command
from ..pool.motoneuron import CHANNELS

#: Default run (about two minutes on this 2-core machine) and --full (the issue's table).
DEFAULT_UNITS = (50, 100)
DEFAULT_DURATION_MS = 1000.0
FULL_UNITS = (100, 200, 400, 800)
FULL_DURATION_MS = 5000.0
RANKS = (1, 2)

#: Keys every run's report carries (besides its configuration).
RUN_KEYS = ("n_units", "ranks", "wall_s", "peak_rss_mib", "build_s", "sim_s", "s_per_unit_s", "spikes",
            "peak_rss_mib_per_rank", "startup_s", "load_1min_before", "load_1min_after")


def _load() -> float:
    return float(os.getloadavg()[0])


def run_one(n_units: int, ranks: int, duration_ms: float, dt_ms: float, drive: str,
            extra: Sequence[str] = (), timeout_s: float = 3600.0) -> dict[str, Any]:
    """One pool run of n_units on ``ranks`` MPI ranks (fresh processes); its report (run_mpi's JSON plus the
    load average before and after).  Raises NeuromuscleError when the run fails."""
    args = ["-m", "neuromuscle.pool.run_mpi", "--json", "--units", str(n_units), "--duration-ms", str(duration_ms),
            "--dt-ms", str(dt_ms), "--drive", drive, *extra]
    cmd = mpiexec_command(ranks, args) if ranks > 1 else [sys.executable, *args]
    before = _load()
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s)
    if proc.returncode != 0:
        raise NeuromuscleError(f"pool of {n_units} units on {ranks} ranks failed (exit {proc.returncode}): "
                               f"{proc.stderr.strip()[-1500:]}")
    report = json.loads(proc.stdout[proc.stdout.index("{"):])
    report["process_s"] = time.perf_counter() - start
    report["load_1min_before"], report["load_1min_after"] = before, _load()
    return report


def bench_pool(units: Sequence[int] = DEFAULT_UNITS, ranks: Sequence[int] = RANKS,
               duration_ms: float = DEFAULT_DURATION_MS, dt_ms: float = 0.025, drive: str = "ramp",
               full: bool = False, progress: bool = False, muscle: str = "fused", substeps: int = 8,
               nthread: int = 1, channels: str = "fused") -> dict[str, Any]:
    """Run every (N, ranks) pair and return {"runs": [report, ...], "skipped": [...], settings}; a rank count
    that cannot run here (no MPI) is listed under "skipped" with the reason.  The drive is a common current ramp
    0 -> 20 nA over the run ("ramp": recruitment across the pool) or independent Poisson input ("poisson").
    ``muscle``: "modules" (KimCa, KimAct, KimForce) or "fused" (KimUnit); ``substeps`` k: the fused muscle
    advances every k membrane steps; ``nthread``: NEURON threads per rank; ``channels``: the motoneurons'
    ("fused" or "separate").  The defaults are the fast path (fused muscle every 8 steps, fused channels); the
    errors of each against the reference are in the README ("Motoneuron pools", speed)."""
    if not units or any(isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in units):
        raise InputError(f"pool sizes must be integers >= 1, got {list(units)}")
    if not ranks or any(isinstance(r, bool) or not isinstance(r, int) or r < 1 for r in ranks):
        raise InputError(f"rank counts must be integers >= 1, got {list(ranks)}")
    too_many = [(n, r) for n in units for r in ranks if r > n]
    if too_many:
        raise InputError(f"more ranks than units in {too_many}: use at most one rank per unit")
    if drive not in ("ramp", "poisson"):
        raise InputError(f"drive must be 'ramp' or 'poisson', got {drive!r}")
    if muscle not in ("modules", "fused"):
        raise InputError(f"muscle must be 'modules' or 'fused', got {muscle!r}")
    for name, k in (("substeps", substeps), ("nthread", nthread)):
        if isinstance(k, bool) or not isinstance(k, int) or k < 1:
            raise InputError(f"{name} must be an integer >= 1, got {k!r}")
    if substeps > 1 and muscle != "fused":
        raise InputError(f"substeps = {substeps} needs muscle='fused'")
    if channels not in CHANNELS:
        raise InputError(f"channels must be one of {', '.join(CHANNELS)}, got {channels!r}")
    extra = ["--ramp-peak-na", "20"] if drive == "ramp" else []
    extra += ["--muscle", muscle, "--substeps", str(substeps), "--nthread", str(nthread), "--channels", channels]
    out: dict[str, Any] = {"duration_ms": duration_ms, "dt_ms": dt_ms, "drive": drive, "full": full,
                           "muscle": muscle, "substeps": substeps, "nthread": nthread, "channels": channels,
                           "cpu_count": os.cpu_count(), "runs": [], "skipped": []}
    for n in units:
        for r in ranks:
            if r > 1 and not mpi_available():
                out["skipped"].append({"n_units": n, "ranks": r, "reason": "no MPI: install the mpi extra"})
                continue
            rep = run_one(n, r, duration_ms, dt_ms, drive, extra)
            if progress:
                print(f"neuromuscle bench pool: N={n} ranks={r} wall {rep['wall_s']:.1f} s, peak "
                      f"{rep['peak_rss_mib']:.0f} MiB, load {rep['load_1min_before']:.1f}", file=sys.stderr,
                      flush=True)
            out["runs"].append(rep)
    return out


def table_lines(res: dict[str, Any]) -> list[str]:
    """The result as a Markdown table (N x ranks: wall, sim, build, memory, spikes, load)."""
    lines = [f"pools, {res['duration_ms'] / 1000:g} s simulated at dt {res['dt_ms']} ms, {res['drive']} drive, muscle "
             f"{res.get('muscle', 'modules')} (substeps {res.get('substeps', 1)}), motoneuron channels "
             f"{res.get('channels', 'separate')}, {res.get('nthread', 1)} thread(s)",
             "", "| N | ranks | wall s | sim s | build s | s per unit-s | peak MiB (largest rank) | spikes | load |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in res["runs"]:
        lines.append(f"| {r['n_units']} | {r['ranks']} | {r['wall_s']:.2f} | {r['sim_s']:.2f} | {r['build_s']:.2f} "
                     f"| {r['s_per_unit_s']:.4f} | {r['peak_rss_mib']:.0f} | {r['spikes']} | "
                     f"{r['load_1min_before']:.1f}-{r['load_1min_after']:.1f} |")
    for s in res["skipped"]:
        lines.append(f"| {s['n_units']} | {s['ranks']} | skipped: {s['reason']} | | | | | | |")
    return lines
