"""``neuromuscle bench diagnose --suite N``: how often the diagnosis names the hidden causes of synthetic
preparations, per cause and per world, and how often it names something that is not there.

For every world asked (``neuromuscle.synth.worlds``), every canonical cause, the out-of-catalogue effect
(expected: "unexplained") and no effect ("none"), N preparations are made by ``synth.make_dataset`` with a random
realistic strength (uniform 0.25-1 of the effect's range), noise (uniform over the world's range, % of P0) and
seed; ``--two-effect K`` adds K preparations per world that carry two different causes at once.  Each is diagnosed
blind (the truth group removed).  A file of a world whose model has eq 18 carries ``length_dependent_activation``
beside its hidden effects (``World.background_causes``).

Scores (``score``), from each case's ``named`` list:

* a hidden cause is **hit** when it is named, with a passing held-out gain;
* a **wrong name** is a named cause that is neither hidden, nor in the world's background, nor allowed by it
  (``World.allowed_causes``), or "unexplained" beside a catalogue effect;
* a null is a **false alarm** when it names anything beyond the world's background;
* a two-effect file scores **both named** when both of its causes are.

``--journal FILE`` appends each finished case to FILE as a JSON line; ``--score FILE ...`` scores the cases of one or
more journals as one suite (:func:`score_journals`: runs split over processes, seeds or sessions), refusing a case
that appears twice.

Each case also records how close the baseline comes to the data: every held-out trial's residual RMS under the
baseline over the true noise sd (1 at the noise floor; the baseline of a null of world B should stay within 1.25).

The draws come from one generator per world, seeded by the suite seed and the world's name, so a suite is
reproducible and adding a world does not change another's draws.  Units: %, s.
"""

from __future__ import annotations

import gzip
import json
import sys
import time
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..errors import InputError, NumericalError

if TYPE_CHECKING:
    from ..diagnose.evidence import Evidence

#: Strength (fraction of the effect's amplitude range) of the suite's draws.
STRENGTH_RANGE = (0.25, 1.0)
#: The per-world row of the nulls: "named" counts those that name nothing beyond the world's background.
NULL_ROW = "none (nothing beyond the background)"


@dataclass(frozen=True)
class SuiteCase:
    """One preparation of the suite: its world, hidden effects ((name, strength 0-1), none for a null), noise (% of
    P0) and dataset seed."""

    world: str
    effects: tuple[tuple[str, float], ...]
    noise_pct: float
    seed: int

    @property
    def label(self) -> str:
        return "+".join(n for n, _ in self.effects) or "none"

    def expected(self) -> dict[str, list[str]]:
        """What a right diagnosis names: "required" (the hidden catalogue causes and the world's background),
        "allowed" (also acceptable) and whether "unexplained" is expected (an out-of-catalogue effect)."""
        from ..synth import OUTSIDE
        from ..synth.worlds import world

        w = world(self.world)
        hidden = [n for n, _ in self.effects if n not in OUTSIDE]
        outside = [n for n, _ in self.effects if n in OUTSIDE]
        required = list(dict.fromkeys(hidden + list(w.background_causes)))
        return {"required": required, "allowed": list(w.allowed_causes),
                "unexplained": ["unexplained"] if outside else []}


def _rng(seed: int, world_name: str) -> np.random.Generator:
    return np.random.default_rng([seed, zlib.crc32(world_name.encode())])


def suite_cases(n_seeds: int, causes: Sequence[str] | None = None, seed: int = 0,
                worlds: Sequence[str] = ("B",), two_effect: int = 0) -> list[SuiteCase]:
    """n_seeds cases for each of ``causes`` (default: every canonical cause, the out-of-catalogue effects and
    "none") in each of ``worlds``, then ``two_effect`` two-cause cases per world; drawn from one generator per world
    (module docstring).  Every known cause is drawn and the others dropped, so a subset gets the same draws as
    the whole suite, and the first k seeds of N those of a suite of k."""
    from ..synth import CAUSES, OUTSIDE
    from ..synth.worlds import world

    if isinstance(n_seeds, bool) or not isinstance(n_seeds, int) or n_seeds < 0:
        raise InputError(f"the suite needs an integer number of seeds >= 0, got {n_seeds!r}")
    if isinstance(two_effect, bool) or not isinstance(two_effect, int) or two_effect < 0:
        raise InputError(f"--two-effect must be an integer >= 0, got {two_effect!r}")
    known = [*CAUSES, *OUTSIDE, "none"]
    names = list(causes) if causes else known
    unknown = [c for c in names if c not in known]
    if unknown:
        raise InputError(f"unknown cause(s) {unknown}; known: {', '.join(known)}")
    out = []
    for wname in worlds:
        w = world(wname)
        rng = _rng(seed, w.name)
        for _ in range(n_seeds):
            for c in known:
                effects = () if c == "none" else ((c, float(rng.uniform(*STRENGTH_RANGE))),)
                case = SuiteCase(w.name, effects, float(rng.uniform(*w.noise_pct)), int(rng.integers(0, 2**31 - 1)))
                if c in names:
                    out.append(case)
        pair_rng = np.random.default_rng([seed, zlib.crc32(w.name.encode()), 2])
        catalogue = sorted(CAUSES)
        for _ in range(two_effect):
            a, b = pair_rng.choice(len(catalogue), size=2, replace=False)
            effects = tuple((catalogue[k], float(pair_rng.uniform(*STRENGTH_RANGE))) for k in sorted((a, b)))
            out.append(SuiteCase(w.name, effects, float(pair_rng.uniform(*w.noise_pct)),
                                 int(pair_rng.integers(0, 2**31 - 1))))
    return out


def _journal(path: str | None, row: dict[str, Any]) -> None:
    """Append one case's record to the journal file as a JSON line (nothing without a journal)."""
    if path is not None:
        with open(path, "a", encoding="utf-8") as fh:
            fh.write(json.dumps(row) + "\n")


def judge_case(case: SuiteCase, named: Sequence[str], passed: Sequence[str]) -> dict[str, Any]:
    """The case's score from the causes ``named`` (in order, maybe "unexplained") and those among them named with
    a passing held-out gain (``passed``)."""
    exp = case.expected()
    ok = set(exp["required"]) | set(exp["allowed"]) | set(exp["unexplained"])
    hidden = [n for n, _ in case.effects if n in exp["required"]]
    hits = {n: n in passed for n in hidden}
    wrong = [n for n in named if n not in ok]
    is_null = not case.effects
    background = set(exp["required"]) - set(hidden)
    return {"hits": hits, "wrong_names": wrong,
            "background_named": {n: n in named for n in background},
            "false_alarm": bool(is_null and [n for n in named if n not in set(exp["required"]) | set(exp["allowed"])]),
            "expected_unexplained": bool(exp["unexplained"]),
            "unexplained_hit": bool(exp["unexplained"]) and "unexplained" in named,
            "both_named": (all(hits.values()) if len(case.effects) == 2 else None)}


#: The counts of each world's summary in :func:`score`.
WORLD_COUNTS = ("hidden_causes", "hidden_named", "files_with_a_wrong_name", "nulls", "false_alarms",
                "two_effect_files", "both_named")


def score(results: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Hit rates per world and cause, per world (``worlds``: hidden causes named, files with a wrong name, false
    alarms, two-effect files with both causes named), per cause over the worlds (``causes``) and overall, from the
    per-case results (each with "world", "effects" and "score")."""
    per: dict[str, dict[str, dict[str, int]]] = {}
    worlds: dict[str, dict[str, int]] = {}
    causes: dict[str, dict[str, int]] = {}
    nulls = fa = wrong_files = effects_files = 0
    pairs = both = 0
    for r in results:
        if r.get("error"):
            continue
        s = r["score"]
        w = per.setdefault(r["world"], {})
        ws = worlds.setdefault(r["world"], dict.fromkeys(WORLD_COUNTS, 0))
        ws["hidden_causes"] += len(s["hits"])
        ws["hidden_named"] += sum(map(bool, s["hits"].values()))
        for n, hit in s["hits"].items():
            for p in (w.setdefault(n, {"n": 0, "hits": 0}), causes.setdefault(n, {"n": 0, "hits": 0})):
                p["n"] += 1
                p["hits"] += int(hit)
        for n, hit in s["background_named"].items():
            p = w.setdefault(f"{n} (background)", {"n": 0, "hits": 0})
            p["n"] += 1
            p["hits"] += int(hit)
        if s["expected_unexplained"]:
            p = w.setdefault("unexplained (outside the catalogue)", {"n": 0, "hits": 0})
            p["n"] += 1
            p["hits"] += int(s["unexplained_hit"])
        if not r["effects"]:
            nulls += 1
            fa += int(s["false_alarm"])
            ws["nulls"] += 1
            ws["false_alarms"] += int(s["false_alarm"])
            p = w.setdefault(NULL_ROW, {"n": 0, "hits": 0})
            p["n"] += 1
            p["hits"] += int(not s["false_alarm"])
        else:
            effects_files += 1
            wrong_files += int(bool(s["wrong_names"]))
            ws["files_with_a_wrong_name"] += int(bool(s["wrong_names"]))
        if s["both_named"] is not None:
            pairs += 1
            both += int(s["both_named"])
            ws["two_effect_files"] += 1
            ws["both_named"] += int(s["both_named"])
    hidden = [(n, hit) for r in results if not r.get("error") for n, hit in r["score"]["hits"].items()]

    def pct(a: int, b: int) -> float | None:
        return round(100.0 * a / b, 1) if b else None

    return {"per_world": {w: {c: {**p, "hit_rate_pct": pct(p["hits"], p["n"])} for c, p in cs.items()}
                          for w, cs in per.items()},
            "worlds": {w: {**c, "hit_rate_pct": pct(c["hidden_named"], c["hidden_causes"])} for w, c in worlds.items()},
            "causes": {n: {**c, "hit_rate_pct": pct(c["hits"], c["n"])} for n, c in sorted(causes.items())},
            "hidden_causes": len(hidden), "hidden_named": sum(h for _, h in hidden),
            "hit_rate_pct": pct(sum(h for _, h in hidden), len(hidden)),
            "nulls": nulls, "false_alarms": fa, "false_alarm_rate_pct": pct(fa, nulls),
            "files_with_a_wrong_name": wrong_files, "wrong_name_file_rate_pct": pct(wrong_files, effects_files),
            "two_effect_files": pairs, "both_named": both, "both_named_pct": pct(both, pairs),
            "errors": sum(bool(r.get("error")) for r in results),
            "targets": {"hit_rate_pct": ">= 90, no wrong name", "false_alarms": "0",
                        "both_named_pct": ">= 80"}}


def _rounded(value: float | None, digits: int = 1) -> float | None:
    return None if value is None else round(value, digits)


def _evidence_row(ev: Evidence) -> dict[str, Any]:
    """A candidate's evidence in a suite row: gains (held-out and calibration), excess, window with its bootstrap,
    and the rules it failed with why."""
    return {"chi2_gain": round(ev.chi2_gain, 1), "calibration_chi2_gain": round(ev.calibration_chi2_gain, 1),
            "score": round(ev.score, 1), "excess": round(ev.excess, 1),
            "excess_removed": round(ev.excess_removed, 3),
            "share_of_baseline_excess": _rounded(ev.share_of_baseline_excess, 3),
            "window": ev.window_how, "window_chi2_gain": _rounded(ev.window_chi2_gain),
            "window_p05": _rounded(ev.window_p05),
            "quiet_chi2_gain": _rounded(ev.quiet_chi2_gain), "quiet_p05": _rounded(ev.quiet_p05),
            "structured_before": len(ev.structured_before), "failed": sorted(ev.failed), "why": dict(ev.failed),
            "cross_validated_trials": list(ev.crossed),
            "beyond_resize_chi2_gain": _rounded(ev.beyond_resize_chi2_gain),
            "resize_chi2_gain": _rounded(ev.resize_chi2_gain),
            "bic_penalty": round(ev.bic_penalty, 1), "ranking_chi2_gain": _rounded(ev.ranking_chi2_gain),
            "ranking_bic_penalty": _rounded(ev.ranking_penalty),
            "trials": {i: {"gain": round(t["gain"], 1), "excess": round(t["excess"], 1),
                           "nrmse": [round(t["nrmse_before"], 3), round(t["nrmse_after"], 3)],
                           **({"window_chi2_gain": round(ev.window_trials[i]["chi2_gain"], 1)}
                              if i in ev.window_trials else {})}
                       for i, t in ev.per_trial.items()}}


def run_case(case: SuiteCase, workers: int, reach: bool = False) -> dict[str, Any]:
    """Make and diagnose one case blind (reach: the diagnosis's option of that name); its record (draw, named,
    per-step candidates, score, wall time)."""
    from ..diagnose.diagnosis import diagnose_data
    from ..synth import make_dataset, truth, without_truth

    t0 = time.perf_counter()
    first, *also = case.effects or ((None, 0.0),)
    data = make_dataset(first[0], first[1], case.seed, noise_pct=case.noise_pct, workers=workers, world=case.world,
                        also=dict(also) or None)
    row: dict[str, Any] = {"world": case.world, "effects": [list(e) for e in case.effects],
                           "noise_pct": case.noise_pct, "seed": case.seed, "label": case.label,
                           **({"heldout_reach": True} if reach else {})}
    try:
        d = diagnose_data(without_truth(data), workers=workers, reach=reach)
    except (InputError, NumericalError) as e:  # one case's failure is recorded, and the suite goes on
        return {**row, "error": str(e), "named": [], "wall_s": round(time.perf_counter() - t0, 1)}
    passed = d.causes
    sd = float(truth(data)["noise_sd_N"])
    ratio = {i: float(np.sqrt(np.mean((d.baseline.simulated[i] - data.trials[i].force) ** 2))) / sd
             for i in d.split.heldout} if sd > 0 else {}
    row.update({
        "named": d.named, "verdict": d.verdict,
        "steps": [{"named": s.named_causes,
                   "candidates": {n: _evidence_row(c.evidence) for n, c in s.candidates.items()
                                  if c.evidence is not None},
                   "joint": (None if s.joint is None else
                             {"names": list(s.joint.names), "passed": s.joint.passed,
                              "evidence": {n: _evidence_row(e) for n, e in s.joint.evidence.items()},
                              "seconds": round(s.joint.model.wall_s, 1)}),
                   "screening": {n: round(c.screen.score, 1) for n, c in s.candidates.items()
                                 if c.screen is not None},
                   "seconds": {"screening": round(s.screen_s, 1),
                               **{n: round(c.model.wall_s, 1) for n, c in s.candidates.items() if c.model},
                               **({"consolidation": round(s.consolidated.wall_s, 1)} if s.consolidated else {})}}
                  for s in d.steps],
        "backward": [{"name": c.name, "round": c.round, "dropped": c.dropped, **_evidence_row(c.evidence),
                      "seconds": round(c.without.wall_s, 1)} for c in d.checks],
        "baseline_s": round(d.baseline.model.wall_s, 1),
        "baseline_converged": d.baseline.model.converged,
        "baseline_heldout_rms_over_noise": {i: round(v, 3) for i, v in ratio.items()},
        "structured_trials": list(d.structured_after),
        "wall_s": round(time.perf_counter() - t0, 1)})
    row["score"] = judge_case(case, d.named, passed)
    return row


def run_suite(n_seeds: int, *, causes: Sequence[str] | None = None, seed: int = 0, workers: int = 2,
              worlds: Sequence[str] = ("B",), two_effect: int = 0, progress: bool = False,
              journal: str | None = None, first: int = 1, reach: bool = False) -> dict[str, Any]:
    """Make and diagnose every case of ``suite_cases`` blind and return {"cases": [...], **score}.  journal: a
    file to which each case's record is appended as one JSON line when done (a long suite's finished cases survive
    an interrupt); first: the case (1-based, in ``suite_cases`` order) to start from, to resume; reach: the
    diagnosis's option of that name."""
    cases = suite_cases(n_seeds, causes, seed, worlds, two_effect)
    if not cases:
        raise InputError("the suite has no case: give --suite N >= 1 or --two-effect K >= 1")
    if isinstance(first, bool) or not isinstance(first, int) or not 1 <= first <= len(cases):
        raise InputError(f"the first case must be between 1 and {len(cases)}, got {first!r}")
    results = []
    for k, case in enumerate(cases[first - 1:], first):
        row = run_case(case, workers, reach)
        results.append(row)
        _journal(journal, row)
        if progress:
            what = f"ERROR {row['error']}" if row.get("error") else f"named {', '.join(row['named']) or 'none'}"
            print(f"neuromuscle bench diagnose --suite: {k}/{len(cases)} world {case.world} {case.label} (seed "
                  f"{case.seed}, noise {case.noise_pct:.2f} %) -> {what} ({row['wall_s']:.0f} s)", file=sys.stderr,
                  flush=True)
    return {"n_seeds": n_seeds, "seed": seed, "workers": workers, "worlds": list(worlds), "two_effect": two_effect,
            "cases": results, **score(results)}


def read_journals(paths: Sequence[str]) -> list[dict[str, Any]]:
    """Every case record of the journal files ``paths`` (one JSON line per finished case, as ``--journal`` writes
    them; gzip-compressed when the name ends in .gz), in order: several partial or parallel runs of a suite scored
    as one.  InputError naming the file and line of a record that is not a case, and of a case that appears twice
    (same world, effects and dataset seed)."""
    rows: list[dict[str, Any]] = []
    seen: dict[tuple, str] = {}
    for path in paths:
        try:
            raw = Path(path).read_bytes()
            lines = (gzip.decompress(raw) if str(path).endswith(".gz") else raw).decode("utf-8").splitlines()
        except OSError as e:
            raise InputError(f"{path}: cannot read the journal ({e.strerror or e})") from None
        except (EOFError, UnicodeDecodeError, zlib.error) as e:
            raise InputError(f"{path}: cannot read the journal ({e})") from None
        for k, line in enumerate(lines, 1):
            if not line.strip():
                continue
            where = f"{path}, line {k}"
            try:
                row = json.loads(line)
            except json.JSONDecodeError as e:
                raise InputError(f"{where}: not a JSON line ({e.msg})") from None
            missing = [f for f in ("world", "effects", "seed") if not isinstance(row, dict) or f not in row]
            if missing or ("score" not in row and "error" not in row):
                raise InputError(f"{where}: not a case record of bench diagnose --suite (missing "
                                 f"{', '.join(missing) or 'score'})")
            key = (row["world"], json.dumps(row["effects"]), row["seed"])
            if key in seen:
                raise InputError(f"{where}: the case (world {row['world']}, {row.get('label', key[1])}, seed "
                                 f"{row['seed']}) is already in {seen[key]}")
            seen[key] = where
            rows.append(row)
    if not rows:
        raise InputError(f"no case record in {', '.join(paths)}")
    return rows


def score_journals(paths: Sequence[str]) -> dict[str, Any]:
    """The suite's scores (:func:`score`) over the cases of the journal files ``paths`` (:func:`read_journals`),
    with the files and the number of cases."""
    rows = read_journals(paths)
    return {"journals": list(paths), "n_cases": len(rows), **score(rows)}


def table_lines(res: dict[str, Any]) -> list[str]:
    """The suite's result as Markdown: per world and cause, n, hits and hit rate; per world; per cause over the
    worlds; then the overall rates."""
    lines = ["| world | cause | n | named | rate % |", "|---|---|---|---|---|"]
    for w, cs in res["per_world"].items():
        for c, p in cs.items():
            lines.append(f"| {w} | {c} | {p['n']} | {p['hits']} | {p['hit_rate_pct']} |")
    lines += ["", "| world | causes named | rate % | files with a wrong name | false alarms / nulls | both named / "
                  "two-effect files |", "|---|---|---|---|---|---|"]
    for w, c in res["worlds"].items():
        lines.append(f"| {w} | {c['hidden_named']} of {c['hidden_causes']} | {c['hit_rate_pct']} | "
                     f"{c['files_with_a_wrong_name']} | {c['false_alarms']} / {c['nulls']} | "
                     f"{c['both_named']} / {c['two_effect_files']} |")
    lines += ["", "| cause (every world) | n | named | rate % |", "|---|---|---|---|"]
    for n, c in res["causes"].items():
        lines.append(f"| {n} | {c['n']} | {c['hits']} | {c['hit_rate_pct']} |")
    lines += ["", f"hidden causes named {res['hidden_named']} of {res['hidden_causes']} ({res['hit_rate_pct']} %); "
                  f"false alarms {res['false_alarms']} of {res['nulls']} nulls; files with a wrong name "
                  f"{res['files_with_a_wrong_name']}; both causes named in {res['both_named']} of "
                  f"{res['two_effect_files']} two-effect files; errors {res['errors']}"]
    return lines
