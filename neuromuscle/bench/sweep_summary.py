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


def summarise(runs: list[dict[str, Any]], comparisons: list[dict[str, Any]], *, seed: int, n_draws: int,
              n_refused: int = 0, n_runs_expected: int | None = None,
              tolerance_pct: float = TOLERANCE_PCT) -> dict[str, Any]:
    """The sweep's summary: counts of exceptions, hangs (budget stops and timeouts, with the time reached),
    non-finite and negative-force runs, each with examples; the worst fixed-vs-CVODE difference (% of peak) with
    its draw and protocol, percentiles of that difference per protocol; wall time (s) per run; and ``failures``,
    one line per broken check (empty when the sweep passed)."""
    exceptions = [r for r in runs if r["status"] in ("exception", "died")]
    hangs = [r for r in runs if r["status"] in HANG_STATUSES]
    nonfinite = [r for r in runs if r["status"] == "nonfinite"]
    negative = [r for r in runs if r["min_N"] is not None and r["min_N"] < 0.0]
    scored = [c for c in comparisons if np.isfinite(c["pct"])]
    worst = max(comparisons, key=lambda c: c["pct"] if not np.isnan(c["pct"]) else np.inf, default=None)
    by_protocol: dict[str, list[float]] = {}
    for c in scored:
        by_protocol.setdefault(c["protocol"], []).append(c["pct"])
    walls = [r for r in runs if r["wall_s"] is not None]
    slowest = max(walls, key=lambda r: r["wall_s"], default=None)
    summary: dict[str, Any] = {
        "seed": seed, "n_draws": n_draws, "n_runs": len(runs), "n_runs_expected": n_runs_expected,
        "n_refused_sets": n_refused,
        "exceptions": len(exceptions), "hangs": len(hangs), "nonfinite": len(nonfinite),
        "negative_force": len(negative),
        "worst_fixed_vs_cvode_pct": None if worst is None else
        {"pct": worst["pct"], "draw": worst["draw"], "protocol": worst["protocol"]},
        "tolerance_pct": tolerance_pct,
        "fixed_vs_cvode_pct": {p: {**_stats(v), "n_over_tolerance": int(sum(x > tolerance_pct for x in v))}
                               for p, v in sorted(by_protocol.items())},
        "wall_s": {"median": float(np.median([r["wall_s"] for r in walls])) if walls else None,
                   "max": None if slowest is None else slowest["wall_s"],
                   "slowest": None if slowest is None else _where(slowest),
                   **{m: _stats([r["wall_s"] for r in walls if r["method"] == m]) for m in ("fixed", "cvode")}},
        "exceptions_by_class": dict(Counter(_masked(r["error"]) for r in exceptions).most_common()),
        "status_by_method": {m: dict(Counter(r["status"] for r in runs if r["method"] == m)) for m in ("fixed", "cvode")},
        "draws_with": {"exceptions": sorted({r["draw"] for r in exceptions}), "hangs": sorted({r["draw"] for r in hangs}),
                       "nonfinite": sorted({r["draw"] for r in nonfinite}),
                       "negative_force": sorted({r["draw"] for r in negative}),
                       "over_tolerance": sorted({c["draw"] for c in scored if c["pct"] > tolerance_pct})},
        "examples": {"exceptions": [_where(r) for r in exceptions[:EXAMPLES]],
                     "hangs": [_where(r) for r in hangs[:EXAMPLES]],
                     "nonfinite": [_where(r) for r in nonfinite[:EXAMPLES]],
                     "negative_force": [_where(r) for r in negative[:EXAMPLES]],
                     "over_tolerance": sorted((c for c in scored if c["pct"] > tolerance_pct),
                                              key=lambda c: -c["pct"])[:EXAMPLES]},
    }
    summary["failures"] = failures(summary)
    return summary


def failures(summary: dict[str, Any]) -> list[str]:
    """One line per broken check of a summary: exceptions, hangs, non-finite values, negative force, a
    fixed-vs-CVODE difference above the tolerance, missing runs or comparisons."""
    out = []
    for key, what in (("exceptions", "run(s) raised"), ("hangs", "run(s) hung (budget stop or timeout)"),
                      ("nonfinite", "run(s) gave non-finite values"), ("negative_force", "run(s) gave negative force")):
        if summary[key]:
            out.append(f"{summary[key]} {what}")
    worst = summary["worst_fixed_vs_cvode_pct"]
    if worst is None:
        out.append("no fixed-vs-CVODE comparison")
    elif not worst["pct"] <= summary["tolerance_pct"]:
        out.append(f"fixed vs CVODE differ by {worst['pct']:.3g} % of peak (draw {worst['draw']}, "
                   f"{worst['protocol']}), above {summary['tolerance_pct']:g} %")
    if summary["n_runs_expected"] is not None and summary["n_runs"] != summary["n_runs_expected"]:
        out.append(f"{summary['n_runs']} runs recorded of {summary['n_runs_expected']} expected")
    return out
