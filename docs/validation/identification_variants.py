"""Recompute the table of identification variants in docs/validation/pools_vs_recorded.md: for each Caillet
recording, the P0 spread fitted to it (``follow_force.fit_p0_spread_to_recording``) under variants of the model of
which units a decomposition identifies (``neuromuscle.pool.identification``), and the thresholds' KS distance of
the identified units at that spread, averaged over the reported depth seeds 0-19.  No pool follows a force here:
the distances are those the fit expects from the thresholds on the calibration ramp (a trial that follows the
force gives its own, in the tables of that page).

Variants: the units of highest weight (ranked) at several depth attenuations; drawn in proportion to their weights
(sampled); weighted by their time discharging (activity exponent 1 and 2); and one spread for the five
decompositions of subject S1's tibialis anterior (two contractions, three and two grids), fitted to the sum of
their distances.

Run from the repository root:  python docs/validation/identification_variants.py [--quick]
The calibrations are those of ``networks/pool_vs_recorded.py --units 120 --motoneurons human
--calibration-top-uS 1.6 --calibration-ramp-ms 40000`` (about two minutes a muscle); every fit then takes a few
seconds (26 min in all for the page's table, on one of two cores shared with two diagnoses).  --quick: two TA files,
30 units, dt 0.05 ms (a check that the script runs, not the table).  Prints Markdown.
"""

from __future__ import annotations

import argparse
import importlib.util
from dataclasses import replace
from pathlib import Path

import numpy as np

from neuromuscle.pool.follow_force import HUMAN_MUSCLES, best_spread, spread_distances, time_above_s
from neuromuscle.pool.identification import DEPTH_ATTENUATION, IdentificationModel, identified_ks
from neuromuscle.pool.motoneuron import motoneuron_profile

ROOT = Path(__file__).resolve().parents[2]
REPORT_SEEDS = range(20)


def _networks_module():
    """networks/pool_vs_recorded.py as a module (its file list, loader and calibration)."""
    spec = importlib.util.spec_from_file_location("pool_vs_recorded", ROOT / "networks" / "pool_vs_recorded.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def variants() -> dict[str, IdentificationModel]:
    """Name -> identification model of every variant of one spread per recording."""
    out = {f"ranked, a {a:g}": IdentificationModel(depth_attenuation=a) for a in (0.0, 1.0, 1.75, 3.0, 6.0, 12.0)}
    out.update({f"sampled, a {a:g}": IdentificationModel(depth_attenuation=a, selection="sampled")
                for a in (0.0, 1.75, 6.0)})
    out.update({f"ranked, a {DEPTH_ATTENUATION:g}, activity exponent {e:g}":
                IdentificationModel(activity_exponent=e) for e in (1.0, 2.0)})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--units", type=int, default=120)
    ap.add_argument("--dt-ms", type=float, default=0.025)
    ap.add_argument("--quick", action="store_true", help="S1_30_36L and S1_50_64L, 30 units, dt 0.05 ms")
    a = ap.parse_args()
    if a.quick:
        a.units, a.dt_ms = 30, 0.05
    pvr = _networks_module()
    profile = motoneuron_profile("human")
    options = {"motoneuron_overrides": dict(profile.overrides), "neuromodulation": profile.neuromodulation,
               "synaptic_noise_uS": profile.synaptic_noise_uS}
    files = [Path(pvr.DATA) / f for f in (("S1_30_36L.mat", "S1_50_64L.mat") if a.quick else pvr.ALL_FILES)]
    recs = {}
    for path in files:
        rec = pvr.load_caillet(path)
        thr = np.asarray(rec.thresholds_percent_mvc(), float)
        recs[path.stem] = (pvr.muscle_of(path), thr[np.isfinite(thr)], float(np.nanmax(rec.force_percent_mvc)),
                           np.asarray(rec.force_percent_mvc, float), 1.0 / rec.fsamp_hz)
    cals = {m: pvr.calibrate_muscle(m, a.units, options, dict(profile.scales), dt_ms=a.dt_ms, top_uS=1.6,
                                    ramp_ms=40000.0) for m in sorted({r[0] for r in recs.values()})}

    def distances(stem: str, model: IdentificationModel):
        m, thr, peak, force, sample_s = recs[stem]
        return spread_distances(cals[m], HUMAN_MUSCLES[m], thr, peak, model=model, recorded_force_percent=force,
                                force_sample_s=sample_s)

    def reported(stem: str, spread, model: IdentificationModel) -> float:
        m, thr, peak, force, sample_s = recs[stem]
        t = spread.thresholds_percent
        return identified_ks(spread.p0_N(cals[m].rank), t <= peak, t, thr, motor_units=HUMAN_MUSCLES[m].motor_units,
                             model=model, seeds=REPORT_SEEDS, active_s=time_above_s(force, sample_s, t))

    stems = list(recs)
    print("| variant | " + " | ".join(stems) + " |")
    print("|---|" + "---|" * len(stems))
    for name, model in variants().items():
        cells = []
        for stem in stems:
            grid, d = distances(stem, model)
            spread, _ = best_spread(grid, d)
            cells.append(f"{reported(stem, spread, model):.2f}")
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)
    subject = [s for s in stems if s.startswith("S1_")]
    for name, model in (("one spread for S1, ranked, a 1.75", IdentificationModel()),
                        ("one spread for S1, sampled, a 1.75", IdentificationModel(selection="sampled")),
                        ("one spread for S1, ranked, a 1.75, activity exponent 1",
                         replace(IdentificationModel(), activity_exponent=1.0))):
        grids = [distances(s, model) for s in subject]
        spread, _ = best_spread(grids[0][0], np.sum([g[1] for g in grids], axis=0))
        cells = [f"{reported(s, spread, model):.2f}" if s in subject else "" for s in stems]
        print(f"| {name} (R {spread.range_ratio:.3g}, q {spread.exponent:.3g}) | " + " | ".join(cells) + " |",
              flush=True)


if __name__ == "__main__":
    main()
