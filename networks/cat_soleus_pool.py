"""A cat soleus motor-unit pool (slow units): a recruitment ramp by a common synaptic drive, and force-frequency.

Grounding of the pool definition:
- units: cat soleus has about 150 motor units (Burke 1981, Handbook of Physiology sect. 1 vol. II "Motor units:
  anatomy, physiology and functional organization"); --full builds 150, the default 20.
- types: the soleus is almost purely slow (type S units / type I fibres: Burke et al. 1974 J Physiol 238:503;
  Ariano, Armstrong & Edgerton 1973 J Histochem Cytochem 21:51): 95 % S, 5 % FR, no FF here; motoneuron size
  indices 0-0.3 (the S end of neuromuscle.pool.motoneuron's range).
- forces: every unit is the CT09 set of Kim et al. 2015 (a whole cat soleus, P0 23 N) with its P0 spread exponentially
  (Fuglevand, Winter & Patla 1993 J Neurophysiol 70:2470) over a 5-fold range (cat soleus unit tetanic forces span
  roughly one decade, Burke 1981) so that the unit P0s sum to CT09's 23 N.
- motoneurons: the small end of the size-scaled reduced cells, their PIC at the decerebrate cat's strong
  neuromodulation (--neuromodulation, default 1: S cells bistable, Lee & Heckman 1998; the cats of Kim, Sandercock
  & Heckman 2015 were decerebrate), driven by a common synaptic conductance (Pool.drive_synaptic).

Experiments: (1) a synaptic drive 0 -> --peak-us (held, then down to 0), isometric at -8 mm: raster, rates, unit
and pool force, recruitment drive by unit; with the strong PIC the first units keep firing after the drive is
gone (self-sustained firing); (2) force-frequency: 2-100 Hz trains into one unit of each type (relative force)
and the pool's plateau force with every unit at that rate (N).
Run: python networks/cat_soleus_pool.py --out DIR [--full] [--overwrite]
Writes DIR/cat_soleus_ramp.h5 (schema neuromuscle.pool/1 with a force_frequency group, provenance),
DIR/cat_soleus_ramp.png (the pool summary) and DIR/cat_soleus_summary.png.  Units: ms, uS, N, Hz, mm.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from neuromuscle import Simulator, load_parameters
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.experiments import force_frequency, summary_figure, total_force_smallest_p0_N
from neuromuscle.reports.outdir import prepare_out_dir

FILES = ("cat_soleus_ramp.h5", "cat_soleus_ramp.png", "cat_soleus_summary.png")
RATES_HZ = (2, 5, 8, 10, 15, 20, 30, 40, 60, 100)
P0_RANGE = 5.0


def definition(n_units: int, neuromodulation: float = 1.0) -> PoolDefinition:
    """The cat soleus pool of ``n_units`` units (module docstring)."""
    muscle = load_parameters("CT09")
    return PoolDefinition(n_units, muscle, smallest_p0_N=total_force_smallest_p0_N(n_units, muscle["P0"], P0_RANGE),
                          p0_range=P0_RANGE, type_fractions=(0.95, 0.05, 0.0), max_size=0.3,
                          axon_length_mm=150.0, neuromodulation=neuromodulation, name="cat_soleus")


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns a summary (units recruited, peak force, wall times)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--full", action="store_true", help="150 units, 6 s ramp (default 20 units, 2 s)")
    ap.add_argument("--peak-us", type=float, default=0.3, help="peak of the synaptic drive (uS a cell)")
    ap.add_argument("--neuromodulation", type=float, default=1.0, help="PIC strength (0 none, 1 decerebrate)")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    out = prepare_out_dir(a.out, a.overwrite, FILES)
    n, duration = (150, 6000.0) if a.full else (20, 2000.0)
    times, drive = [0.0, 0.4 * duration, 0.6 * duration, 0.8 * duration], [0.0, a.peak_us, a.peak_us, 0.0]
    d = definition(n, a.neuromodulation)
    t0 = time.time()
    with Pool(d, length=-8.0) as pool:
        pool.drive_synaptic(times, drive)
        ramp = pool.run(duration, Simulator(method="fixed", dt_ms=0.025))
    ff = force_frequency(d, RATES_HZ)
    ramp.save(out / FILES[0], overwrite=a.overwrite)
    ff.save_into(out / FILES[0], d, rates_hz=list(RATES_HZ), muscle_set="CT09", length_mm=-8.0)
    ramp.figure(out / FILES[1], title=f"cat soleus pool, {n} units, synaptic drive to {a.peak_us:g} uS")
    summary_figure(out / FILES[2], ramp, times, drive, ff, d, f"cat soleus pool ({n} units): ramp, recruitment, "
                                                             "force-frequency")
    after = times[-1]
    summary = {"units": n, "recruited": int(sum(s.size > 0 for s in ramp.spikes_ms)),
               "self_sustained": int(sum(bool(np.any(s > after + 100.0)) for s in ramp.spikes_ms)),
               "peak_pool_force_N": float(ramp.pool_force_N.max()), "ramp_wall_s": round(ramp.wall_s, 1),
               "total_wall_s": round(time.time() - t0, 1)}
    print(summary)
    return summary


if __name__ == "__main__":
    main()
