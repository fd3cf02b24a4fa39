"""Module 3 calibrated against real cat soleus data: a worked example of :mod:`.module3` on published datasets
(numbers only; no simulation)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..literature import load_herzog_leonard_2002, load_scott_brown_loeb_1996
from .module3 import calibrate_force_length, calibrate_force_velocity


def _plateau(force: np.ndarray, frac: float = 0.8) -> float:
    """Median of the middle half of the samples at or above frac * max (the tetanic plateau)."""
    idx = np.flatnonzero(force >= frac * np.max(force))
    a, b = idx[0], idx[-1]
    mid = force[a + (b - a) // 4: b - (b - a) // 4 + 1]
    return float(np.median(mid))


def real_data_calibration(real_data_dir: str | Path) -> dict[str, Any]:
    """Module 3 calibration against real cat soleus data (numbers only; no simulation).

    Scott, Brown & Loeb 1996 (cat_digitized_literature): g1 (L0), g2 (L0), P0 (F0) from the active tetanic
    force-length points of five specimens; a0 (F0), b0 (L0/s), c0 (F0), d0 (L0/s) by least squares through
    the force-velocity points with P0 = 1 F0 (normalised units; multiply by P0 (N) and L0 (mm) of a given
    muscle to get model units).  Errors: RMS and max |residual| in F0.

    Herzog & Leonard 2002 (cat_soleus_herzog_leonard_2002): isometric plateau forces at the paper's 0 and
    +9 mm, passive force at +9 mm, active force ratio F(9)/F(0), and the peak force at the end of the 0->9 mm
    stretches over the isometric force at 9 mm (force enhancement + velocity, per speed).  NOT calibratable
    from these traces: KSE (no step or quick release), Module 2 (stimulus times unknown, single supramaximal
    rate), g1/g2 in mm (two lengths only, and the paper's 0 mm is not the model's reference), c0/d0 (the force
    at the stretch end includes history-dependent enhancement that the model does not have)."""
    root = Path(real_data_dir)
    out: dict[str, Any] = {}
    sbl = load_scott_brown_loeb_1996(root / "cat_digitized_literature")
    fl = calibrate_force_length(sbl.active_length_L0, sbl.active_force_F0)
    fl1 = calibrate_force_length(sbl.active_length_L0, sbl.active_force_F0, fix_P0=1.0)
    fv = calibrate_force_velocity(sbl.velocity_L0_per_s, sbl.velocity_force_F0, 1.0)
    out["scott_brown_loeb_1996"] = {
        "force_length": {"g1_L0": fl.values["g1"], "g2_L0": fl.values["g2"], "P0_F0": fl.values["P0"],
                         "rms_F0": fl.errors["rms"], "max_abs_F0": fl.errors["max_abs"],
                         "n_points": int(fl.errors["n_points"]),
                         "P0_fixed_1": {"g1_L0": fl1.values["g1"], "g2_L0": fl1.values["g2"],
                                        "rms_F0": fl1.errors["rms"]}},
        "force_velocity": {"a0_F0": fv.values["a0"], "b0_L0_per_s": fv.values["b0"], "c0_F0": fv.values["c0"],
                           "d0_L0_per_s": fv.values["d0"], "rms_F0": fv.errors["rms"],
                           "rms_shortening_F0": fv.errors["rms_shortening"],
                           "rms_lengthening_F0": fv.errors["rms_lengthening"],
                           "vmax_L0_per_s": fv.errors["vmax"],
                           "lengthening_asymptote_F0": fv.errors["lengthening_asymptote_over_P0"],
                           "n_points": int(np.sum(sbl.velocity_L0_per_s != 0))},
        "notes": ["normalised units: lengths in L0, forces in F0, velocities in L0/s",
                  "CT09 for comparison (P0 = 23 N): a0/P0 = 0.102, c0/P0 = -0.32, asymptote 1.68 F0"],
    }
    hl = load_herzog_leonard_2002(root / "cat_soleus_herzog_leonard_2002")
    iso0_by = {t.trial_id: _plateau(t.force) for t in hl.trials.values() if t.protocol == "isometric"
               and t.attrs["start_length_mm"] == 0.0}
    iso0 = list(iso0_by.values())
    iso9 = {t.attrs["figure"]: _plateau(t.force) for t in hl.trials.values() if t.protocol == "isometric"
            and t.attrs["start_length_mm"] == 9.0}
    passive9 = [float(np.median(t.force[-100:])) for t in hl.trials.values() if t.protocol == "passive"]
    stretch = {}
    for t in hl.trials.values():
        if t.protocol == "stretch" and t.attrs["start_length_mm"] == 0.0 and t.attrs["figure"] in iso9:
            i_end = int(np.argmax(t.length >= 8.9))
            f_end = float(np.max(t.force[max(i_end - 5, 0): i_end + 5]))
            stretch[t.trial_id] = {
                "speed_mm_s": float(t.attrs.get("stretch_speed_nominal_mm_s", t.attrs["ramp_speed_estimated_mm_s"])),
                "peak_end_of_stretch_N": f_end, "over_isometric_9mm": f_end / iso9[t.attrs["figure"]]}
    p9 = float(np.mean(passive9))
    a0m, a9m = float(np.mean(iso0)), float(np.mean(list(iso9.values())))
    out["herzog_leonard_2002"] = {
        "isometric_0mm_N": {"mean": a0m, "sd": float(np.std(iso0)), "n": len(iso0), "per_trial": iso0_by},
        "isometric_9mm_N": {"mean": a9m, "sd": float(np.std(list(iso9.values()))), "n": len(iso9),
                            "per_figure": iso9},
        "passive_9mm_N": {"mean": p9, "n": len(passive9)},
        "active_ratio_9mm_over_0mm": (a9m - p9) / a0m,
        "stretch_0_to_9mm": stretch,
        "not_calibrated": ["KSE: no step shortening or quick release in the traces",
                           "Module 2: stimulus times unknown (constant supramaximal train, ~30 Hz unverified)",
                           "g1/g2 in mm: two lengths only, paper's 0 mm is not the model reference",
                           "c0/d0: stretch forces include force enhancement (history dependence not modelled)"],
        "P0_estimate_N": max(a0m, a9m - p9),
        "P0_note": "lower bound on P0 (largest active isometric plateau; the optimum may lie between 0 and 9 mm)",
    }
    return out
