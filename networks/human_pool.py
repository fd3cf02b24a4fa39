"""A human motor-unit pool of the Fuglevand type: a recruitment ramp of the common synaptic drive, force-frequency,
and a random locomotor-like length shared by the pool.

Grounding of the pool definition:
- units and forces: Fuglevand, Winter & Patla 1993 (J Neurophysiol 70:2470) spread twitch forces exponentially over
  a 100-fold range across the pool, most units small; the same P0 spread here (neuromuscle.pool.p0_spread_N),
  scaled so the unit P0s sum to 600 N (a human tibialis anterior order of magnitude).  --full: 800 units (the
  size of the benchmark pool; human TA is estimated at a few hundred units, McComas 1998 Muscle Nerve 21:1339), default
  20 units.
- types: 70 % S, 20 % FR, 10 % FF (human TA is about 70-75 % type I fibres: Johnson, Polgar, Weightman &
  Appleton 1973 J Neurol Sci 18:111); twitch speed by type from neuromuscle.pool.TWITCH_SPEED; motoneuron size
  index over the whole S..FF range; axon 900 mm (human leg).
- motoneurons: the size-scaled reduced cells with the human profile (neuromuscle.pool.motoneuron.PROFILES: the
  setting whose pools fire like decomposed human motor units), driven by a common synaptic conductance, the same
  total on every cell (Pool.drive_synaptic): the peak (--peak-us, default 0.8 uS) recruits the whole pool, and
  every unit's median rate stays within the 10-23 Hz of recorded human units (the 5th-95th percentiles of the unit
  medians of the Caillet et al. recordings, tibialis anterior and gastrocnemius medialis at 30-50 % MVC).

Experiments: (1) synaptic drive 0 -> peak (half the run), held, then down to 0, isometric at -8 mm; (2)
force-frequency by type and for the pool (every unit at each rate); (3) the same pool held at the peak drive under
a random locomotor-like length (neuromuscle.protocols.random_length, band 5 Hz, -16..0 mm, seed --seed) shared by
all units.
Run: python networks/human_pool.py --out DIR [--full] [--overwrite]
Writes DIR/human_ramp.h5 (neuromuscle.pool/1 + force_frequency group), DIR/human_length.h5, their pool figures
(.png) and DIR/human_summary.png; prints a summary (units recruited, peak and median unit rates).  Units: ms, uS,
N, Hz, mm.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from neuromuscle import Simulator, load_parameters
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.discharge_stats import inside_human_range, unit_rates
from neuromuscle.pool.experiments import force_frequency, summary_figure, total_force_smallest_p0_N
from neuromuscle.pool.motoneuron import motoneuron_profile
from neuromuscle.protocols import random_length
from neuromuscle.reports.outdir import prepare_out_dir

FILES = ("human_ramp.h5", "human_ramp.png", "human_length.h5", "human_length.png", "human_summary.png")
RATES_HZ = (2, 5, 8, 10, 15, 20, 30, 40, 60, 100)
P0_RANGE, TOTAL_P0_N = 100.0, 600.0


def definition(n_units: int) -> PoolDefinition:
    """The human pool of ``n_units`` units (module docstring)."""
    return PoolDefinition(n_units, load_parameters("CT09"),
                          smallest_p0_N=total_force_smallest_p0_N(n_units, TOTAL_P0_N, P0_RANGE),
                          p0_range=P0_RANGE, type_fractions=(0.7, 0.2, 0.1), max_size=1.0, axon_length_mm=900.0,
                          name="human", **motoneuron_profile("human").pool_options())


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns a summary (units recruited, forces, wall times)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--full", action="store_true", help="800 units, 5 s runs (default 20 units, 1.5 s)")
    ap.add_argument("--peak-us", type=float, default=0.8, help="peak of the synaptic drive (uS a cell)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the random length")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    out = prepare_out_dir(a.out, a.overwrite, FILES)
    n, duration = (800, 5000.0) if a.full else (20, 1500.0)
    times, drive = [0.0, 0.5 * duration, 0.75 * duration, duration], [0.0, a.peak_us, a.peak_us, 0.0]
    d = definition(n)
    sim = Simulator(method="fixed", dt_ms=0.025)
    t0 = time.time()
    with Pool(d, length=-8.0) as pool:
        pool.drive_synaptic(times, drive)
        ramp = pool.run(duration, sim)
    length = random_length(duration, seed=a.seed)
    with Pool(d, length=length) as pool:
        pool.drive_synaptic([0.0, 0.1 * duration, duration], [0.0, a.peak_us, a.peak_us])
        moving = pool.run(duration, sim)
    ff = force_frequency(d, RATES_HZ)
    ramp.save(out / FILES[0], overwrite=a.overwrite)
    ff.save_into(out / FILES[0], d, rates_hz=list(RATES_HZ), muscle_set="CT09", length_mm=-8.0)
    ramp.figure(out / FILES[1], title=f"human pool, {n} units, synaptic drive to {a.peak_us:g} uS")
    moving.save(out / FILES[2], overwrite=a.overwrite)
    moving.figure(out / FILES[3], title=f"human pool, {n} units, {a.peak_us:g} uS, random length (seed {a.seed})")
    summary_figure(out / FILES[4], ramp, times, drive, ff, d, f"human pool ({n} units): ramp, recruitment, "
                                                             "force-frequency, random length", length_run=moving)
    rates = unit_rates([s for s in ramp.spikes_ms if s.size > 2])
    summary = {"units": n, "recruited": int(sum(s.size > 0 for s in ramp.spikes_ms)),
               "peak_pool_force_N": float(ramp.pool_force_N.max()),
               "unit_peak_rate_max_hz": round(float(np.nanmax(rates.peak_hz)), 1),
               "unit_median_rate_median_hz": round(float(np.nanmedian(rates.median_hz)), 1),
               "unit_median_rates_min_max_hz": [round(float(np.nanmin(rates.median_hz)), 1),
                                                round(float(np.nanmax(rates.median_hz)), 1)],
               "medians_inside_human_range": round(inside_human_range(rates), 3),
               "ramp_wall_s": round(ramp.wall_s, 1),
               "length_wall_s": round(moving.wall_s, 1), "total_wall_s": round(time.time() - t0, 1)}
    print(summary)
    return summary


if __name__ == "__main__":
    main()
