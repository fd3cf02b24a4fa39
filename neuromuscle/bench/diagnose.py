"""``neuromuscle bench diagnose``: wall time of one full diagnosis of a synthetic null file (synth's standard
protocol set, 28 trials, or with ``--protocols extended`` its extended one, 34) with 2 workers, and of its baseline
calibration alone.

The file comes from ``neuromuscle.synth.make_dataset`` when that module exists; until then from the diagnosis
tests' generator (``tests/diagnose/diagnose_datasets.py`` of a source checkout; a null preparation, seed 0), and
the result says which.
"""

from __future__ import annotations

import importlib.util
import tempfile
import time
from pathlib import Path
from typing import Any

from ..errors import InputError


def standard_data(protocols: str = "standard") -> tuple[Any, str]:
    """The synthetic null preparation of seed 0 on synth's protocol set ``protocols`` and where it came from."""
    try:
        from ..synth import make_dataset  # type: ignore[attr-defined]
        return (make_dataset("none", 0.0, 0, protocols=protocols),
                f"neuromuscle.synth.make_dataset('none', 0, seed 0, protocols={protocols!r})")
    except ImportError:
        path = Path(__file__).resolve().parents[2] / "tests" / "diagnose" / "diagnose_datasets.py"
        if not path.is_file():
            raise InputError(f"bench diagnose needs neuromuscle.synth or a source checkout with {path}") from None
        spec = importlib.util.spec_from_file_location("diagnose_datasets", path)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)  # type: ignore[union-attr]
        return mod.make_data(0, standard=True), f"{path.name} make_data(0, standard=True) (synth not yet merged)"


def bench_diagnose(workers: int = 2, protocols: str = "standard") -> dict[str, Any]:
    """Wall times (s) of the baseline calibration alone and of the full diagnosis (report written to a temporary
    folder), with the file's trial count, the verdict and the simulation settings."""
    from ..diagnose import run_diagnosis
    from ..diagnose.baseline import DT_MS, SETTLE_MS, calibrate_baseline
    from ..diagnose.diagnosis import prepare
    from ..diagnose.extension_fit import JACOBIAN_DT_MS
    from ..diagnose.screening import COLUMN_DT_MS
    from ..fit.evaluate import BATCH_UNITS
    from ..measured import write_measured
    from ..parameters import load_parameters

    data, source = standard_data(protocols)
    with tempfile.TemporaryDirectory() as tmp:
        path = write_measured(Path(tmp) / "standard.h5", data)
        split = prepare(data)
        t0 = time.perf_counter()
        calibrate_baseline(data, split.calibration, load_parameters("CT09"), workers=workers)
        t_base = time.perf_counter() - t0
        t0 = time.perf_counter()
        doc = run_diagnosis(path, Path(tmp) / "report", workers=workers)
        t_full = time.perf_counter() - t0
    return {"data": source, "n_trials": len(data.trials), "workers": workers,
            "simulation": f"fixed step dt {DT_MS} ms (0.27 % twitch-peak error vs SciPy, below 1-2 % noise), "
                          f"{SETTLE_MS:g} ms settling (the model starts at rest); the "
                          f"screening's finite differences at {COLUMN_DT_MS} ms and the fits' Jacobians at "
                          f"{JACOBIAN_DT_MS} ms (the step's error cancels in the differences); the runs of one "
                          f"trial under several parameter sets batched as units of one NEURON run (up to "
                          f"{BATCH_UNITS}; each unit's force bit for bit its own run's)",
            "baseline_calibration_s": round(t_base, 1), "full_diagnosis_s": round(t_full, 1),
            "verdict": doc["verdict"], "target_s": 180.0, "within_target": t_full < 180.0}
