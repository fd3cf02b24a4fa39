"""How far a suite case's hidden effect can be told from calibration, to first order at the generator's truth.

A miss of the diagnosis suite has two kinds of cause: the data cannot separate the effect from the preparation's
own parameters, or the diagnosis fails to use what they hold.  This measures the first, with no fit.

For one case (``diagnose_suite.SuiteCase``): r = F_effect - F_null on every trial of the standard protocols (the two
files of one seed share the preparation and the noise, so r is the effect alone), whitened as the verdict's
chi-square is (1 / noise sd x sqrt((1 - rho)/(1 + rho)), rho = exp(-sample interval / noise correlation time)).
J_m holds the sensitivities of the forces, at the true parameters, to what the diagnosis's reference refits
(Module 2's C1, C2, C3, alpha, Umax, tau2 and Module 3's P0, g1, g2; 2 % relative steps).  Then

* chi2_effect = |r|^2: what the effect adds if nothing were refitted;
* chi2_unabsorbed = min |r - J_m c|^2: what no refit of those parameters absorbs (to first order);
* chi2_with_extension = min |r - J_m c - J_e d|^2: also with the cause's catalogue extension's effect parameters
  (their columns at neutral, moved as the screening moves them: ``screening.effect_moves``), at the best of
  ``GRID_POINTS`` values (log-spaced over its range) of the extension's first parameter without a neutral value
  (its time constant), the others at their defaults.

chi2_unabsorbed near 0 says no method could name the cause from these trials at this noise; a large
chi2_unabsorbed that the extension captures, with the diagnosis still missing, points at the diagnosis (e.g. a
nonlinear reference that reaches parameters far from the truth).  First order only: a calibration that moves a
parameter far can absorb more.  Cost: 2 synthetic files and 1 + 6 + GRID_POINTS x (1 + effect parameters)
simulations of the 28 trials, about 1 min a case (measured with 1 worker).
"""

from __future__ import annotations

import math
from contextlib import nullcontext
from dataclasses import asdict, dataclass
from typing import Any, Sequence

import numpy as np

#: Values of the extension's time constant tried (log-spaced over its range).
GRID_POINTS = 5
#: Relative step of the refitted parameters.
REFIT_STEP = 0.02


@dataclass(frozen=True)
class Separability:
    """One case's first-order separability (module docstring); chi-square units (noise variances, corrected for
    autocorrelation); ``trials``: per trial (effect, unabsorbed), the largest unabsorbed first."""

    cause: str
    strength: float
    noise_pct: float
    seed: int
    chi2_effect: float
    chi2_unabsorbed: float
    chi2_with_extension: float | None
    extension_setting: dict[str, float]
    trials: dict[str, tuple[float, float]]

    @property
    def captured(self) -> float | None:
        """Share of the unabsorbed chi-square the extension removes (None without an extension)."""
        if self.chi2_with_extension is None or self.chi2_unabsorbed <= 0:
            return None
        return 1.0 - self.chi2_with_extension / self.chi2_unabsorbed

    def to_json(self) -> dict[str, Any]:
        return {**asdict(self), "captured": self.captured}


def _residual_after(r: np.ndarray, J: np.ndarray) -> np.ndarray:
    """r - J c for the least-squares c (columns scaled to unit norm first: Umax's ~1e3 beside C1's ~0.1)."""
    norms = np.linalg.norm(J, axis=0)
    keep = norms > 0
    if not keep.any():
        return r
    Js = J[:, keep] / norms[keep]
    c, *_ = np.linalg.lstsq(Js, r, rcond=None)
    return r - Js @ c


def separability(cause: str, strength: float, seed: int, noise_pct: float, *, workers: int = 1,
                 trials: Sequence[str] | None = None, world: str = "B") -> Separability:
    """The first-order separability of hidden effect ``cause`` at ``strength`` (0-1) in the preparation of dataset
    seed ``seed`` with noise ``noise_pct`` (% of P0); ``world``: synth's world, ``trials``: a subset of its
    protocol set's ids."""
    from ..diagnose.models import OPTIONS
    from ..model.extensions import ACTIVATION_PARAMETERS, LENGTH_PARAMETERS
    from ..diagnose.residuals import Noise
    from ..diagnose.screening import effect_moves, simulate_runs
    from ..errors import InputError
    from ..fit.evaluate import TrialPool
    from ..model.extensions import registry
    from ..synth import make_dataset, truth

    if cause == "none":
        raise InputError("separability needs a hidden effect, not 'none'")
    with_effect = make_dataset(cause, strength, seed, noise_pct=noise_pct, workers=workers, trials=trials,
                               world=world)
    null = make_dataset(None, strength, seed, noise_pct=noise_pct, workers=workers, trials=trials, world=world)
    tr = truth(with_effect)
    P = tr["parameters"]
    sd, tau = float(tr["noise_sd_N"]), float(tr["noise_tau_ms"])
    cases = list(null.trials.values())
    ids = [t.trial_id for t in cases]
    weight = {}  # sqrt of the verdict's chi-square weight (1/N), from the generator's noise sd and correlation time
    for t in cases:
        rho = math.exp(-1000.0 * float(t.time_s[1] - t.time_s[0]) / tau)
        weight[t.trial_id] = math.sqrt(Noise(sd, rho, t.n_samples * (1 - rho) / (1 + rho)).chi2_weight)
    r = {i: (np.asarray(with_effect.trials[i].force) - np.asarray(null.trials[i].force)) * weight[i] for i in ids}

    steps = [(n, abs(P[n]) * REFIT_STEP) for n in ACTIVATION_PARAMETERS + LENGTH_PARAMETERS]
    runs = [(P, ())] + [(P.with_values({n: P[n] + h}), ()) for n, h in steps]
    ext = registry().get(cause)
    grid: list[dict[str, float]] = []
    moves: list[tuple[str, float]] = []
    if ext is not None:
        neutral = {ext.qualified(p.name): (p.neutral if p.neutral is not None else p.default) for p in ext.parameters}
        timing = [p for p in ext.parameters if p.neutral is None and p.lower > 0]
        grid = ([{ext.qualified(timing[0].name): float(v)}
                 for v in np.geomspace(timing[0].lower, timing[0].upper, GRID_POINTS)] if timing else [{}])
        moves = [(q, h) for q, h, _ in effect_moves(ext)]
        grid = grid if moves else []  # an extension without an effect parameter has nothing to move
        for g in grid:
            at = {**neutral, **g}
            runs.append((P.with_values(at), (cause,)))
            runs += [(P.with_values({**at, q: at[q] + h}), (cause,)) for q, h in moves]
    with TrialPool(cases, workers) if workers > 1 else nullcontext() as pool:
        sims = simulate_runs(runs, cases, OPTIONS, pool)

    def column(s: dict[str, np.ndarray], s0: dict[str, np.ndarray], h: float) -> np.ndarray:
        return np.concatenate([(s[i] - s0[i]) * weight[i] / h for i in ids])

    rv = np.concatenate([r[i] for i in ids])
    Jm = np.column_stack([column(sims[1 + k], sims[0], h) for k, (_, h) in enumerate(steps)])
    e = _residual_after(rv, Jm)
    bounds = np.cumsum([0] + [len(r[i]) for i in ids])
    per = {i: (float(r[i] @ r[i]), float(e[a:b] @ e[a:b])) for i, a, b in zip(ids, bounds[:-1], bounds[1:])}
    best: tuple[float, dict[str, float]] | None = None
    at = 1 + len(steps)
    for g in grid:
        Je = np.column_stack([column(sims[at + 1 + j], sims[at], h) for j, (_, h) in enumerate(moves)])
        at += 1 + len(moves)
        e2 = _residual_after(rv, np.hstack([Jm, Je]))
        if best is None or float(e2 @ e2) < best[0]:
            best = (float(e2 @ e2), g)
    order = sorted(ids, key=lambda i: -per[i][1])
    return Separability(cause, float(strength), float(noise_pct), int(seed), float(rv @ rv), float(e @ e),
                        None if best is None else best[0], {} if best is None else best[1],
                        {i: per[i] for i in order})


def table_lines(rows: Sequence[Separability]) -> list[str]:
    """A markdown table of the cases."""
    out = ["| cause | strength | seed | chi2 effect | unabsorbed by the reference's refits | with the extension | "
           "captured | most unabsorbed trial |", "|---|---|---|---|---|---|---|---|"]
    for s in rows:
        top = next(iter(s.trials), "-")
        cap = "-" if s.captured is None else f"{100 * s.captured:.0f} %"
        ext = "-" if s.chi2_with_extension is None else f"{s.chi2_with_extension:.4g}"
        out.append(f"| {s.cause} | {s.strength:.2f} | {s.seed} | {s.chi2_effect:.4g} | {s.chi2_unabsorbed:.4g} | "
                   f"{ext} | {cap} | {top} |")
    return out


def run_separability(n_seeds: int, *, causes: Sequence[str] | None = None, seed: int = 0, workers: int = 2,
                     first: int = 1, journal: str | None = None, progress: bool = True,
                     worlds: Sequence[str] = ("B",)) -> list[Separability]:
    """:func:`separability` of the suite's cases (``diagnose_suite.suite_cases``, the same draws; nulls skipped),
    from case ``first`` (1-based), each appended to ``journal`` as a JSON line when given."""
    import json
    import sys

    from ..errors import InputError
    from .diagnose_suite import suite_cases

    cases = [c for c in suite_cases(n_seeds, causes, seed, worlds) if len(c.effects) == 1]
    if isinstance(first, bool) or not isinstance(first, int) or not 1 <= first <= len(cases):
        raise InputError(f"the first case must be between 1 and {len(cases)} (nulls are skipped), got {first!r}")
    out = []
    for k, c in enumerate(cases[first - 1:], first):
        (cause, strength), = c.effects
        s = separability(cause, strength, c.seed, c.noise_pct, workers=workers, world=c.world)
        out.append(s)
        if progress:
            print(f"[separability] {k}/{len(cases)} {table_lines([s])[-1]}", file=sys.stderr, flush=True)
        if journal:
            with open(journal, "a") as f:
                f.write(json.dumps(s.to_json()) + "\n")
    return out
