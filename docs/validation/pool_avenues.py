"""Recompute the README's pool-avenue table: each fast path of a motoneuron pool against the reference (the three
Kim mechanisms every step, one mechanism per motoneuron channel, dt 0.025 ms), with the reference at dt/2 for the
scale of its own error.

Run from the repository root:  python docs/validation/pool_avenues.py [--units N] [--duration-ms T]
Prints Markdown (100 units, 2 s: about 45 s on two cores).  The drive is a common current ramp 0 -> 20 nA over
the run (the benchmark's ramp, compressed); errors in % of the reference's peak pool force; times in s, ms.
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from neuromuscle import Simulator, load_parameters
from neuromuscle.pool import Pool, PoolDefinition

#: (label, PoolDefinition fields, dt ms), the reference first.
CONFIGURATIONS: list[tuple[str, dict[str, Any], float]] = [
    ("reference", {"muscle_model": "modules", "motoneuron_channels": "separate"}, 0.025),
    ("reference at dt 0.0125 ms", {"muscle_model": "modules", "motoneuron_channels": "separate"}, 0.0125),
    ("fused channels (`mn_soma`, `mn_pic`)", {"muscle_model": "modules"}, 0.025),
    ("+ fused muscle (`KimUnit`, every step)", {"muscle_model": "fused"}, 0.025),
    ("+ muscle every 4 steps", {"muscle_model": "fused", "muscle_substeps": 4}, 0.025),
    ("+ muscle every 8 steps (the default)", {"muscle_model": "fused", "muscle_substeps": 8}, 0.025),
]


def run(n_units: int, duration_ms: float, fields: dict[str, Any], dt_ms: float) -> Any:
    """One pool run (PoolResult) of the ramp."""
    d = PoolDefinition(n_units, load_parameters("CT09"), smallest_p0_N=0.2, p0_range=20.0, **fields)
    with Pool(d) as pool:
        pool.drive_current_ramp([0.0, duration_ms], [0.0, 20.0])
        return pool.run(duration_ms, Simulator(dt_ms=dt_ms))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--units", type=int, default=100)
    ap.add_argument("--duration-ms", type=float, default=2000.0)
    args = ap.parse_args()
    results = [(label, run(args.units, args.duration_ms, fields, dt)) for label, fields, dt in CONFIGURATIONS]
    ref = results[0][1]
    peak = float(ref.pool_force_N.max())
    print(f"{args.units} units, {args.duration_ms / 1000:g} s, ramp 0 -> 20 nA; reference peak pool force "
          f"{peak:.1f} N\n")
    print("| configuration | sim s | spikes | max force error % | RMS force error % | largest first-spike shift ms |")
    print("|---|---|---|---|---|---|")
    for label, r in results:
        diff = r.pool_force_N - ref.pool_force_N
        shift = max((abs(a[0] - b[0]) for a, b in zip(r.spikes_ms, ref.spikes_ms) if a.size and b.size),
                    default=0.0)
        print(f"| {label} | {r.wall_s:.2f} | {sum(s.size for s in r.spikes_ms):,} | "
              f"{100 * np.max(np.abs(diff)) / peak:.2f} | {100 * np.sqrt(np.mean(diff ** 2)) / peak:.3f} | "
              f"{shift:.3f} |")


if __name__ == "__main__":
    main()
