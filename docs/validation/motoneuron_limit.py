"""The arithmetic limit of a motoneuron pool's step: the reduced motoneuron's fixed-step update (the equations of
mn_soma and mn_pic with their tables, the leak, the common synaptic conductance, the implicit cable solve of its
four compartments and the spike threshold) written as one C loop over N cells (structure of arrays), timed in
ns per cell-step beside NEURON's cost for the same cells.

Run from the repository root:  python docs/validation/motoneuron_limit.py [--units N] [--duration-ms T]
It compiles the loop (neuromuscle.bench.machine_limit, which ``neuromuscle bench pool`` also times before and
after its pools) with the system's C compiler twice (-O3, scalar; and -O3 -march=native -ffast-math, which
vectorises it), checks it against NEURON on the same cells (a constant synaptic conductance of --g-us on every
cell: spike counts and first spike times per cell, NEURON at the same step), and prints Markdown: ns per
cell-step of each build and of NEURON (one core; the 1-minute load average beside each).  The muscle's share is
not in the loop: its fused update, vectorised, costs about 23 ns per unit-step at its own cadence (every 8
membrane steps: about 3 ns per membrane step).  Units: ms, mV, uS, nA, nF, um.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from neuromuscle.bench.machine_limit import BUILDS, compile_loop, run_loop


def run_neuron(n: int, duration_ms: float, dt_ms: float, g_uS: float,
               channels: str = "fused") -> tuple[float, np.ndarray, np.ndarray]:
    """The same N cells in NEURON (``channels``: fused ones with the leak, or their fixed-step forms; a constant
    synaptic conductance g_uS on each cell's membrane as a pool's common drive sets it, the threshold): (ns per
    cell-step, spike counts, first spike times in ms or -1)."""
    from neuron import h

    from neuromuscle.pool.motoneuron import COMMON_SYNAPTIC_MECHANISMS, Motoneuron, motoneuron_parameters

    h.load_file("stdrun.hoc")
    cells = [Motoneuron(motoneuron_parameters(i / max(n - 1, 1)), name=f"mn{i}", channels=channels)
             for i in range(n)]
    recs = []
    for mech in COMMON_SYNAPTIC_MECHANISMS:
        setattr(h, f"gcommon_{mech}", g_uS)
    for cell in cells:
        cell.share_common_synaptic(True)
        nc = h.NetCon(cell.spike_source(), None, sec=cell.soma)
        nc.threshold = -10.0
        tv = h.Vector()
        nc.record(tv)
        recs.append((nc, tv))
    h.dt = dt_ms
    h.secondorder = 0
    h.CVode().active(0)
    h.finitialize(-70.0)
    start = time.perf_counter()
    h.continuerun(duration_ms)
    wall = time.perf_counter() - start
    for cell in cells:
        cell.destroy()
    counts = np.array([tv.size() for _, tv in recs])
    first = np.array([tv[0] if tv.size() else -1.0 for _, tv in recs])
    for mech in COMMON_SYNAPTIC_MECHANISMS:
        setattr(h, f"gcommon_{mech}", 0.0)
    return wall * 1e9 / (n * round(duration_ms / dt_ms)), counts, first


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--units", type=int, default=800)
    ap.add_argument("--duration-ms", type=float, default=1000.0)
    ap.add_argument("--dt-ms", type=float, default=0.025)
    ap.add_argument("--g-us", type=float, default=0.3, help="constant synaptic conductance of each cell (uS)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        load = os.getloadavg()[0]
        ns, counts, first = run_neuron(args.units, args.duration_ms, args.dt_ms, args.g_us)
        rows.append(("NEURON (mn_soma, mn_pic; no muscle)", ns, int(counts.sum()), load, "-"))
        load = os.getloadavg()[0]
        ns, fixed_counts, _ = run_neuron(args.units, args.duration_ms, args.dt_ms, args.g_us, "fused_fixed")
        rows.append(("NEURON (mn_soma_fixed, mn_pic_fixed; no muscle)", ns, int(fixed_counts.sum()), load,
                     f"{int(np.sum(fixed_counts != counts))} cells with another count"))
        for i, (label, flags) in enumerate(BUILDS):
            exe = compile_loop(folder, flags, f"loop{i}")
            load = os.getloadavg()[0]
            ns, spikes = run_loop(exe, args.units, args.duration_ms, args.dt_ms, args.g_us, folder / "out.txt")
            c = np.loadtxt(folder / "out.txt", ndmin=2)
            both = (c[:, 1] >= 0) & (first >= 0)
            shift = float(np.max(np.abs(c[both, 1] - first[both]))) if both.any() else 0.0
            agree = (f"{int(np.sum(c[:, 0] != counts))} cells with another count, first spikes within "
                     f"{shift:.3f} ms")
            rows.append((label, ns, spikes, load, agree))
    print(f"{args.units} motoneurons, {args.duration_ms / 1000:g} s at dt {args.dt_ms} ms, a constant synaptic "
          f"conductance of {args.g_us} uS on each; one core\n")
    print("| implementation | ns per cell-step | spikes | load | against NEURON |")
    print("|---|---|---|---|---|")
    for label, ns, spikes, load, agree in rows:
        print(f"| {label} | {ns:.1f} | {spikes:,} | {load:.1f} | {agree} |")


if __name__ == "__main__":
    main()
