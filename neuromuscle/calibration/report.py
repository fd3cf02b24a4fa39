"""``neuromuscle fit``: fit a measured-data file and write a report directory.

    neuromuscle fit DATA.h5 --out DIR [--params CT09] [--free C1,C3] [--workers N] [--staged]

Writes into DIR:

* ``params.json``  the fitted ParameterSet (``neuromuscle simulate --params DIR/params.json`` accepts it),
* ``fit.json``     estimates, standard errors, 95 % intervals and how they were made (``interval_method``,
  ``interval_method_text``, ``numerical_bias``), identifiability flags, NRMSE per trial, cost,
* ``summary.md``   the same as a readable table naming the interval method, plus the stages of ``--staged``,
* ``figures/<trial>.png``  measured vs simulated force and the residual, per fitted trial.

Default mode: one :func:`~neuromuscle.fit.fit` of the ``--free`` parameters (default C1, C2, C3, alpha)
to every stimulated trial in N and mm (or ``--trials``).  ``--staged``: the staged calibration of Kim et al. 2015
(:func:`~neuromuscle.calibration.staged_calibration`); the intervals are those of its Module 2 stage, and the
figures/NRMSE use the final parameters.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..fit import INTERVAL_METHODS, FitProblem, FitResult, SimulationOptions, describe_method, fit, trial_simulation
from ..analysis.metrics import nrmse_percent
from ..measured import MeasuredData, Trial, read_measured
from ..parameters import SPECS, ParameterSet, load_parameters
from ..reports.figures import fit_figure, legend, mark_times, save_figure, set_title
from ..reports.markdown import bullets, interval, link, sig, table
from ..reports.outdir import atomic_path, check_out_dir, prepare_out_dir, write_text
from .module2 import MODULE2_FREE
from .staged import StagedCalibration, staged_calibration

#: The files whose presence in ``out_dir`` means a report is there (kept unless overwrite).
REPORT_FILES: tuple[str, ...] = ("params.json", "fit.json", "summary.md")


def _fit_trials(data: MeasuredData, ids: Sequence[str] | None) -> tuple[list[Trial], list[str]]:
    """The trials to fit and notes on the ones left out."""
    if ids:
        missing = [i for i in ids if i not in data.trials]
        if missing:
            raise InputError(f"--trials: {missing} not in the file (have: {', '.join(data.trials)})")
        return [data.trials[i] for i in ids], []
    chosen, notes = [], []
    for t in data.trials.values():
        if t.force_unit != "N" or t.length_unit != "mm":
            notes.append(f"trial '{t.trial_id}' left out: {t.force_unit}/{t.length_unit}, the model needs N/mm")
        elif np.size(t.stimulus_times_s) == 0:
            notes.append(f"trial '{t.trial_id}' left out: no stimulus times")
        else:
            chosen.append(t)
    if not chosen:
        raise InputError("no trial to fit: none is in N and mm with stimulus times (" + "; ".join(notes) + ")")
    return chosen, notes


def _plot_trial(trial: Trial, sim: np.ndarray, nrmse: float, path: Path) -> None:
    fig, ax = fit_figure(trial.time_s, trial.force, sim, x="time (s)", y="force (N)",
                         residual_y="simulated - measured (N)")
    mark_times(ax[0], trial.stimulus_times_s)
    legend(ax[0])
    set_title(ax[0], f"{trial.trial_id} ({trial.protocol})", f"NRMSE {nrmse:.2f} %")
    save_figure(fig, path)


def _safe_name(tid: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in tid)


def run_fit(data_path: str | Path, out_dir: str | Path, *, params: str | Path = "CT09",
            free: Sequence[str] | None = None, trials: Sequence[str] | None = None, workers: int = 1,
            staged: bool = False, dt_ms: float = 0.05, record_dt_ms: float | None = 0.5,
            settle_ms: float = 300.0, max_iterations: int = 30, objective: str = "nrmse",
            intervals: str = INTERVAL_METHODS[0], progress: bool = False,
            overwrite: bool = False) -> dict[str, Any]:
    """Fit ``data_path`` (measured-data HDF5) from the parameter set ``params``; write the report into
    ``out_dir`` (see the module docstring); an existing report there is kept unless overwrite.  intervals: the
    fit's interval method (``neuromuscle.fit.INTERVAL_METHODS``).  ``trials`` and a non-default ``intervals`` apply to
    the default fit only: with ``staged`` they are refused (InputError).  Returns the content of fit.json."""
    check_out_dir(out_dir, overwrite, REPORT_FILES)
    if staged and trials:
        raise InputError("--trials chooses the trials of the default fit; the staged calibration takes each stage's "
                         "trials from the file itself (give one or the other)")
    if staged and intervals != INTERVAL_METHODS[0]:
        raise InputError(f"--intervals applies to the default fit; the staged calibration's intervals are its "
                         f"Module 2 stage's ({INTERVAL_METHODS[0]})")
    data = read_measured(data_path)
    base = load_parameters(params)
    free = list(free) if free else list(MODULE2_FREE)
    unknown = [n for n in free if n not in SPECS]
    if unknown:
        raise InputError(f"--free: unknown parameter(s) {unknown}; known: {', '.join(SPECS)}")
    opts = SimulationOptions(dt_ms=dt_ms, record_dt_ms=record_dt_ms, settle_ms=settle_ms)
    chosen, notes = _fit_trials(data, trials)
    out = prepare_out_dir(out_dir, overwrite, REPORT_FILES)
    stages: StagedCalibration | None = None
    result: FitResult | None = None
    if staged:
        stages = staged_calibration(data, base, module2_free=free, options=opts, workers=workers,
                                    max_iterations=max_iterations, progress=progress,
                                    name=f"{base.name}-fit")
        final = stages.parameters
        m2 = [s for s in stages.stages if s.stage == "module2" and s.fit is not None]
        result = m2[0].fit if m2 else None
    else:
        problem = FitProblem(chosen, base, free, objective=objective, options=opts)
        result = fit(problem, workers=workers, progress=progress, max_iterations=max_iterations,
                     intervals=intervals)
        final = ParameterSet(f"{base.name}-fit", result.parameters.values,
                             f"neuromuscle fit {Path(data_path).name} from {base.name}, free {','.join(free)}")
    with atomic_path(out / "params.json") as part:
        final.save(part)
    sims: dict[str, np.ndarray] = {}
    for t in chosen:
        if not staged and result is not None:
            sims[t.trial_id] = result.simulated[t.trial_id]
        else:
            sims[t.trial_id] = trial_simulation(final, t, dt_ms, record_dt_ms=record_dt_ms, settle_ms=settle_ms)
    nrmse = {tid: nrmse_percent(data.trials[tid].force, s) for tid, s in sims.items()}
    figdir = out / "figures"
    figdir.mkdir(exist_ok=True)
    figures = {}
    for t in chosen:
        p = figdir / f"{_safe_name(t.trial_id)}.png"
        _plot_trial(t, sims[t.trial_id], nrmse[t.trial_id], p)
        figures[t.trial_id] = str(p.relative_to(out))
    doc: dict[str, Any] = {
        "data": str(data_path), "base_parameters": base.name, "mode": "staged" if staged else "fit",
        "free": free, "trials": [t.trial_id for t in chosen], "notes": notes,
        "simulation": {"dt_ms": dt_ms, "record_dt_ms": record_dt_ms, "settle_ms": settle_ms},
        "nrmse_percent": nrmse, "figures": figures, "parameters_file": "params.json",
    }
    if result is not None:
        doc["fit"] = {"estimates": result.estimates, "std_errors": result.std_errors,
                      "ci95": {k: list(v) for k, v in result.ci95.items()},
                      "interval_method": result.interval_method,
                      "interval_method_text": describe_method(result.interval_method),
                      "numerical_bias": result.uncertainty.numerical_bias, "identifiable": result.identifiable,
                      "flags": result.flags, "cost": result.cost, "iterations": result.n_iterations,
                      "simulations": result.n_simulations, "wall_time_s": result.wall_time_s,
                      "message": result.message, "objective": objective, "trials_in_fit": list(result.simulated)}
    if stages is not None:
        doc["stages"] = [{"stage": s.stage, "values": s.values, "errors": s.errors, "data": s.trials,
                          "notes": s.notes, "skipped": s.skipped} for s in stages.stages]
    doc["final_parameters"] = {k: final[k] for k in sorted(set(free) | {
        k for s in (stages.stages if stages else []) for k in s.values if k in SPECS})}
    write_text(out / "fit.json", json.dumps(doc, indent=1, default=float) + "\n")
    write_text(out / "summary.md", _markdown(doc, final, result))
    return doc


def _markdown(doc: dict[str, Any], final: ParameterSet, result: FitResult | None) -> str:
    lines = [f"# Fit of `{doc['data']}`", "",
             f"Mode: **{doc['mode']}**, start set {doc['base_parameters']}, free {', '.join(doc['free'])}; "
             f"simulation dt {doc['simulation']['dt_ms']} ms, settle {doc['simulation']['settle_ms']} ms.", ""]
    if result is not None:
        f = doc["fit"]
        lines += [f"## Fitted parameters ({f['iterations']} iterations, {f['simulations']} simulations, "
                  f"{f['wall_time_s']:.1f} s; {f['message']})", "",
                  f"Intervals (`{f['interval_method']}`): {f['interval_method_text']}.", ""]
        lines += table(("parameter", "estimate", "unit", "SE", "integrator bias", "95 % interval", "identifiable"),
                       ((n, sig(result.estimates[n], 6), SPECS[n].unit, sig(result.std_errors[n]),
                         sig(f["numerical_bias"][n]), interval(*result.ci95[n]),
                         "yes" if result.identifiable[n] else f"NO: {result.flags[n]}")
                        for n in result.free))
        lines.append("")
    if "stages" in doc:
        lines += ["## Stages", ""]
        lines += bullets(_stage_line(s) for s in doc["stages"])
        lines.append("")
    lines += ["## NRMSE per trial (eq 17, final parameters)", ""]
    lines += table(("trial", "NRMSE (%)", "figure"),
                   ((tid, f"{v:.3f}", link(doc["figures"][tid])) for tid, v in doc["nrmse_percent"].items()))
    if doc["notes"]:
        lines += ["", "## Notes", ""] + bullets(doc["notes"])
    lines += ["", f"Parameters: `params.json` (set `{final.name}`); all numbers: `fit.json`.", ""]
    return "\n".join(lines)


def _stage_line(stage: dict[str, Any]) -> str:
    if stage["skipped"]:
        return f"**{stage['stage']}**: skipped ({stage['skipped']})"
    vals = ", ".join(f"{k} = {sig(v, 6)}" for k, v in stage["values"].items())
    errs = ", ".join(f"{k} {sig(v, 4)}" for k, v in stage["errors"].items())
    return f"**{stage['stage']}**: {vals}; errors: {errs}; data: {', '.join(stage['data'])}"
