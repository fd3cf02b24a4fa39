"""``neuromuscle bench diagnose``: wall time of one full diagnosis of a synthetic file of a world (by default a null
of world B: the extended protocol set, 36 trials; ``cause`` hides one catalogue cause in it) with 2 workers, and of
its baseline calibration alone, with the machine's load average before and after.  A file with a cause costs more
than a null: every step fits candidates, and a world with eq 18 names it besides.

Beside each wall time, the CPU time of this process and of its worker processes: on a shared host the wall time of
one run varies with the other load by a tenth or more, while the CPU the diagnosis needs varies less, so two
versions are compared by both."""

from __future__ import annotations

import os
import resource
import tempfile
import time
from pathlib import Path
from typing import Any

#: The full diagnosis's target on 2 workers (s).
TARGET_S = 180.0


def cpu_seconds() -> dict[str, float]:
    """CPU time (s, user + system) used so far by this process ("main") and by its child processes that have ended
    and been waited for ("workers": a diagnosis's worker processes, once its pool has closed)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"main": own.ru_utime + own.ru_stime, "workers": kids.ru_utime + kids.ru_stime}


def cpu_between(before: dict[str, float], after: dict[str, float], wall_s: float,
                workers: int) -> dict[str, float]:
    """The CPU time (s) spent between two :func:`cpu_seconds` readings, by process kind, and the workers' share
    busy: their CPU time over ``workers`` x ``wall_s`` (1.0: every worker busy for the whole wall time)."""
    used = {k: round(after[k] - before[k], 1) for k in before}
    used["workers_busy"] = round((after["workers"] - before["workers"]) / (workers * wall_s), 3) if wall_s > 0 else 0.0
    return used


def bench_diagnose(workers: int = 2, world: str = "B", cause: str | None = None,
                   strength: float = 0.7) -> dict[str, Any]:
    """Wall times (s) of the baseline calibration alone and of the full diagnosis (report written to a temporary
    folder) of the preparation of seed 0 in ``world`` (a null, or hiding ``cause`` at ``strength``, 0-1 of its
    range), with the file's trial count, what was named, the simulation settings, the CPU time of each part
    (:func:`cpu_between`) and the load average (1 min) before and after."""
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
        c0, t0 = cpu_seconds(), time.perf_counter()
        with TrialPool(list(data.trials.values()), workers) as pool:
            calibrate_baseline(data, describe_all(data.trials), split.calibration, load_parameters("CT09"), pool=pool)
        t_base = time.perf_counter() - t0
        c1, t0 = cpu_seconds(), time.perf_counter()
        doc = run_diagnosis(path, Path(tmp) / "report", workers=workers)
        t_full = time.perf_counter() - t0
        c2 = cpu_seconds()
    hidden = f"{cause!r}, strength {strength:g}" if cause else "None"
    return {"data": f"neuromuscle.synth.make_dataset({hidden}, seed 0, world {world!r})", "hidden": cause,
            "n_trials": len(data.trials),
            "workers": workers,
            "simulation": f"fixed step dt {DT_MS} ms, the fits' and the screening's finite differences at "
                          f"{DIFFERENCE_DT_MS} ms; the runs of each evaluation packed as units of shared NEURON runs "
                          f"(up to {BATCH_UNITS}, trials down to {PACK_SHARE:g} of a run's longest)",
            "baseline_calibration_s": round(t_base, 1), "full_diagnosis_s": round(t_full, 1),
            "baseline_calibration_cpu_s": cpu_between(c0, c1, t_base, workers),
            "full_diagnosis_cpu_s": cpu_between(c1, c2, t_full, workers),
            "named": doc["named"], "target_s": TARGET_S, "within_target": t_full < TARGET_S,
            "load_average_1min": {"before": round(load_before, 2), "after": round(os.getloadavg()[0], 2)}}
