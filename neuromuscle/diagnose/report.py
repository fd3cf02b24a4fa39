"""``neuromuscle diagnose DATA.h5 --out DIR``: run the diagnosis and write what a physiologist reads.

Writes into DIR (refused when DIR already holds a report, unless overwrite; checked before any work):

* ``diagnosis.json``  schema ``neuromuscle.diagnosis/2``: ``verdict`` (the first cause named, or none / unexplained),
  ``named`` (every cause in order, each with its held-out gain over the model before it, then "unexplained" when
  structure remains), every step of the forward selection with its candidates and their evidence, the backward check
  (each cause named before the last one judged against the final model without it; those that fail a rule of
  redundancy are dropped from ``named``), untestable causes, the baseline (parameters, free and held ones,
  convergence, NRMSE per trial), the final model, the split, the noise per trial, the residual structure and the
  decision rules;
* ``report.md``       the causes named first, then each step with its figures, the backward check, the trials' errors,
  the rules;
* ``params.json``     the final model (the baseline plus every cause named); ``neuromuscle simulate --params
  DIR/params.json --no-length-compensation --extension NAME ...`` runs it (the diagnosis's models have eq 18 off
  unless length_dependent_activation is named);
* ``figures/*.png``   measured vs the model before and after each named cause on its deciding held-out trials,
  and the baseline's residual against its best explanatory variable.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..analysis.metrics import nrmse_percent
from ..measured import read_measured
from ..reports.figures import label_axes, legend, mark_times, new_figure, save_figure, set_title
from ..reports.markdown import bullets, link, sig, table
from ..reports.outdir import atomic_path, check_out_dir, prepare_out_dir, write_text
from .diagnosis import ACTIVE_STRUCTURE_RATIO, Diagnosis, diagnose_data, prepare
from .evidence import N_BOOTSTRAP, STRUCTURE_RATIO
from .models import DIFFERENCE_DT_MS, DT_MS, RECORD_DT_MS, FittedModel, extension_class
from .residuals import VARIABLES
from .rules import REDUNDANCY_RULES, RULES
from .selection import Candidate, Step

SCHEMA = "neuromuscle.diagnosis/2"
REPORT_FILES: tuple[str, ...] = ("diagnosis.json", "report.md", "params.json")
#: Figures per named cause.
FIGURES_PER_STEP = 3


def run_diagnosis(data_path: str | Path, out_dir: str | Path, *, heldout: Sequence[str] | None = None,
                  workers: int = 1, overwrite: bool = False, progress: bool = False) -> dict[str, Any]:
    """Diagnose ``data_path`` and write the report into ``out_dir`` (module docstring); returns diagnosis.json's
    content.  Bad input (unusable trials, unknown --split ids, too few trials, an existing report) raises
    InputError before anything is written."""
    check_out_dir(out_dir, overwrite, REPORT_FILES)
    data = read_measured(data_path)
    prepare(data, heldout)
    d = diagnose_data(data, heldout=heldout, workers=workers, progress=progress)
    return write_report(d, data_path, out_dir, overwrite=overwrite)


def write_report(d: Diagnosis, data_path: str | Path, out_dir: str | Path, *,
                 overwrite: bool = False) -> dict[str, Any]:
    """Write a finished diagnosis ``d`` of ``data_path`` into ``out_dir`` (module docstring); returns
    diagnosis.json's content.  An existing report is refused unless overwrite."""
    out = prepare_out_dir(out_dir, overwrite, REPORT_FILES)
    figdir = out / "figures"
    figdir.mkdir(exist_ok=True)
    figures = _figures(d, figdir, out)
    doc = diagnosis_json(d, str(data_path), figures)
    with atomic_path(out / "params.json") as part:
        d.final.parameters.save(part)
    write_text(out / "diagnosis.json", json.dumps(doc, indent=1, default=float) + "\n")
    write_text(out / "report.md", markdown(doc))
    return doc


def _mean_nrmse(d: Diagnosis, sims: dict[str, np.ndarray], ids: Sequence[str]) -> float:
    return float(np.mean([nrmse_percent(d.data.trials[i].force, sims[i]) for i in ids]))


def _parameters(model: FittedModel, name: str) -> dict[str, dict[str, Any]]:
    ext = extension_class(name)
    ci = model.ci95(name)
    return {ext.qualified(p.name): {"value": float(model.parameters[ext.qualified(p.name)]), "unit": p.unit,
                                    "ci95": list(ci[ext.qualified(p.name)]), "neutral": p.neutral}
            for p in ext.parameters}


def _model_json(d: Diagnosis, m: FittedModel) -> dict[str, Any]:
    return {"extensions": list(m.extensions), "free": list(m.free), "start": m.start,
            "start_costs": m.start_costs, "converged": m.converged, "message": m.message,
            "calibration_chi2": m.cost,
            "nrmse_heldout_mean": _mean_nrmse(d, m.simulated, d.split.heldout)}


def _candidate_json(d: Diagnosis, s: Step, c: Candidate) -> dict[str, Any]:
    out: dict[str, Any] = {"name": c.name, "fitted": c.fitted, "untestable": c.untestable,
                           "telling_calibration": c.telling_calibration, "telling_heldout": c.telling_heldout,
                           "screening": c.screen.to_json() if c.screen is not None else None}
    if c.fitted:
        out.update({"evidence": c.evidence.text(), "statistics": c.evidence.to_json(),
                    "parameters": _parameters(c.model, c.name), "model": _model_json(d, c.model),
                    "nrmse_heldout_before": _mean_nrmse(d, s.before.simulated, d.split.heldout),
                    "nrmse_heldout_after": _mean_nrmse(d, c.model.simulated, d.split.heldout),
                    "interval_method": c.model.fit.interval_method if c.model.fit is not None else None})
    elif c.untestable is None and c.screen is not None:
        out["evidence"] = (f"not fitted: linearised calibration chi2 gain {c.screen.gain:.4g} at the model before "
                           f"it, " + ("below its BIC penalty" if c.screen.score <= 0 else "below the fitted ones'"))
    return out


def _named_json(d: Diagnosis, s: Step, name: str) -> dict[str, Any]:
    """Named cause ``name`` of step ``s``: its candidate entry with the evidence that named it (for two causes
    named together, against the model with the other one alone)."""
    c = replace(s.candidates[name], model=s.model_of(name), evidence=s.evidence_of(name))
    out = _candidate_json(d, replace(s, before=s.before_of(name)), c)
    if s.named_jointly:
        out["named_with"] = s.joint.other(name)
    return out


def _causes(d: Diagnosis) -> list[dict[str, Any]]:
    """Every fitted candidate, the named causes first in their order, then the others of the first step by
    score; each with its evidence against the model before it."""
    out, seen = [], set()
    dropped = {c.name for c in d.checks if c.dropped}
    for s in d.steps:
        for n in s.named_causes:
            out.append({**_named_json(d, s, n), "step": s.index, "named": n not in dropped,
                        "dropped": n in dropped})
            seen.add(n)
    first = d.steps[0] if d.steps else None
    if first is not None:
        rest = [c for c in first.candidates.values() if c.fitted and c.name not in seen]
        for c in sorted(rest, key=lambda c: -c.evidence.score):
            out.append({**_candidate_json(d, first, c), "step": first.index, "named": False})
    return out


def _joint_json(d: Diagnosis, s: Step) -> dict[str, Any] | None:
    """The pair fitted together at step ``s`` (none when a candidate passed alone): each one's evidence against
    the model with the other alone."""
    if s.joint is None:
        return None
    j = s.joint
    return {"names": list(j.names), "passed": j.passed, "model": _model_json(d, j.model),
            "evidence": {n: {"beside": j.other(n), "evidence": e.text(), "statistics": e.to_json()}
                         for n, e in j.evidence.items()}}


def diagnosis_json(d: Diagnosis, data_path: str, figures: dict[str, str]) -> dict[str, Any]:
    """The content of diagnosis.json."""
    named = []
    for s in d.steps:
        for n in (n for n in s.named_causes if n in d.causes):
            ev = s.evidence_of(n)
            named.append({"name": n, "step": s.index, "heldout_chi2_gain": ev.chi2_gain,
                          "bic_penalty": ev.bic_penalty, "excess_removed": ev.excess_removed,
                          "nrmse_heldout_before": ev.nrmse_before, "nrmse_heldout_after": ev.nrmse_after})
    b = d.baseline
    first = d.steps[0] if d.steps else None
    return {
        "schema": SCHEMA, "data": data_path, "verdict": d.verdict, "named": d.named, "named_detail": named,
        "causes": _causes(d),
        "steps": [{"step": s.index, "model_before": _model_json(d, s.before), "named": s.named_causes,
                   "candidates": [_candidate_json(d, s, c) for c in s.candidates.values()],
                   "together": _joint_json(d, s)} for s in d.steps],
        "backward_check": [{"name": c.name, "round": c.round, "dropped": c.dropped,
                            "against": list(c.without.extensions), "model": _model_json(d, c.without),
                            "evidence": c.evidence.text(), "statistics": c.evidence.to_json()} for c in d.checks],
        "untestable": ([{"name": c.name, "reason": c.untestable} for c in first.candidates.values() if c.untestable]
                       if first is not None else []),
        "baseline": {"nrmse": {i: nrmse_percent(t.force, b.simulated[i]) for i, t in d.data.trials.items()},
                     "parameters": dict(b.parameters.values), "free": list(b.free), "held": b.held,
                     **_model_json(d, b.model), "notes": b.notes,
                     "stages": [{"stage": st.stage, "values": st.values, "skipped": st.skipped, "data": st.trials,
                                 "notes": st.notes} for st in b.stages]},
        "final": {"extensions": list(d.final.extensions),
                  "nrmse": {i: nrmse_percent(t.force, d.final.simulated[i]) for i, t in d.data.trials.items()}},
        "split": d.split.to_json(),
        "noise": {i: n.to_json() | {"nrmse_floor": 100 * n.sd_N / float(np.ptp(d.data.trials[i].force))}
                  for i, n in d.noise.items()},
        "residual_structure": {"baseline": {"best_variable": d.structure.best_variable, "eta2": d.structure.eta2},
                               "final": {"structured_trials": d.structured_after, "rest_trend_z": d.rest}},
        "rules": [r.to_json() for r in RULES],
        "settings": {"n_bootstrap": N_BOOTSTRAP, "structure_ratio": STRUCTURE_RATIO,
                     "active_structure_ratio": ACTIVE_STRUCTURE_RATIO, "heldout_reach": d.reach},
        "simulation": {"method": "fixed step", "dt_ms": DT_MS, "record_dt_ms": RECORD_DT_MS, "settle_ms": 0.0,
                       "fit_jacobian": "forward differences", "difference_dt_ms": DIFFERENCE_DT_MS},
        "figures": figures, "parameters_file": "params.json", "wall_time_s": d.wall_time_s,
    }


def _safe(tid: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in tid)


def _deciding(d: Diagnosis, s: Step, name: str) -> list[str]:
    """The held-out trials where named cause ``name`` of step ``s`` gained most."""
    before, after = s.before_of(name), s.model_of(name)
    measured = {i: np.asarray(d.data.trials[i].force, dtype=float) for i in d.split.heldout}

    def gain(i: str) -> float:
        e0, e1 = before.simulated[i] - measured[i], after.simulated[i] - measured[i]
        return float(e0 @ e0 - e1 @ e1) / d.noise[i].sd_N ** 2

    return sorted(d.split.heldout, key=lambda i: -gain(i))[:FIGURES_PER_STEP]


def _trial_figure(d: Diagnosis, i: str, models: list[tuple[str, FittedModel]], path: Path) -> None:
    t = d.data.trials[i]
    fig, (ax, axr) = new_figure(2, height_ratios=(3, 1), sharex=True)
    ax.plot(t.time_s, t.force, color="0.5", lw=1, label="measured")
    for k, (label, m) in enumerate(models):
        ax.plot(t.time_s, m.simulated[i], color=f"C{k}", lw=1.1, label=label)
        axr.plot(t.time_s, m.simulated[i] - t.force, color=f"C{k}", lw=0.7)
    axr.axhline(0.0, color="0.7", lw=0.5)
    mark_times(ax, t.stimulus_times_s)
    label_axes(ax, x=None, y="force (N)")
    label_axes(axr, x="time (s)", y="simulated - measured (N)")
    legend(ax)
    side = "held out" if i in d.split.heldout else "calibration"
    set_title(ax, f"{i} ({t.protocol}, {side})",
              "NRMSE " + ", ".join(f"{lab} {nrmse_percent(t.force, m.simulated[i]):.2f} %" for lab, m in models))
    save_figure(fig, path)


def _figures(d: Diagnosis, figdir: Path, out: Path) -> dict[str, str]:
    figures: dict[str, str] = {}
    for s in d.steps:
        for n in s.named_causes:
            for i in _deciding(d, s, n):
                p = figdir / f"step{s.index}_{_safe(n)}_{_safe(i)}.png"
                _trial_figure(d, i, [("before", s.before_of(n)), (f"with {n}", s.model_of(n))], p)
                figures[f"step {s.index} ({n}): {i}"] = str(p.relative_to(out))
    if not any(s.named for s in d.steps):
        worst = sorted(d.split.heldout, key=lambda i: -nrmse_percent(d.data.trials[i].force, d.final.simulated[i]))
        for i in worst[:FIGURES_PER_STEP]:
            p = figdir / f"trial_{_safe(i)}.png"
            _trial_figure(d, i, [("baseline", d.baseline.model)], p)
            figures[i] = str(p.relative_to(out))
    var = d.structure.best_variable
    if var in VARIABLES:
        fig, (ax,) = new_figure(1)
        for k, (i, t) in enumerate(d.data.trials.items()):
            x = d.variables[i][var]
            r = 100.0 * (d.baseline.simulated[i] - t.force) / float(np.ptp(t.force))
            ax.plot(x[::5], r[::5], ".", ms=1.5, color=f"C{k % 10}", label=i if k < 10 else None)
        ax.axhline(0.0, color="0.7", lw=0.5)
        label_axes(ax, x=f"{var.replace('_', ' ')} ({VARIABLES[var]})", y="baseline residual (% of range)")
        legend(ax, small=True)
        set_title(ax, "baseline residual against its best explanatory variable", f"eta2 {d.structure.best_eta2:.2f}")
        p = figdir / f"residual_vs_{var}.png"
        save_figure(fig, p)
        figures["baseline residual"] = str(p.relative_to(out))
    return figures


def _headline(doc: dict[str, Any]) -> list[str]:
    named = doc["named_detail"]
    if not named:
        if doc["verdict"] == "unexplained":
            return ["**Named: unexplained.** Residual structure beyond noise remains that no candidate of the "
                    "catalogue removes.", ""]
        return ["**Named: none.** No candidate's extension beats the baseline on held-out trials beyond noise and "
                "its extra parameters.", ""]
    lines = [f"**Named: {', '.join(doc['named'])}.**", ""]
    for n in named:
        lines.append(f"{n['step']}. **{n['name']}**: held-out NRMSE {n['nrmse_heldout_before']:.2f} -> "
                     f"{n['nrmse_heldout_after']:.2f} % against the model before it; held-out chi2 gain "
                     f"{n['heldout_chi2_gain']:.4g} noise variances (BIC penalty {n['bic_penalty']:.1f}), "
                     f"{100 * n['excess_removed']:.0f} % of the held-out error above noise removed.")
    if "unexplained" in doc["named"]:
        lines.append("Then **unexplained**: structure beyond noise remains after these causes.")
    return lines + [""]


def markdown(doc: dict[str, Any]) -> str:
    """report.md: the causes named first, then each step, the trials' errors, the rules."""
    lines = [f"# Diagnosis of `{doc['data']}`", ""] + _headline(doc)
    ext_args = " ".join(f"--extension {e}" for e in doc["final"]["extensions"])
    lines += [f"Final model: `params.json` (`neuromuscle simulate --params params.json --no-length-compensation "
              f"{ext_args}`; eq 18 is on only when length_dependent_activation is named).", ""]
    for s in doc["steps"]:
        lines += [f"## Step {s['step']}: from {' + '.join(['baseline'] + s['model_before']['extensions'])}", ""]
        lines.append(f"Named: **{', '.join(s['named'])}**" + (" (together)." if len(s["named"]) > 1 else ".")
                     if s["named"] else "Named: nothing (no candidate passes every rule).")
        lines.append("")
        fitted = [c for c in s["candidates"] if c["fitted"]]
        if fitted:
            lines += table(("cause", "held-out NRMSE before (%)", "after (%)", "evidence"),
                           ((c["name"], f"{c['nrmse_heldout_before']:.2f}", f"{c['nrmse_heldout_after']:.2f}",
                             c["evidence"]) for c in fitted))
            lines.append("")
        if s["together"]:
            j = s["together"]
            lines += [f"No candidate passed alone; {' and '.join(j['names'])} fitted together, each against the model "
                      "with the other alone:", ""]
            lines += table(("cause", "beside", "evidence"), ((n, e["beside"], e["evidence"])
                                                             for n, e in j["evidence"].items()))
            lines.append("")
        for c in (c for c in doc["causes"] if (c["named"] or c.get("dropped")) and c["step"] == s["step"]):
            lines += table((f"{c['name']}: parameter", "value", "unit", "95 % interval", "neutral"),
                           ((q, sig(p["value"], 4), p["unit"], f"[{sig(p['ci95'][0], 4)}, {sig(p['ci95'][1], 4)}]",
                             sig(p["neutral"]) if p["neutral"] is not None else "-")
                            for q, p in c["parameters"].items()))
            lines.append("")
        figs = [(k, v) for k, v in doc["figures"].items() if k.startswith(f"step {s['step']} ")]
        if figs:
            lines += bullets(f"{k}: {link(v)}" for k, v in figs) + [""]
    if doc["backward_check"]:
        lines += ["## Backward check", "",
                  "Each cause named before the last one, judged by every rule against the final model without it "
                  f"(refitted): one that fails a rule of redundancy ({', '.join(REDUNDANCY_RULES)}) is dropped as "
                  "made redundant by the causes named after it; the other rules, met when it was named, are "
                  "reported but do not drop it.", ""]
        lines += table(("round", "cause", "against", "outcome", "evidence"),
                       ((str(c["round"]), c["name"], " + ".join(["baseline"] + c["against"]),
                         "dropped" if c["dropped"] else "kept", c["evidence"]) for c in doc["backward_check"]))
        lines.append("")
    if doc["untestable"]:
        lines += ["Untestable with these data:", ""] + bullets(f"{u['name']}: {u['reason']}"
                                                               for u in doc["untestable"]) + [""]
    b = doc["baseline"]
    lines += ["## Baseline", "",
              f"Free: {', '.join(b['free'])}. Held: " + ("; ".join(f"{k} ({v})" for k, v in b["held"].items())
                                                           or "none") + ".",
              f"Fitted from the {b['start']} ({'converged' if b['converged'] else 'NOT converged: ' + b['message']}).",
              ""]
    lines += ["## Trials", "", f"Split: {doc['split']['method']}.", ""]
    final = doc["final"]["nrmse"]
    rows = []
    for i, v in b["nrmse"].items():
        side = "held out" if i in doc["split"]["heldout"] else "calibration"
        rows.append((i, side, f"{doc['noise'][i]['nrmse_floor']:.2f}", f"{v:.2f}", f"{final[i]:.2f}"))
    lines += table(("trial", "side", "noise floor NRMSE (%)", "baseline NRMSE (%)", "final NRMSE (%)"), rows)
    other = [(k, v) for k, v in doc["figures"].items() if not k.startswith("step ")]
    if other:
        lines += ["", "## Figures", ""] + bullets(f"{k}: {link(v)}" for k, v in other)
    lines += ["", "## Decision rules", "", "A cause is named only when it passes every rule:", ""]
    lines += table(("rule", "name", "what must hold"), ((r["id"], r["name"], r["statement"]) for r in doc["rules"]))
    lines += ["", f"Simulation: fixed step {doc['simulation']['dt_ms']} ms; wall time {doc['wall_time_s']:.0f} s.", ""]
    return "\n".join(lines)
