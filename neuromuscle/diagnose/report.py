"""``neuromuscle diagnose DATA.h5 --out DIR``: run the diagnosis and write what a physiologist reads.

Writes into DIR (refused when DIR already holds a report, unless overwrite; checked before any work):

* ``diagnosis.json``  schema ``neuromuscle.diagnosis/1``: verdict, ranked causes with evidence, fitted extension
  parameters with 95 % intervals and test statistics, untestable causes, baseline NRMSE per trial, the split,
  noise per trial, the residual structure, the decision rule;
* ``report.md``       the verdict first, the trials' held-out error before and after, candidates, figures;
* ``params.json``     the model of the verdict (the named cause's fit, else the reference); ``neuromuscle
  simulate --params DIR/params.json [--extension NAME]`` accepts it;
* ``figures/*.png``   measured vs baseline vs extended for the trials that decide, residuals against their best
  explanatory variable.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..analysis.metrics import nrmse_percent
from ..calibration import MODULE2_FREE
from ..measured import read_measured
from ..parameters import SPECS, ParameterSet
from ..reports.figures import label_axes, legend, mark_times, new_figure, save_figure, set_title
from ..reports.markdown import bullets, link, sig, table
from ..reports.outdir import atomic_path, check_out_dir, prepare_out_dir, write_text
from . import verdict as rule
from .baseline import DT_MS, MAX_TRAIN_S
from .diagnosis import Diagnosis, diagnose_data, prepare
from .extension_fit import JACOBIAN_DT_MS
from .residuals import VARIABLES
from .screening import COLUMN_DT_MS

SCHEMA = "neuromuscle.diagnosis/1"
REPORT_FILES: tuple[str, ...] = ("diagnosis.json", "report.md", "params.json")
MAX_FIGURES = 4


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
        _final_parameters(d).save(part)
    write_text(out / "diagnosis.json", json.dumps(doc, indent=1, default=float) + "\n")
    write_text(out / "report.md", markdown(doc))
    return doc


def _final_parameters(d: Diagnosis) -> ParameterSet:
    """The verdict's model: the named cause's fit, else the reference."""
    return d.fits[d.verdict].parameters if d.verdict in d.fits else d.reference.parameters


def _mean_nrmse(d: Diagnosis, sims: dict[str, np.ndarray], ids: Sequence[str]) -> float:
    return float(np.mean([nrmse_percent(d.data.trials[i].force, sims[i]) for i in ids]))


def _cause_entries(d: Diagnosis) -> list[dict[str, Any]]:
    before = _mean_nrmse(d, d.reference.simulated, d.split.heldout)
    fitted = sorted(d.fits, key=lambda n: (not d.evidence[n].passed, -d.evidence[n].whole_file_score))
    entries = []
    for n in fitted:
        f, ev = d.fits[n], d.evidence[n]
        entries.append({
            "name": n, "evidence": ev.text(), "fitted": True,
            "parameters": {q: {"value": v, "unit": SPECS[q].unit, "ci95": list(f.ci95[q]), "neutral": f.neutral[q]}
                           for q, v in f.extension_values.items()},
            "refitted_baseline": {k: f.fit.estimates[k] for k in f.fit.estimates if k not in f.extension_values},
            "interval_method": f.fit.interval_method,
            "nrmse_heldout_before": before, "nrmse_heldout_after": _mean_nrmse(d, f.simulated, d.split.heldout),
            "statistics": ev.to_json(),
            "telling_heldout": next(c.telling_heldout for c in d.candidates if c.cause.name == n)})
    for c in d.candidates:
        if c.untestable is None and c.cause.name not in d.fits:
            sc = d.screens.get(c.cause.name)
            at = ", ".join(f"{q.split('.')[-1]} {v:.3g}" for q, v in (sc.time_constants if sc else {}).items())
            why = ("no extension in the catalogue" if sc is None else
                   f"linearised chi2 gain at the reference {sc.gain:.4g}{f' (at {at})' if at else ''} " +
                   (f"<= its BIC penalty {sc.penalty:.3g}" if sc.score <= 0 else "below the fitted ones'"))
            entries.append({"name": c.cause.name, "fitted": False, "parameters": {},
                            "evidence": f"testable but not fitted ({why}); residual score {c.score:.3g}",
                            "nrmse_heldout_before": before, "nrmse_heldout_after": before})
    return entries


def diagnosis_json(d: Diagnosis, data_path: str, figures: dict[str, str]) -> dict[str, Any]:
    """The content of diagnosis.json."""
    final = d.final_simulated
    return {
        "schema": SCHEMA, "data": data_path, "verdict": d.verdict,
        "causes": _cause_entries(d),
        "untestable": [{"name": c.cause.name, "reason": c.untestable} for c in d.candidates if c.untestable],
        "ranking": [{"name": c.cause.name, "score": c.score, "eta2": c.eta2, "excess_share": c.excess_share,
                     "variable": c.cause.variable,
                     **({"screening": d.screens[c.cause.name].to_json()} if c.cause.name in d.screens else {})}
                    for c in d.candidates],
        "baseline": {"nrmse": d.baseline.nrmse, "parameters": dict(d.baseline.parameters.values),
                     "stages": [{"stage": s.stage, "values": s.values, "skipped": s.skipped, "data": s.trials,
                                 "notes": s.notes} for s in d.baseline.stages]},
        "reference": {
            "what": "the baseline with Module 2, Umax and tau2 refitted on every calibration trial; the candidates' "
                    "held-out NRMSE before and gains are measured against it",
            "module2": {k: d.reference.fit.estimates[k] for k in MODULE2_FREE},
            "Umax_M_per_ms": d.reference.fit.estimates.get("Umax"),
            "tau2_ms": d.reference.fit.estimates.get("tau2"),
            "nrmse": {i: nrmse_percent(t.force, d.reference.simulated[i]) for i, t in d.data.trials.items()}},
        "final": {"nrmse": {i: nrmse_percent(t.force, final[i]) for i, t in d.data.trials.items()}},
        "split": d.split.to_json(),
        "noise": {i: n.to_json() | {"nrmse_floor": 100 * n.sd_N / float(np.ptp(d.data.trials[i].force))}
                  for i, n in d.noise.items()},
        "residual_structure": {"baseline": {"best_variable": d.structure.best_variable,
                                            "eta2": d.structure.eta2},
                               "after_verdict": {"structured_trials": d.structured_after,
                                                 "best_variable": d.structure_after.best_variable,
                                                 "eta2": d.structure_after.eta2,
                                                 "rest_trend_z": d.rest,
                                                 "rest_structured_trials": rule.rest_structured(d.rest)[0]}},
        "decision_rule": {"n_bootstrap": rule.N_BOOTSTRAP, "min_excess_removed": rule.MIN_EXCESS_REMOVED,
                          "min_excess_removed_diffuse": rule.MIN_EXCESS_REMOVED_DIFFUSE,
                          "structure_ratio": rule.STRUCTURE_RATIO,
                          "active_structure_ratio": rule.ACTIVE_STRUCTURE_RATIO, "rest_z": rule.REST_Z,
                          "min_structured_trials": rule.MIN_STRUCTURED_TRIALS,
                          "min_structured_fraction": rule.MIN_STRUCTURED_FRACTION,
                          "text": " ".join(rule.__doc__.split())},
        "simulation": {"method": "fixed step", "dt_ms": DT_MS, "record_dt_ms": d.baseline.options.record_dt_ms,
                       "settle_ms": d.baseline.options.settle_ms, "baseline_max_train_s": MAX_TRAIN_S,
                       "fit_jacobian_dt_ms": JACOBIAN_DT_MS, "screening_dt_ms": COLUMN_DT_MS},
        "figures": figures, "parameters_file": "params.json", "wall_time_s": d.wall_time_s,
    }


def _deciding_trials(d: Diagnosis) -> tuple[str | None, list[str]]:
    """The candidate shown (the verdict, else the best-ranked fitted one) and its deciding held-out trials."""
    name = d.verdict if d.verdict in d.fits else next(iter(sorted(d.fits, key=lambda n: -d.evidence[n].chi2_gain)),
                                                       None)
    if name is None:
        worst = sorted(d.split.heldout, key=lambda i: -d.baseline.nrmse[i])
        return None, worst[:MAX_FIGURES]
    telling = next(c.telling_heldout for c in d.candidates if c.cause.name == name)
    return name, (telling or list(d.split.heldout))[:MAX_FIGURES]


def _safe(tid: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in tid)


def _figures(d: Diagnosis, figdir: Path, out: Path) -> dict[str, str]:
    name, ids = _deciding_trials(d)
    figures: dict[str, str] = {}
    for i in ids:
        t = d.data.trials[i]
        fig, (ax, axr) = new_figure(2, height_ratios=(3, 1), sharex=True)
        ax.plot(t.time_s, t.force, color="0.5", lw=1, label="measured")
        ax.plot(t.time_s, d.baseline.simulated[i], color="C0", lw=1.1, label="baseline")
        axr.plot(t.time_s, d.baseline.simulated[i] - t.force, color="C0", lw=0.7)
        if name is not None:
            ax.plot(t.time_s, d.fits[name].simulated[i], color="C3", lw=1.1, label=f"with {name}")
            axr.plot(t.time_s, d.fits[name].simulated[i] - t.force, color="C3", lw=0.7)
        axr.axhline(0.0, color="0.7", lw=0.5)
        mark_times(ax, t.stimulus_times_s)
        label_axes(ax, x=None, y="force (N)")
        label_axes(axr, x="time (s)", y="simulated - measured (N)")
        legend(ax)
        set_title(ax, f"{i} ({t.protocol}, held out)", f"baseline NRMSE {d.baseline.nrmse[i]:.2f} %")
        p = figdir / f"trial_{_safe(i)}.png"
        save_figure(fig, p)
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
        figures["residual"] = str(p.relative_to(out))
    return figures


def markdown(doc: dict[str, Any]) -> str:
    """report.md: the verdict first, then the trials' errors, the causes and their evidence, the figures."""
    v = doc["verdict"]
    fitted = [c for c in doc["causes"] if c.get("fitted")]
    lines = [f"# Diagnosis of `{doc['data']}`", ""]
    if v in ("none", "unexplained"):
        head = ("**Verdict: none.** No candidate's extension beats the baseline on held-out trials beyond noise and "
                "its extra parameters" if v == "none" else
                "**Verdict: unexplained.** Residual structure beyond noise remains that no candidate removes")
        s = doc["residual_structure"]["after_verdict"]
        lines += [head + ".", ""]
        if s["structured_trials"]:
            lines += [f"Trials with residual RMS above {rule.STRUCTURE_RATIO} x noise: "
                      f"{', '.join(s['structured_trials'])}; the residual follows "
                      f"**{s['best_variable'].replace('_', ' ')}** most (eta^2 "
                      f"{s['eta2'].get(s['best_variable'], 0.0):.2f}).", ""]
        if s.get("rest_structured_trials"):
            lines += [f"Trials whose force trends in time (|z| > {rule.REST_Z}) where the model's muscle is quiet "
                      f"(isometric, before the first stimulus or after relaxation; no muscle parameter acts there): "
                      f"{', '.join(s['rest_structured_trials'])}.", ""]
    else:
        c = next(c for c in fitted if c["name"] == v)
        lines += [f"**Verdict: {v}.** Held-out NRMSE {c['nrmse_heldout_before']:.2f} % -> "
                  f"{c['nrmse_heldout_after']:.2f} % (mean over held-out trials).", "", f"Evidence: {c['evidence']}.",
                  ""]
        rivals = [r for r in fitted if r["name"] != v and r["statistics"]["passed"]]
        if rivals:
            scores = "; ".join(f"{e['name']} {e['statistics']['whole_file_score']:.1f}" for e in [c, *rivals])
            lines += [f"Also passing every rule: {', '.join(r['name'] for r in rivals)}. The verdict is the passing "
                      f"candidate that fits the whole file best (held-out plus calibration chi2 gain, each less its "
                      f"BIC penalty): {scores}.", ""]
        lines += table(("parameter", "value", "unit", "95 % interval", "neutral"),
                       ((q, sig(p["value"], 4), p["unit"], f"[{sig(p['ci95'][0], 4)}, {sig(p['ci95'][1], 4)}]",
                         sig(p["neutral"])) for q, p in c["parameters"].items()))
        lines += ["", f"Model: `params.json` (`neuromuscle simulate --params params.json --extension {v}`).", ""]
    lines += ["## Trials", "", f"Split: {doc['split']['method']}.", ""]
    final = doc["final"]["nrmse"]
    rows = []
    for i, b in doc["baseline"]["nrmse"].items():
        side = "held out" if i in doc["split"]["heldout"] else "calibration"
        rows.append((i, side, f"{doc['noise'][i]['nrmse_floor']:.2f}", f"{b:.2f}", f"{final[i]:.2f}"))
    lines += table(("trial", "side", "noise floor NRMSE (%)", "baseline NRMSE (%)",
                    f"{'with ' + v if v in [c['name'] for c in fitted] else 'final'} NRMSE (%)"), rows)
    lines += ["", "## Candidates", ""]
    lines += table(("cause", "held-out NRMSE before (%)", "after (%)", "evidence"),
                   ((c["name"], f"{c['nrmse_heldout_before']:.2f}", f"{c['nrmse_heldout_after']:.2f}", c["evidence"])
                    for c in doc["causes"]))
    if doc["untestable"]:
        lines += ["", "Untestable with these data:", ""] + bullets(f"{u['name']}: {u['reason']}"
                                                                   for u in doc["untestable"])
    lines += ["", "## Figures", ""] + bullets(f"{k}: {link(p)}" for k, p in doc["figures"].items())
    lines += ["", "## Decision rule", "", doc["decision_rule"]["text"], "",
              f"Simulation: fixed step {doc['simulation']['dt_ms']} ms; wall time {doc['wall_time_s']:.0f} s.", ""]
    return "\n".join(lines)
