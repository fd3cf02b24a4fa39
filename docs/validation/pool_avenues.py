"""Recompute the pool-avenue table of docs/validation/speed.md: each fast path of a motoneuron pool against the
reference (the three Kim mechanisms every step, one mechanism per motoneuron channel, dt 0.025 ms), with the
reference at dt/2 for the scale of its own error, and against a fine one (the reference's mechanisms under
Crank-Nicolson at dt 0.00625 ms, whose discharges converge at second order) for each row's error itself.

Run from the repository root:  python docs/validation/pool_avenues.py [--units N] [--duration-ms T] [--drive D]
Prints Markdown (100 units, 2 s: about two minutes on two cores).  The drive is the benchmark's: a common synaptic
conductance rising 0 -> 0.6 uS over the run ("synaptic": every unit recruited, 8-35 Hz) or a common current ramp
0 -> 20 nA ("ramp": about 150 Hz).  Errors in % of the reference's peak pool force; times in s, ms; the cost per
cell-step in ns of integration per motoneuron-and-muscle-unit step, counted at dt 0.025 ms whatever the step (so
that rows compare by the wall time of the same simulated time); the 1-minute load average before and after.

A second table bounds what placing each spike inside its step could gain (NEURON's ``CVode.condition_order(2)``
does so under CVODE only: the fixed step, NEURON's or CoreNEURON's, gives a spike the time of the step that detects
it): 20 units, 1 s, the first spikes at dt 0.05 and 0.025 ms against dt 0.003125 ms, as detected and as placed
exactly by linear interpolation of the soma's voltage, recorded every step, across the threshold.
"""

from __future__ import annotations

import argparse
import os
from typing import Any, Callable

import numpy as np

from neuromuscle import Simulator, load_parameters
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.drives import Drive
from neuromuscle.pool.motoneuron import Motoneuron

REFERENCE = {"muscle_model": "modules", "motoneuron_channels": "separate"}
FAST = {"muscle_model": "fused", "muscle_substeps": 8}


def nseg_by_type(nseg: dict[str, int]) -> Callable[[Any, str], Motoneuron]:
    """A cell factory whose dendrite has nseg[type] compartments (the others as defined)."""
    from dataclasses import replace

    return lambda spec, name: Motoneuron(replace(spec.motoneuron, dend_nseg=nseg.get(spec.unit_type,
                                                                                     spec.motoneuron.dend_nseg)),
                                         name=name)


#: (label, PoolDefinition fields, dt ms, options: engine, cell_permute, cache_efficient, cells, condition_order,
#: secondorder), reference first.
CONFIGURATIONS: list[tuple[str, dict[str, Any], float, dict[str, Any]]] = [
    ("reference", REFERENCE, 0.025, {}),
    ("reference at dt 0.0125 ms", REFERENCE, 0.0125, {}),
    ("the row above, `condition_order` 2", REFERENCE, 0.0125, {"condition_order": 2}),
    ("fused channels (`mn_soma`, `mn_pic`)", {"muscle_model": "modules"}, 0.025, {}),
    ("+ fused muscle (`KimUnit`, every step)", {"muscle_model": "fused"}, 0.025, {}),
    ("+ muscle every 4 steps", {"muscle_model": "fused", "muscle_substeps": 4}, 0.025, {}),
    ("+ muscle every 8 steps (0.2 ms)", FAST, 0.025, {}),
    ("the row above, `condition_order` 2", FAST, 0.025, {"condition_order": 2}),
    ("+ PIC gate every 8 steps (`pic_substeps` 8)", {**FAST, "pic_substeps": 8}, 0.025, {}),
    ("+ membrane at dt 0.0375 ms, muscle every 5 steps (0.1875 ms)", {**FAST, "muscle_substeps": 5}, 0.0375, {}),
    ("the row above, `condition_order` 2", {**FAST, "muscle_substeps": 5}, 0.0375, {"condition_order": 2}),
    ("+ membrane at dt 0.05 ms, muscle every 4 steps (0.2 ms)", {**FAST, "muscle_substeps": 4}, 0.05, {}),
    ("the row above, `condition_order` 2", {**FAST, "muscle_substeps": 4}, 0.05, {"condition_order": 2}),
    ("muscle every 8 steps, Crank-Nicolson (`secondorder` 2)", FAST, 0.025, {"secondorder": 2}),
    ("the row above, membrane at dt 0.0375 ms, muscle every 5 steps", {**FAST, "muscle_substeps": 5}, 0.0375,
     {"secondorder": 2}),
    ("the row above, membrane at dt 0.05 ms, muscle every 4 steps", {**FAST, "muscle_substeps": 4}, 0.05,
     {"secondorder": 2}),
    ("Crank-Nicolson, membrane at dt 1/30 ms, muscle every 6 steps", {**FAST, "muscle_substeps": 6}, 1 / 30,
     {"secondorder": 2}),
    ("the row above, PIC gate every 6 steps", {**FAST, "muscle_substeps": 6, "pic_substeps": 6}, 1 / 30,
     {"secondorder": 2}),
    ("the row above, fixed-step forms (`KimUnitFixed`, `mn_soma_fixed`, `mn_pic_fixed`: the benchmark's default)",
     {**FAST, "muscle_model": "fused_fixed", "muscle_substeps": 6, "pic_substeps": 6,
      "motoneuron_channels": "fused_fixed"}, 1 / 30, {"secondorder": 2}),
    ("the row above, CoreNEURON", {**FAST, "muscle_substeps": 6, "pic_substeps": 6}, 1 / 30,
     {"secondorder": 2, "engine": "coreneuron"}),
    ("Crank-Nicolson, membrane at dt 0.04 ms, muscle and PIC gate every 5 steps", {**FAST, "muscle_substeps": 5,
                                                                                   "pic_substeps": 5}, 0.04,
     {"secondorder": 2}),
    ("muscle every 8 steps, 2 dendritic compartments instead of 3", {**FAST, "motoneuron_overrides":
                                                                        {"dend_nseg": 2}}, 0.025, {}),
    ("muscle every 8 steps, 2 dendritic compartments in S cells only", FAST, 0.025,
     {"cells": nseg_by_type({"S": 2})}),
    ("muscle every 8 steps, NEURON's cache-efficient layout", FAST, 0.025, {"cache_efficient": True}),
    ("muscle every 8 steps, CoreNEURON", FAST, 0.025, {"engine": "coreneuron"}),
    ("muscle every 8 steps, CoreNEURON, `cell_permute` 1", FAST, 0.025, {"engine": "coreneuron", "cell_permute": 1}),
    ("dt 0.05 ms, muscle every 4 steps, CoreNEURON", {**FAST, "muscle_substeps": 4}, 0.05,
     {"engine": "coreneuron"}),
]


def run(n_units: int, duration_ms: float, fields: dict[str, Any], dt_ms: float, drive: str,
        options: dict[str, Any]) -> Any:
    """One pool run (PoolResult) of ``drive`` ("synaptic" or "ramp") over duration_ms (ms) at step dt_ms (ms)."""
    from neuron import coreneuron, h

    engine = options.get("engine", "neuron")
    d = PoolDefinition(n_units, load_parameters("CT09"), smallest_p0_N=0.2, p0_range=20.0, **fields)
    coreneuron.cell_permute = options.get("cell_permute", 0)
    with Pool(d, engine=engine, cells=options.get("cells")) as pool:
        (Drive.rise("synaptic", 0.6, duration_ms) if drive == "synaptic"
         else Drive.rise("current", 20.0, duration_ms)).apply(pool)
        h.CVode().cache_efficient(int(options.get("cache_efficient", False)))
        # NEURON's threshold-crossing interpolation: it acts under CVODE only, the fixed step ignores it
        order = int(options.get("condition_order", 1))
        try:
            return pool.run(duration_ms, Simulator(dt_ms=dt_ms, engine=engine, condition_order=order,
                                                   secondorder=int(options.get("secondorder", 0))))
        finally:
            coreneuron.cell_permute = 0


def first_spikes_exact(n_units: int, duration_ms: float, dt_ms: float) -> tuple[np.ndarray, np.ndarray]:
    """Each unit's first spike (ms; NaN where none) in the fast path at step dt_ms under the synaptic drive: as the
    NetCon detects it, and at the threshold crossing interpolated linearly between the steps around it."""
    from neuron import h

    from neuromuscle.pool.pool import SPIKE_THRESHOLD_MV

    d = PoolDefinition(n_units, load_parameters("CT09"), smallest_p0_N=0.2, p0_range=20.0, muscle_model="fused",
                       muscle_substeps=max(1, round(0.2 / dt_ms)))
    with Pool(d) as pool:
        Drive.rise("synaptic", 0.6, duration_ms).apply(pool)
        tv = h.Vector().record(h._ref_t)
        vs = {gid: h.Vector().record(cell.soma(0.5)._ref_v) for gid, cell in pool.cells.items()}
        r = pool.run(duration_ms, Simulator(dt_ms=dt_ms))
        t = np.array(tv)
        detected, exact = np.full(n_units, np.nan), np.full(n_units, np.nan)
        for gid, vec in vs.items():
            v = np.array(vec)
            up = np.nonzero((v[1:] > SPIKE_THRESHOLD_MV) & (v[:-1] <= SPIKE_THRESHOLD_MV))[0]
            if r.spikes_ms[gid].size and up.size:
                k = up[0]
                detected[gid] = r.spikes_ms[gid][0]
                exact[gid] = t[k] + (SPIKE_THRESHOLD_MV - v[k]) / (v[k + 1] - v[k]) * (t[k + 1] - t[k])
    return detected, exact


def crossing_table(n_units: int = 20, duration_ms: float = 1000.0) -> None:
    """Print the second table of the module docstring."""
    _, ref = first_spikes_exact(n_units, duration_ms, 0.003125)
    print(f"\n{n_units} units, {duration_ms / 1000:g} s, first spikes against dt 0.003125 ms (interpolated):\n")
    print("| dt ms | mean shift as detected ms | largest | mean shift interpolated ms | largest |")
    print("|---|---|---|---|---|")
    for dt in (0.05, 0.025):
        detected, exact = first_spikes_exact(n_units, duration_ms, dt)
        a, b = detected - ref, exact - ref
        print(f"| {dt:g} | {np.nanmean(a):+.3f} | {np.nanmax(np.abs(a)):.3f} | {np.nanmean(b):+.3f} | "
              f"{np.nanmax(np.abs(b)):.3f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--units", type=int, default=100)
    ap.add_argument("--duration-ms", type=float, default=2000.0)
    ap.add_argument("--drive", choices=("synaptic", "ramp"), default="synaptic")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    fine = run(args.units, args.duration_ms, REFERENCE, 0.00625, args.drive, {"secondorder": 2})
    results = [(label, run(args.units, args.duration_ms, fields, dt, args.drive, opts))
               for label, fields, dt, opts in CONFIGURATIONS]
    ref = results[0][1]
    peak = float(ref.pool_force_N.max())
    steps = args.units * args.duration_ms / 0.025
    unit_s = args.units * args.duration_ms / 1000.0
    max_rate = max(s.size for s in ref.spikes_ms) / (args.duration_ms / 1000.0)
    print(f"{args.units} units, {args.duration_ms / 1000:g} s, {args.drive} drive; reference: peak pool force "
          f"{peak:.1f} N, mean rate {sum(s.size for s in ref.spikes_ms) / unit_s:.1f} Hz, largest {max_rate:.0f} Hz; "
          f"fine reference: {sum(s.size for s in fine.spikes_ms):,} spikes; "
          f"load average {load:.1f} -> {os.getloadavg()[0]:.1f}\n")
    print("| configuration | sim s | ns per cell-step | spikes | max force error % | RMS force error % | "
          "largest first-spike shift ms | mean first-spike shift ms | against the fine reference: max force error % "
          "| largest first-spike shift ms |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, r in results:
        diff = r.pool_force_N - ref.pool_force_N
        shifts = np.array([a[0] - b[0] for a, b in zip(r.spikes_ms, ref.spikes_ms) if a.size and b.size])
        fine_shifts = np.array([a[0] - b[0] for a, b in zip(r.spikes_ms, fine.spikes_ms) if a.size and b.size])
        print(f"| {label} | {r.wall_s:.2f} | {r.wall_s / steps * 1e9:.0f} | {sum(s.size for s in r.spikes_ms):,} | "
              f"{100 * np.max(np.abs(diff)) / peak:.2f} | {100 * np.sqrt(np.mean(diff ** 2)) / peak:.3f} | "
              f"{np.max(np.abs(shifts), initial=0.0):.3f} | {np.mean(shifts) if shifts.size else 0.0:+.3f} | "
              f"{100 * np.max(np.abs(r.pool_force_N - fine.pool_force_N)) / peak:.2f} | "
              f"{np.max(np.abs(fine_shifts), initial=0.0):.3f} |")
    crossing_table()
    print(f"\nload average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
