"""``neuromuscle fit``: fit a measured-data file and write a report directory.

    neuromuscle fit DATA.h5 --out DIR [--params CT09] [--free C1,C3] [--workers N] [--staged]

Writes into DIR:

* ``params.json``  the fitted ParameterSet (``neuromuscle simulate --params DIR/params.json`` accepts it),
* ``fit.json``     estimates, standard errors, 95 % intervals, identifiability flags, NRMSE per trial, cost,
* ``summary.md``   the same as a readable table, plus the stages of ``--staged``,
* ``figures/<trial>.png``  measured vs simulated force and the residual, per fitted trial.

Default mode: one :func:`~neuromuscle.fitting.fit` of the ``--free`` parameters (default C1, C2, C3, alpha)
to every stimulated trial in N and mm (or ``--trials``).  ``--staged``: the seed's staged calibration
(:func:`~neuromuscle.calibration.staged_calibration`); the intervals are those of its Module 2 stage, and the
figures/NRMSE use the final parameters.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .calibration import MODULE2_FREE, StagedCalibration, staged_calibration
from .errors import InputError
from .fit import FitProblem, FitResult, SimulationOptions, fit, trial_simulation
from .identification import nrmse_percent
from .measured import MeasuredData, Trial, read_measured
from .parameters import SPECS, ParameterSet, load_parameters


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
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = np.asarray(trial.time_s)
    fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 4.5), gridspec_kw={"height_ratios": [3, 1]})
    ax[0].plot(t, trial.force, color="0.5", lw=1, label="measured")
    ax[0].plot(t, sim, "C0", lw=1.2, label="simulated")
    for s in np.asarray(trial.stimulus_times_s)[:200]:
        ax[0].axvline(s, color="C3", lw=0.3, alpha=0.4)
    ax[0].set_ylabel("force (N)")
    ax[0].legend(fontsize=8)
    ax[0].set_title(f"{trial.trial_id} ({trial.protocol}): NRMSE {nrmse:.2f} %", fontsize=9)
    ax[1].plot(t, sim - trial.force, "k", lw=0.8)
    ax[1].axhline(0, color="0.7", lw=0.5)
    ax[1].set_ylabel("sim - meas (N)")
    ax[1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _safe_name(tid: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in tid)


def run_fit(data_path: str | Path, out_dir: str | Path, *, params: str | Path = "CT09",
            free: Sequence[str] | None = None, trials: Sequence[str] | None = None, workers: int = 1,
            staged: bool = False, dt_ms: float = 0.05, record_dt_ms: float | None = 0.5,
            settle_ms: float = 300.0, max_iterations: int = 30, objective: str = "nrmse",
            progress: bool = False, overwrite: bool = False) -> dict[str, Any]:
    """Fit ``data_path`` (measured-data HDF5) from the parameter set ``params``; write the report into
    ``out_dir`` (see the module docstring); an existing report there is kept unless overwrite.  Returns the
    content of fit.json."""
    existing = [n for n in ("params.json", "fit.json", "summary.md") if (Path(out_dir) / n).exists()]
    if existing and not overwrite:
        raise InputError(f"{out_dir}: already holds {', '.join(existing)}; refusing to overwrite "
                         "(--overwrite replaces them)")
    data = read_measured(data_path)
    base = load_parameters(params)
    free = list(free) if free else list(MODULE2_FREE)
    unknown = [n for n in free if n not in SPECS]
    if unknown:
        raise InputError(f"--free: unknown parameter(s) {unknown}; known: {', '.join(SPECS)}")
    opts = SimulationOptions(dt_ms=dt_ms, record_dt_ms=record_dt_ms, settle_ms=settle_ms)
    chosen, notes = _fit_trials(data, trials)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
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
        result = fit(problem, workers=workers, progress=progress, max_iterations=max_iterations)
        final = ParameterSet(f"{base.name}-fit", result.parameters.values,
                             f"neuromuscle fit {Path(data_path).name} from {base.name}, free {','.join(free)}")
    final.save(out / "params.json")
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
                      "ci95": {k: list(v) for k, v in result.ci95.items()}, "identifiable": result.identifiable,
                      "flags": result.flags, "cost": result.cost, "iterations": result.n_iterations,
                      "simulations": result.n_simulations, "wall_time_s": result.wall_time_s,
                      "message": result.message, "objective": objective, "trials_in_fit": list(result.simulated)}
    if stages is not None:
        doc["stages"] = [{"stage": s.stage, "values": s.values, "errors": s.errors, "data": s.trials,
                          "notes": s.notes, "skipped": s.skipped} for s in stages.stages]
    doc["final_parameters"] = {k: final[k] for k in sorted(set(free) | {
        k for s in (stages.stages if stages else []) for k in s.values if k in SPECS})}
    (out / "fit.json").write_text(json.dumps(doc, indent=1, default=float) + "\n")
    (out / "summary.md").write_text(_markdown(doc, final, result))
    return doc


def _markdown(doc: dict[str, Any], final: ParameterSet, result: FitResult | None) -> str:
    lines = [f"# Fit of `{doc['data']}`", "",
             f"Mode: **{doc['mode']}**, start set {doc['base_parameters']}, free {', '.join(doc['free'])}; "
             f"simulation dt {doc['simulation']['dt_ms']} ms, settle {doc['simulation']['settle_ms']} ms.", ""]
    if result is not None:
        f = doc["fit"]
        lines += [f"## Fitted parameters ({f['iterations']} iterations, {f['simulations']} simulations, "
                  f"{f['wall_time_s']:.1f} s; {f['message']})", "",
                  "| parameter | estimate | unit | SE | 95 % interval | identifiable |", "|---|---|---|---|---|---|"]
        for n in result.free:
            lo, hi = result.ci95[n]
            ok = "yes" if result.identifiable[n] else f"NO: {result.flags[n]}"
            lines.append(f"| {n} | {result.estimates[n]:.6g} | {SPECS[n].unit} | {result.std_errors[n]:.3g} | "
                         f"[{lo:.6g}, {hi:.6g}] | {ok} |")
        lines.append("")
    if "stages" in doc:
        lines += ["## Stages", ""]
        for s in doc["stages"]:
            if s["skipped"]:
                lines.append(f"- **{s['stage']}**: skipped ({s['skipped']})")
                continue
            vals = ", ".join(f"{k} = {v:.6g}" for k, v in s["values"].items())
            errs = ", ".join(f"{k} {v:.4g}" for k, v in s["errors"].items())
            lines.append(f"- **{s['stage']}**: {vals}; errors: {errs}; data: {', '.join(s['data'])}")
        lines.append("")
    lines += ["## NRMSE per trial (eq 17, final parameters)", "", "| trial | NRMSE (%) | figure |", "|---|---|---|"]
    for tid, v in doc["nrmse_percent"].items():
        lines.append(f"| {tid} | {v:.3f} | [{doc['figures'][tid]}]({doc['figures'][tid]}) |")
    if doc["notes"]:
        lines += ["", "## Notes", ""] + [f"- {n}" for n in doc["notes"]]
    lines += ["", f"Parameters: `params.json` (set `{final.name}`); all numbers: `fit.json`.", ""]
    return "\n".join(lines)
