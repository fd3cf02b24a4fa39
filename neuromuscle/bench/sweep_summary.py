"""Records and summary of the parameter sweep (``neuromuscle bench sweep``); plain data, no NEURON.

A run record is one protocol of one draw under one integrator: its status ("ok"; "exception"; "budget_stop",
CVODE spent its budget; "nonfinite"; "timeout", the draw's process was killed; "died", its process ended), its
wall time (s), peak and minimum force (N) and count of non-finite samples.  A comparison is the largest
fixed-vs-CVODE force difference of one protocol of one draw, in % of the larger peak.
"""

from __future__ import annotations

import re
from collections import Counter
from typing import Any, Iterable

import numpy as np

from ..reports.markdown import bullets, sig, table

#: Largest accepted fixed-vs-CVODE difference (% of peak).
TOLERANCE_PCT = 1.0
#: Statuses that count as a hang: CVODE's budget stopped the run, or the draw's process-level timeout did.
HANG_STATUSES = ("budget_stop", "timeout")
#: How many examples of each kind of problem the summary lists.
EXAMPLES = 10


def error_status(message: str) -> str:
    """The status of a run that raised ``message``: "budget_stop" for a Simulator budget, "nonfinite" for the
    package's non-finite check, else "exception"."""
    if "budget of" in message and "reached only" in message:
        return "budget_stop"
    if "non-finite" in message:
        return "nonfinite"
    return "exception"


def run_record(draw: int, protocol: str, method: str, duration_ms: float, wall_s: float, *,
               force_N: np.ndarray | None = None, error: BaseException | str | None = None,
               status: str | None = None, t_reached_ms: float | None = None,
               warnings: Iterable[str] = ()) -> dict[str, Any]:
    """The record of one run: from its force trace (N) when it ran, else from the exception it raised (with
    t_reached_ms, ms, the time a budget stop reached), or from the pool's message (str) and ``status``
    ("timeout", "died") for a draw whose process was killed or ended."""
    rec: dict[str, Any] = {"draw": draw, "protocol": protocol, "method": method, "duration_ms": duration_ms,
                           "wall_s": wall_s, "status": "ok", "error": None, "t_reached_ms": None,
                           "peak_N": None, "min_N": None, "n_nonfinite": 0, "warnings": list(warnings)}
    if isinstance(error, BaseException):
        rec["error"] = f"{type(error).__name__}: {error}"
        rec["status"] = error_status(str(error))
        rec["t_reached_ms"] = t_reached_ms if rec["status"] == "budget_stop" else None
    elif error is not None:
        rec["status"], rec["error"] = status, error
    if force_N is not None:
        f = np.asarray(force_N, dtype=float)
        finite = f[np.isfinite(f)]
        rec["n_nonfinite"] = int(f.size - finite.size)
        rec["peak_N"] = float(finite.max()) if finite.size else None
        rec["min_N"] = float(finite.min()) if finite.size else None
        if rec["n_nonfinite"]:
            rec["status"] = "nonfinite"
    return rec


def fixed_vs_cvode_pct(fixed_N: np.ndarray, cvode_N: np.ndarray) -> float:
    """Largest |fixed - CVODE| force difference in % of the larger peak (both sampled at the same times, N);
    NaN where either trace is not finite."""
    a, b = np.asarray(fixed_N, dtype=float), np.asarray(cvode_N, dtype=float)
    if a.shape != b.shape or not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return float("nan")
    diff = float(np.max(np.abs(a - b)))
    peak = float(max(a.max(), b.max()))
    return 0.0 if diff == 0.0 else (100.0 * diff / peak if peak > 0.0 else float("inf"))


def comparison(draw: int, protocol: str, fixed_N: np.ndarray, cvode_N: np.ndarray) -> dict[str, Any]:
    """The comparison record of one protocol of one draw: the difference (% of peak) and the peak (N)."""
    return {"draw": draw, "protocol": protocol, "pct": fixed_vs_cvode_pct(fixed_N, cvode_N),
            "peak_N": float(np.nanmax(np.concatenate([fixed_N, cvode_N])))}


#: The problems a run can show, each a test of its record.
PROBLEMS = {"exceptions": lambda r: r["status"] in ("exception", "died"),
            "hangs": lambda r: r["status"] in HANG_STATUSES,
            "nonfinite": lambda r: r["status"] == "nonfinite",
            "negative_force": lambda r: r["min_N"] is not None and r["min_N"] < 0.0}
LABELS = {"exceptions": "exceptions", "hangs": "hangs (budget stops, timeouts)", "nonfinite": "non-finite values",
          "negative_force": "negative force"}


def _stats(values: list[float]) -> dict[str, float | int]:
    v = np.asarray(values, dtype=float)
    if not v.size:
        return {"n": 0}
    return {"n": int(v.size), "p50": float(np.percentile(v, 50)), "p90": float(np.percentile(v, 90)),
            "p99": float(np.percentile(v, 99)), "max": float(v.max())}


def _where(rec: dict[str, Any]) -> dict[str, Any]:
    keys = ("draw", "protocol", "method", "duration_ms", "wall_s", "t_reached_ms", "error", "min_N", "peak_N")
    return {k: rec[k] for k in keys if k in rec}


def _masked(message: str) -> str:
    """An error message with its numbers masked, so that the same failure in different draws groups together."""
    return re.sub(r"[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", "#", message.splitlines()[0])[:200]


def _per_protocol(runs: list[dict[str, Any]], scored: list[dict[str, Any]], tolerance_pct: float) -> dict[str, Any]:
    """Per protocol: percentiles of the fixed-vs-CVODE difference (% of peak), how many exceed the tolerance, and
    how many runs show each problem."""
    out: dict[str, Any] = {}
    for name in dict.fromkeys([r["protocol"] for r in runs] + [c["protocol"] for c in scored]):  # in run order
        pct = [c["pct"] for c in scored if c["protocol"] == name]
        mine = [r for r in runs if r["protocol"] == name]
        out[name] = {"fixed_vs_cvode_pct": _stats(pct), "n_over_tolerance": int(sum(x > tolerance_pct for x in pct)),
                     **{k: int(sum(map(test, mine))) for k, test in PROBLEMS.items()}}
    return out


def summarise(runs: list[dict[str, Any]], comparisons: list[dict[str, Any]], *, seed: int, n_draws: int,
              n_refused: int = 0, n_runs_expected: int | None = None,
              tolerance_pct: float = TOLERANCE_PCT) -> dict[str, Any]:
    """The sweep's summary: counts of runs with exceptions, hangs (budget stops and timeouts, with the time
    reached), non-finite values and negative force, with their draws and examples; the worst fixed-vs-CVODE
    difference (% of peak) with its draw and protocol; per protocol, percentiles of that difference and counts of
    each problem; wall time (s) per run; and ``failures``, one line per broken check (empty when all passed)."""
    problems = {k: [r for r in runs if test(r)] for k, test in PROBLEMS.items()}
    scored = [c for c in comparisons if np.isfinite(c["pct"])]
    over = sorted((c for c in scored if c["pct"] > tolerance_pct), key=lambda c: -c["pct"])
    causes = Counter(_cause(c) for c in over)
    unexplained = [c for c in over if _cause(c) == "unexplained"]
    worst = max(comparisons, key=lambda c: c["pct"] if not np.isnan(c["pct"]) else np.inf, default=None)
    walls = [r for r in runs if r["wall_s"] is not None]
    slowest = max(walls, key=lambda r: r["wall_s"], default=None)
    summary: dict[str, Any] = {
        "seed": seed, "n_draws": n_draws, "n_runs": len(runs), "n_runs_expected": n_runs_expected,
        "n_refused_sets": n_refused, **{k: len(v) for k, v in problems.items()},
        "worst_fixed_vs_cvode_pct": None if worst is None else
        {k: worst.get(k) for k in ("pct", "draw", "protocol", "peak_N")},
        "tolerance_pct": tolerance_pct, "n_over_tolerance": len(over),
        "over_tolerance_by_cause": dict(causes.most_common()),
        "worst_unexplained_pct": None if not unexplained else
        {k: unexplained[0].get(k) for k in ("pct", "draw", "protocol", "peak_N")},
        "worst_by_cause": _worst_by_cause(over),
        "per_protocol": _per_protocol(runs, scored, tolerance_pct),
        "wall_s": {"median": float(np.median([r["wall_s"] for r in walls])) if walls else None,
                   "max": None if slowest is None else slowest["wall_s"],
                   "slowest": None if slowest is None else _where(slowest),
                   **{m: _stats([r["wall_s"] for r in walls if r["method"] == m]) for m in ("fixed", "cvode")}},
        "status_by_method": {m: dict(Counter(r["status"] for r in runs if r["method"] == m))
                             for m in ("fixed", "cvode")},
        "exceptions_by_class": dict(Counter(_masked(r["error"]) for r in problems["exceptions"]).most_common()),
        "draws_with": {**{k: sorted({r["draw"] for r in v}) for k, v in problems.items()},
                       "over_tolerance": sorted({c["draw"] for c in over})},
        "examples": {**{k: [_where(r) for r in v[:EXAMPLES]] for k, v in problems.items()},
                     "over_tolerance": over[:EXAMPLES]},
    }
    summary["failures"] = failures(summary)
    return summary


def _cause(comparison_record: dict[str, Any]) -> str:
    """The cause ``sweep_explain`` gave an over-tolerance comparison ("unexplained" when it was not examined)."""
    return comparison_record.get("explained", {}).get("cause", "unexplained")


def _worst_by_cause(over: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """The largest over-tolerance comparison of each cause (``over`` sorted largest first), with its evidence."""
    out: dict[str, dict[str, Any]] = {}
    for c in over:
        out.setdefault(_cause(c), {k: c.get(k) for k in ("pct", "draw", "protocol", "peak_N", "explained")})
    return out


def failures(summary: dict[str, Any]) -> list[str]:
    """One line per broken check of a summary: exceptions, hangs, non-finite values, negative force, a
    fixed-vs-CVODE difference above the tolerance, missing runs or comparisons."""
    out = []
    for key, what in (("exceptions", "run(s) raised"), ("hangs", "run(s) hung (budget stop or timeout)"),
                      ("nonfinite", "run(s) gave non-finite values"),
                      ("negative_force", "run(s) gave negative force")):
        if summary[key]:
            out.append(f"{summary[key]} {what}")
    worst, unexplained = summary["worst_fixed_vs_cvode_pct"], summary["worst_unexplained_pct"]
    if worst is None:
        out.append("no fixed-vs-CVODE comparison")
    elif not np.isfinite(worst["pct"]):
        out.append(f"fixed vs CVODE differ by {worst['pct']} % of peak (draw {worst['draw']}, {worst['protocol']}): "
                   "a trace was not finite")
    elif not worst["pct"] <= summary["tolerance_pct"] and unexplained is not None:
        n = summary["over_tolerance_by_cause"].get("unexplained", 0)
        out.append(f"{n} unexplained fixed-vs-CVODE difference(s) above {summary['tolerance_pct']:g} % of peak, "
                   f"the largest {unexplained['pct']:.3g} % (draw {unexplained['draw']}, {unexplained['protocol']})")
    if summary["n_runs_expected"] is not None and summary["n_runs"] != summary["n_runs_expected"]:
        out.append(f"{summary['n_runs']} runs recorded of {summary['n_runs_expected']} expected")
    return out


def markdown(summary: dict[str, Any]) -> list[str]:
    """The summary as Markdown lines: a table of the checks, a table per protocol, and the failures."""
    w, wall = summary["worst_fixed_vs_cvode_pct"], summary["wall_s"]
    tol = f"{summary['tolerance_pct']:g} %"
    n_cmp = sum(p["fixed_vs_cvode_pct"]["n"] for p in summary["per_protocol"].values())
    worst = "none" if w is None else (f"{sig(w['pct'])} % of peak (draw {w['draw']}, {w['protocol']}, peak "
                                      f"{sig(w['peak_N'])} N)")
    lines = table(["check", "result"], [
        ["draws (sets refused and redrawn)", f"{summary['n_draws']} ({summary['n_refused_sets']})"],
        ["runs recorded (expected)", f"{summary['n_runs']} ({summary['n_runs_expected']})"],
        *[[LABELS[k], f"{summary[k]} runs in {len(summary['draws_with'][k])} draws"] for k in PROBLEMS],
        ["worst fixed-vs-CVODE difference", worst],
        [f"comparisons over {tol}", f"{summary['n_over_tolerance']} of {n_cmp} in "
                                    f"{len(summary['draws_with']['over_tolerance'])} draws"],
        ["their causes (sweep_explain)", ", ".join(f"{k} {v}" for k, v in summary["over_tolerance_by_cause"].items())
         or "none"],
        ["wall time per run, median / max (s)",
         f"{sig(wall['median'])} / {sig(wall['max'])} (median fixed {sig(wall['fixed'].get('p50'))}, CVODE "
         f"{sig(wall['cvode'].get('p50'))})"],
    ])
    rows = [[name, " / ".join(sig(p["fixed_vs_cvode_pct"].get(q)) for q in ("p50", "p90", "p99", "max")),
             p["n_over_tolerance"], *(p[k] for k in PROBLEMS)] for name, p in summary["per_protocol"].items()]
    lines += [""] + table(["protocol", "fixed vs CVODE, % of peak: p50 / p90 / p99 / max", f"over {tol}",
                           *(LABELS[k] for k in PROBLEMS)], rows)
    return lines + [""] + (bullets(summary["failures"]) if summary["failures"] else ["All checks passed."])
