"""``neuromuscle bench diagnose --suite N``: hit and false-alarm rates of the diagnosis on synthetic preparations.

For every canonical cause (``synth.CAUSES``), the out-of-catalogue effect (``synth.OUTSIDE``, expected verdict
"unexplained") and no effect at all ("none"), N preparations are made by ``synth.make_dataset`` (on its extended
protocol set since stop 36; ``protocols="standard"`` for the 28 trials before) with a random realistic strength
(uniform 0.25-1 of the effect's range), noise (uniform 1-2 % of P0) and seed, and diagnosed blind (the truth group
removed).  A hit is the expected verdict with a positive held-out gain (for a cause); a false alarm is a null
preparation given anything but "none"; a wrong name is an effect named as another cause.  The draws come from one
seeded generator, so a suite is reproducible.  Units: %, s.
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import asdict, dataclass
from typing import Any, Sequence

import numpy as np

from ..errors import InputError, NumericalError

#: Strength (fraction of the effect's amplitude range) and noise (% of P0) ranges of the suite's draws.
STRENGTH_RANGE = (0.25, 1.0)
NOISE_PCT_RANGE = (1.0, 2.0)


@dataclass(frozen=True)
class SuiteCase:
    """One preparation of the suite: the hidden effect ("none" for none), its strength (0-1), the noise (% of P0)
    and the dataset seed."""

    cause: str
    strength: float
    noise_pct: float
    seed: int

    @property
    def expected(self) -> str:
        """The verdict a correct diagnosis gives."""
        from ..synth import OUTSIDE

        return "unexplained" if self.cause in OUTSIDE else self.cause


def suite_cases(n_seeds: int, causes: Sequence[str] | None = None, seed: int = 0) -> list[SuiteCase]:
    """n_seeds cases for each of ``causes`` (default: every canonical cause, the out-of-catalogue effects and
    "none"), drawn from one generator seeded by ``seed``.  Every known cause is drawn and the others dropped, so a
    subset gets the same draws as in the whole suite (and the first k seeds of N those of a suite of k)."""
    from ..synth import CAUSES, OUTSIDE

    if isinstance(n_seeds, bool) or not isinstance(n_seeds, int) or n_seeds < 1:
        raise InputError(f"the suite needs an integer number of seeds >= 1, got {n_seeds!r}")
    known = [*CAUSES, *OUTSIDE, "none"]
    names = list(causes) if causes else known
    unknown = [c for c in names if c not in known]
    if unknown:
        raise InputError(f"unknown cause(s) {unknown}; known: {', '.join(known)}")
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_seeds):
        for c in known:
            case = SuiteCase(c, 0.0 if c == "none" else float(rng.uniform(*STRENGTH_RANGE)),
                             float(rng.uniform(*NOISE_PCT_RANGE)), int(rng.integers(0, 2**31 - 1)))
            if c in names:
                out.append(case)
    return out


def _journal(path: str | None, row: dict[str, Any]) -> None:
    """Append one case's record to the journal file as a JSON line (nothing without a journal)."""
    if path is not None:
        with open(path, "a", encoding="utf-8") as fh:
            fh.write(json.dumps(row) + "\n")


def score(results: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Hit rate per cause and overall, false-alarm rate on the nulls, wrong names, from the per-case results
    (each with "cause", "expected", "verdict" and "gain_ok")."""
    per: dict[str, dict[str, int]] = {}
    for r in results:
        p = per.setdefault(r["cause"], {"n": 0, "hits": 0, "wrong_name": 0})
        p["n"] += 1
        hit = r["verdict"] == r["expected"] and (r["expected"] in ("none", "unexplained") or r["gain_ok"])
        p["hits"] += int(hit)
        p["wrong_name"] += int(r["verdict"] not in (r["expected"], "none", "unexplained", "error"))
    effects = [r for r in results if r["cause"] != "none"]
    nulls = [r for r in results if r["cause"] == "none"]
    hits = sum(per[c]["hits"] for c in per if c != "none")
    return {"per_cause": {c: {**p, "hit_rate_pct": round(100.0 * p["hits"] / p["n"], 1)} for c, p in per.items()},
            "hit_rate_pct": round(100.0 * hits / len(effects), 1) if effects else None,
            "false_alarm_rate_pct": (round(100.0 * sum(r["verdict"] not in ("none", "error") for r in nulls)
                                           / len(nulls), 1) if nulls else None),
            "errors": sum(r["verdict"] == "error" for r in results),
            "wrong_name_rate_pct": (round(100.0 * sum(per[c]["wrong_name"] for c in per if c != "none")
                                          / len(effects), 1) if effects else None),
            "targets": {"hit_rate_pct": ">= 90", "false_alarm_rate_pct": "0"}}


def run_suite(n_seeds: int, *, causes: Sequence[str] | None = None, seed: int = 0, workers: int = 2,
              progress: bool = False, journal: str | None = None, first: int = 1,
              protocols: str = "extended") -> dict[str, Any]:
    """Make and diagnose every case of ``suite_cases`` (blind) and return {"cases": [...], **score}; each case
    records its draw, the protocol set, the verdict, the held-out gain of the named extension (if any), each fitted
    candidate's held-out chi-square gain and the rules it failed, every testable extension's screening score, the
    trials still structured under the verdict's model and the wall time (s).  journal: a file to which each case's
    record is appended as one JSON line when it is done (a long suite's finished cases survive an interrupt);
    first: the case (1-based, in ``suite_cases`` order) to start from, to resume an interrupted suite.  protocols:
    synth's protocol set ("extended", the default since stop 36, or "standard"; the draws are the same in both)."""
    from ..diagnose.diagnosis import diagnose_data
    from ..diagnose.verdict import rest_structured
    from ..synth import make_dataset, without_truth

    cases = suite_cases(n_seeds, causes, seed)
    if isinstance(first, bool) or not isinstance(first, int) or not 1 <= first <= len(cases):
        raise InputError(f"the first case must be between 1 and {len(cases)}, got {first!r}")
    results = []
    for k, case in enumerate(cases[first - 1:], first):
        t0 = time.perf_counter()
        data = make_dataset(None if case.cause == "none" else case.cause, case.strength, case.seed,
                            noise_pct=case.noise_pct, workers=workers, protocols=protocols)
        try:
            d = diagnose_data(without_truth(data), workers=workers)
        except (InputError, NumericalError) as e:  # one case's failure is recorded, and the suite goes on
            row = {**asdict(case), "protocols": protocols, "expected": case.expected, "verdict": "error",
                   "error": str(e), "gain_ok": False, "heldout_gain": None,
                   "wall_s": round(time.perf_counter() - t0, 1)}
            results.append(row)
            _journal(journal, row)
            if progress:
                print(f"neuromuscle bench diagnose --suite: {k}/{len(cases)} {case.cause}: ERROR {e}",
                      file=sys.stderr, flush=True)
            continue
        ev = d.evidence.get(d.verdict)
        row = {**asdict(case), "protocols": protocols, "expected": case.expected, "verdict": d.verdict,
               "gain_ok": bool(ev is not None and ev.passed),
               "heldout_gain": None if ev is None else float(ev.chi2_gain),
               "candidates_fitted": {n: e.failed for n, e in d.evidence.items()},
               "candidates_chi2": {n: round(float(e.chi2_gain), 1) for n, e in d.evidence.items()},
               "screening_scores": {n: round(s.score, 1) for n, s in d.screens.items()},
               "structured_trials": list(d.structured_after),
               "rest_structured_trials": rest_structured(d.rest)[0],
               "wall_s": round(time.perf_counter() - t0, 1)}
        results.append(row)
        _journal(journal, row)
        if progress:
            print(f"neuromuscle bench diagnose --suite: {k}/{len(cases)} {case.cause} (strength "
                  f"{case.strength:.2f}, noise {case.noise_pct:.2f} %, seed {case.seed}) -> {d.verdict} "
                  f"({row['wall_s']:.0f} s)", file=sys.stderr, flush=True)
    return {"n_seeds": n_seeds, "seed": seed, "workers": workers, "protocols": protocols, "cases": results,
            **score(results)}


def table_lines(res: dict[str, Any]) -> list[str]:
    """The suite's result as Markdown: per cause n, hits, hit rate, wrong names; then the overall rates."""
    lines = ["| cause | n | hits | hit rate % | named as another cause |", "|---|---|---|---|---|"]
    for c, p in res["per_cause"].items():
        lines.append(f"| {c} | {p['n']} | {p['hits']} | {p['hit_rate_pct']} | {p['wrong_name']} |")
    lines += ["", f"hit rate {res['hit_rate_pct']} % (target >= 90 %), false alarms on nulls "
                  f"{res['false_alarm_rate_pct']} % (target 0), wrong names {res['wrong_name_rate_pct']} %"]
    return lines
