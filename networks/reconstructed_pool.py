"""A pool of reconstructed motoneurons: the pool of networks/reconstructed_pool.toml (every unit's cell the shipped
SWC morphology, read by NEURON's Import3d, with the reduced cell's channels per section group:
neuromuscle.pool.cells), under the file's recruitment ramp of the common synaptic drive.

Prints its figures as JSON: units recruited and their recruitment order and times, each unit's peak rate, the
pool's peak force, the first unit's somatic and dendritic voltage ranges, and the run's wall time.  Every unit
has the same cell under the same common drive, so all are recruited together and fire at the same rates; the
units differ in their muscle (P0, type).  Replace the file's morphology and channels with your own cells.
Writes DIR/pool.h5 (with provenance), DIR/reconstructed_pool.json and DIR/reconstructed_pool.png.
Run: python networks/reconstructed_pool.py --out DIR [--units N] [--duration-ms T] [--overwrite]  (a few seconds)
Units: ms, mV, N, Hz.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from neuromuscle.pool.pool_file import pool_setup, read_document
from neuromuscle.pool.run_mpi import run_definition
from neuromuscle.reports.outdir import prepare_out_dir

DEFINITION = Path(__file__).resolve().parent / "reconstructed_pool.toml"
FILES = ("pool.h5", "reconstructed_pool.json", "reconstructed_pool.png")


def summarise(result, wall_s: float) -> dict:
    """The figures printed (module docstring)."""
    first = {i: float(s[0]) for i, s in enumerate(result.spikes_ms) if s.size}
    order = sorted(first, key=first.get)
    peak_rates = [round(float(1000.0 / np.diff(s).min()), 1) if s.size > 1 else 0.0 for s in result.spikes_ms]
    out = {"units": result.n_units, "recruited": len(first), "recruitment_order": order,
           "recruitment_ms": [round(first[i], 1) for i in order], "peak_rate_hz": peak_rates,
           "peak_pool_force_N": round(float(result.pool_force_N.max()), 3), "wall_s": round(wall_s, 1)}
    for name in ("mn.v", "mn.v_dend"):
        if name in result.recordings:
            v = np.asarray(result.recordings[name].values)[0]
            out[f"unit0_{name.split('.')[1]}_range_mV"] = [round(float(v.min()), 1), round(float(v.max()), 1)]
    return out


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns the figures printed as JSON."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--units", type=int, default=None, help="motor units (default: the file's 6)")
    ap.add_argument("--duration-ms", type=float, default=None, help="run length (ms; default: the file's 1000)")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    doc = read_document(DEFINITION)
    flagged = {}
    if a.units is not None:
        doc["units"]["count"], flagged["units.count"] = a.units, "--units"
    if a.duration_ms is not None:
        doc["run"]["duration_ms"], flagged["run.duration_ms"] = a.duration_ms, "--duration-ms"
    setup = pool_setup(doc, str(DEFINITION.name), flagged, DEFINITION.parent)
    out = prepare_out_dir(a.out, a.overwrite, FILES)
    t0 = time.perf_counter()
    result, _ = run_definition(setup.definition, setup.drive, setup.simulator, setup.duration_ms,
                               length=setup.length, record_dt_ms=setup.record_dt_ms, recordings=setup.recordings,
                               cells=setup.cells)
    summary = summarise(result, time.perf_counter() - t0)
    result.provenance.update({"definition": setup.document, "definition_file": DEFINITION.name})
    result.save(out / FILES[0], overwrite=a.overwrite)
    (out / FILES[1]).write_text(json.dumps(summary, indent=1))
    result.figure(out / FILES[2], title=f"reconstructed motoneurons: {result.n_units} units, ramp drive")
    print(json.dumps(summary))
    return summary


if __name__ == "__main__":
    main()
