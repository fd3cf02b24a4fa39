"""Rule R8's share under different groupings of the held-out trials, from a journal that logged each held-out
trial's sums: the table "One size per kind of trial" in docs/validation/diagnosis.md.

R8 resizes the contributions D_k (one column per resizable cause named before the candidate) of the causes before a
candidate and asks the candidate to keep half of its held-out chi-square gain beyond that resize
(``neuromuscle.diagnose.resize``).  The least squares need only each held-out trial's sums: with r_k the residual of
the model before and d_k the candidate's change of the force, D'D, D'r, D'd, r'r, r'd and d'd, and the trial's
chi-square weight w.  A group of trials shares one size per cause; its sums are the w-weighted sums of its trials'.

Groupings: every trial its own (``trial``), the trial's protocol label (``protocol``), how the length moves while
stimulated (``kind``: isometric, ramps, other movement; the package's grouping, read here from the protocol labels
of ``neuromuscle synth``), and one size for all (``one``).

The journal's rows (``neuromuscle bench diagnose`` rows) carry, for each candidate judged beside a resizable cause,
``resize_stats``: {trial: {"w", "protocol", "DD", "Dr", "Dd", "rr", "rd", "dd"}}.

Run from the repository root:
    python docs/validation/r8_groupings.py docs/validation/journals/r8-kinds-logged-0.4.44.jsonl.gz
Prints Markdown: one row for every candidate that failed R8 and at most one other rule.
"""

from __future__ import annotations

import argparse
import gzip
import json
from typing import Any, Callable, Mapping

import numpy as np
from scipy.optimize import lsq_linear

RAMPS = {"isokinetic", "stretch_hold", "shorten_hold"}
MOVEMENT = {"random_length", "cyclic_length", "step"}


def left(rr: float, dr: np.ndarray, dd: np.ndarray) -> float:
    """min over b >= -1 of |r - D b|^2, from r'r, D'r and D'D."""
    if dd.size == 0 or not np.any(dd):
        return rr
    s, v = np.linalg.eigh(dd)
    keep = s > 1e-12 * s.max()
    a = np.sqrt(s[keep])[:, None] * v[:, keep].T
    y = (v[:, keep].T @ dr) / np.sqrt(s[keep])
    sol = lsq_linear(a, y, bounds=(np.full(a.shape[1], -1.0), np.inf))
    e = a @ sol.x - y
    return float(rr - y @ y + e @ e)


def beyond(stats: Mapping[str, Mapping[str, Any]], key: Callable[[str, Mapping[str, Any]], str]) -> float:
    """The candidate's chi-square gain beyond a resize with one size per cause and group of ``key``."""
    groups: dict[str, list[Mapping[str, Any]]] = {}
    for trial, s in stats.items():
        groups.setdefault(key(trial, s), []).append(s)
    out = 0.0
    for members in groups.values():
        def total(name: str, members: list[Mapping[str, Any]] = members) -> Any:
            return sum(s["w"] * np.asarray(s[name], dtype=float) for s in members)
        rr, dr, dd = float(total("rr")), total("Dr"), total("DD")
        r2 = rr - 2.0 * float(total("rd")) + float(total("dd"))
        out += left(rr, dr, dd) - left(r2, dr - total("Dd"), dd)
    return out


def kind(protocol: str) -> str:
    return "ramps" if protocol in RAMPS else "movement" if protocol in MOVEMENT else "isometric"


GROUPINGS: dict[str, Callable[[str, Mapping[str, Any]], str]] = {
    "trial": lambda trial, s: trial,
    "protocol": lambda trial, s: s["protocol"],
    "kind": lambda trial, s: kind(s["protocol"]),
    "one": lambda trial, s: "all",
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("journals", nargs="+")
    args = ap.parse_args()
    print("| world | hidden | step | candidate | other rule failed | held-out chi2 gain | " + " | ".join(GROUPINGS)
          + " |")
    print("|---|---|---|---|---|---|" + "---|" * len(GROUPINGS))
    for path in args.journals:
        with (gzip.open if path.endswith(".gz") else open)(path, "rt", encoding="utf-8") as fh:
            for line in fh:
                row = json.loads(line)
                for k, step in enumerate(row["steps"], start=1):
                    for name, ev in step["candidates"].items():
                        stats = ev.get("resize_stats")
                        if not stats or "R8" not in ev["failed"] or len(ev["failed"]) > 2 or ev["chi2_gain"] <= 0:
                            continue
                        shares = [f"{100 * beyond(stats, g) / ev['chi2_gain']:.0f} %" for g in GROUPINGS.values()]
                        other = ", ".join(r for r in ev["failed"] if r != "R8") or "-"
                        print(f"| {row['world']} | {row['label'].replace('_', ' ')} | {k} | "
                              f"{name.replace('_', ' ')} | {other} | {ev['chi2_gain']:.0f} | "
                              + " | ".join(shares) + " |")


if __name__ == "__main__":
    main()
