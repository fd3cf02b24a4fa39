"""``neuromuscle bench diagnose``: wall time of one full diagnosis of a synthetic file of a world (by default a null
of world B: the extended protocol set, 36 trials; ``cause`` hides one catalogue cause in it) with 2 workers, and of
its baseline calibration alone, with the machine's load average before and after.  A file with a cause costs more
than a null: every step fits candidates, and a world with eq 18 names it besides."""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path
from typing import Any

#: The full diagnosis's target on 2 workers (s).
TARGET_S = 180.0


def bench_diagnose(workers: int = 2, world: str = "B", cause: str | None = None,
                   strength: float = 0.7) -> dict[str, Any]:
    """Wall times (s) of the baseline calibration alone and of the full diagnosis (report written to a temporary
    folder) of the preparation of seed 0 in ``world`` (a null, or hiding ``cause`` at ``strength``, 0-1 of its
    range), with the file's trial count, what was named, the simulation settings and the load average (1 min)
    before and after."""
    from ..diagnose import run_diagnosis
    from ..diagnose.baseline import calibrate_baseline
    from ..diagnose.diagnosis import prepare
    from ..diagnose.models import DIFFERENCE_DT_MS, DT_MS
    from ..diagnose.phases import describe_all
    from ..fit.evaluate import BATCH_UNITS, PACK_SHARE, TrialPool
    from ..measured import write_measured
    from ..parameters import load_parameters
    from ..synth import make_dataset, without_truth

    data = without_truth(make_dataset(cause, strength if cause else 0.0, 0, world=world, workers=workers))
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        path = write_measured(Path(tmp) / "preparation.h5", data)
        split = prepare(data)
        t0 = time.perf_counter()
        with TrialPool(list(data.trials.values()), workers) as pool:
            calibrate_baseline(data, describe_all(data.trials), split.calibration, load_parameters("CT09"), pool=pool)
        t_base = time.perf_counter() - t0
        t0 = time.perf_counter()
        doc = run_diagnosis(path, Path(tmp) / "report", workers=workers)
        t_full = time.perf_counter() - t0
    hidden = f"{cause!r}, strength {strength:g}" if cause else "None"
    return {"data": f"neuromuscle.synth.make_dataset({hidden}, seed 0, world {world!r})", "hidden": cause,
            "n_trials": len(data.trials),
            "workers": workers,
            "simulation": f"fixed step dt {DT_MS} ms, the fits' and the screening's finite differences at "
                          f"{DIFFERENCE_DT_MS} ms; the runs of each evaluation packed as units of shared NEURON runs "
                          f"(up to {BATCH_UNITS}, trials down to {PACK_SHARE:g} of a run's longest)",
            "baseline_calibration_s": round(t_base, 1), "full_diagnosis_s": round(t_full, 1),
            "named": doc["named"], "target_s": TARGET_S, "within_target": t_full < TARGET_S,
            "load_average_1min": {"before": round(load_before, 2), "after": round(os.getloadavg()[0], 2)}}
