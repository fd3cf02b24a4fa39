"""Which candidates to fit: each extension's linearised gain at the current model on the calibration trials (a
score test).

A full fit of a candidate is the costly step of a diagnosis, so only the most promising are fitted.  Each
candidate is asked what it could do, in the model itself: at the current model (the baseline and the causes named
so far, fitted), every effect parameter of the candidate (those with a neutral value) is moved by
``STEP_FRACTION`` of its range from neutral, the calibration trials are simulated once per move, and so are moves
of everything the candidate's fit refits (the model's free parameters, by ``REFITTED_STEP`` relative).  The finite
differences give a Jacobian J = [J_m | J_e] of the residuals, whitened as the rules' chi-square is.  The
linearised gain is how much further the effect's columns lower the chi-square than the refitted parameters'
alone:

    gain = min_dm |r + J_m dm|^2 - min_(dm, de) |r + J_m dm + J_e de|^2,   de within [lower, upper] - neutral

(scipy's bounded linear least squares).  It is Rao's score statistic with the effect's bounds kept, the locally
most powerful test of "effect = neutral", and what the candidate's fit will start to gain.  Candidates are ordered
by gain minus the BIC penalty p ln N_eff.

A gain can need a time constant (a parameter with no neutral value) far from its default, so each candidate is
screened at its defaults and at every combination of its time constants at ``GRID_QUANTILES`` of their ranges
(:func:`time_constant_settings`), and its best gain counts.  The screen only chooses what to fit; the rules judge.
The moved runs and one run of the current model are simulated at ``.models.DIFFERENCE_DT_MS``, whose integration
error cancels in the differences; they go to the worker pool together.  A candidate that acts only where the length
moves (``Extension.needs_movement``: through a movement or after one) leaves a trial held at a constant length
exactly as the model has it, so its moved runs simulate only the other trials and take the model's run for those
(the same numbers: about a third of a screening's runs, most of whose trial time is isometric).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace
from typing import Any, Mapping, Sequence

import numpy as np
from scipy.optimize import lsq_linear

from ..fit import SimulationOptions
from ..fit.evaluate import TrialPool, simulate_batched
from ..measured import Trial
from ..measured.simulation import constant_length
from ..model.extensions import registry
from ..parameters import SPECS, ParameterSet
from .models import DIFFERENCE_DT_MS, simulate_all
from .residuals import Noise

#: The move of an effect parameter from neutral, as a fraction of its range (a secant: effects are not linear).
STEP_FRACTION = 0.1
#: Quantiles of a time constant's range (log-spaced for a positive range) tried beside its default.
GRID_QUANTILES = (0.25, 0.75)
#: The relative move of what every candidate refits (the current model's free parameters).
REFITTED_STEP = 0.02


@dataclass(frozen=True)
class Screen:
    """One candidate's linearised gain (chi-square units) at the reference, its effect parameters' moves (the
    linearised optimum, parameter units), the BIC penalty it must beat, the score (gain - penalty), and the time
    constants (ms, or the parameter's units) it was screened at where they are not the defaults."""

    name: str
    gain: float
    penalty: float
    moves: dict[str, float]
    time_constants: dict[str, float] = field(default_factory=dict)
    at: str = "model"

    @property
    def score(self) -> float:
        return self.gain - self.penalty

    def to_json(self) -> dict:
        return {"linearised_chi2_gain": self.gain, "bic_penalty": self.penalty, "score": self.score,
                "moves": self.moves, "time_constants": self.time_constants, "at": self.at}


def _whitened(sims: Mapping[str, np.ndarray], measured: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
              ids: Sequence[str]) -> np.ndarray:
    """Residuals of ``ids`` (N) divided by their noise sd and scaled by sqrt((1 - rho)/(1 + rho)), concatenated."""
    return np.concatenate([(sims[i] - measured[i]) * math.sqrt(noise[i].chi2_weight) for i in ids])


def simulate_runs(runs: Sequence[tuple[ParameterSet, tuple[str, ...]]], trials: Sequence[Trial],
                  options: SimulationOptions, pool: TrialPool | None) -> list[dict[str, np.ndarray]]:
    """Every trial's force under each (parameter set, extensions) run: one pool call when a pool is given, so the
    two workers stay busy to the end (longest trials first) rather than idling at the tail of ~20 small calls;
    without a pool, each trial's runs batched in this process."""
    if runs:
        params, opts = [p for p, _ in runs], [replace(options, extensions=e) for _, e in runs]
        out = pool.simulate(params, trials, opts) if pool is not None else simulate_batched(params, trials, opts)
        if not any(s is None for s in out):
            return [{t.trial_id: f for t, f in zip(trials, s)} for s in out]
    return [simulate_all(p, trials, e, options) for p, e in runs]  # one by one: names a failing run


def _step_within(name: str, value: float) -> float:
    """The move of refitted parameter ``name`` from ``value``: REFITTED_STEP relative, downwards where upwards
    would leave the parameter's range (a fit can end on its bound)."""
    h = abs(value) * REFITTED_STEP if value != 0 else REFITTED_STEP
    return -h if value + h > SPECS[name].upper else h


def effect_moves(ext) -> list[tuple[str, float, Any]]:
    """Each effect parameter of extension ``ext`` (one with a neutral value): its qualified name, its move from
    neutral (``STEP_FRACTION`` of its range, in its own units; downwards where upwards would leave the range) and
    its ``Param``."""
    out = []
    for p in (p for p in ext.parameters if p.neutral is not None):
        h = STEP_FRACTION * (p.upper - p.lower)
        out.append((ext.qualified(p.name), h if p.neutral + h <= p.upper else -h, p))
    return out


def _min_sq(r: np.ndarray, J: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> tuple[float, np.ndarray]:
    """min |r + J d|^2 over lower <= d <= upper, and the d that attains it."""
    if J.shape[1] == 0:
        return float(r @ r), np.zeros(0)
    res = lsq_linear(J, -r, bounds=(lower, upper), method="bvls")
    e = r + J @ res.x
    return float(e @ e), res.x


def time_constant_settings(ext) -> list[dict[str, float]]:
    """The values of extension ``ext``'s time constants (parameters without a neutral value) the screening tries:
    the defaults (an empty setting), then every combination of each at ``GRID_QUANTILES`` of its range, log-spaced
    where the range is positive, in the parameter's own units."""
    grids = []
    for p in (p for p in ext.parameters if p.neutral is None):
        if p.lower > 0:
            values = [p.lower * (p.upper / p.lower) ** q for q in GRID_QUANTILES]
        else:
            values = [p.lower + (p.upper - p.lower) * q for q in GRID_QUANTILES]
        grids.append([(ext.qualified(p.name), float(v)) for v in values])
    return [{}] + ([dict(c) for c in itertools.product(*grids)] if grids else [])


def screen_settings(names: Sequence[str], reference: ParameterSet, reference_sims: Mapping[str, np.ndarray],
                    calibration: Sequence[Trial], measured: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
                    options: SimulationOptions, pool: TrialPool | None = None,
                    column_dt_ms: float | None = DIFFERENCE_DT_MS, refitted: Sequence[str] = (),
                    extensions: tuple[str, ...] = (),
                    subsets: Mapping[str, Sequence[str]] | None = None, model_chi2: float | None = None,
                    at: str = "model") -> list[Screen]:
    """A :class:`Screen` of each extension in ``names`` at each of its :func:`time_constant_settings`, at the model
    ``reference`` with ``extensions`` (module docstring), its parameters ``refitted`` refitted; forces in N.  The
    Jacobian's columns difference simulations at fixed step ``column_dt_ms`` (ms; None: ``options``' step, no
    extra simulation of the model) against the model simulated at the same step; the residual it linearises is
    ``reference_sims``.  subsets: for a candidate, the part of ``refitted`` its fit refits (default: all).
    model_chi2: when ``reference`` is not the fitted model but another start (``at`` names it), the model's
    calibration chi-square that the gain is measured from (default: the best of ``reference`` with the refitted
    parameters alone)."""
    ids = [t.trial_id for t in calibration]
    r = _whitened(reference_sims, measured, noise, ids)
    n_eff = max(sum(noise[i].n_eff for i in ids), 2.0)
    exts = tuple(extensions)

    refit = [(n, _step_within(n, reference[n])) for n in refitted]
    known = registry()
    plans = []  # per candidate and setting: the time constants, the point the effect is moved from, the moves
    for name in names:
        ext = known[name]
        defaults = {ext.qualified(p.name): (p.neutral if p.neutral is not None else p.default)
                    for p in ext.parameters}
        moves = effect_moves(ext)
        plans += [(name, setting, {**defaults, **setting}, moves) for setting in time_constant_settings(ext)]
    runs = [(reference.with_values({n: reference[n] + h}), exts) for n, h in refit]
    moved = [(reference.with_values({**at, q: at[q] + h}), exts + (name,)) for name, _, at, moves in plans
             for q, h, _ in moves]
    needs_move = [known[name].needs_movement() for name, _, _, moves in plans for _ in moves]
    r0 = r
    model_sims: Mapping[str, np.ndarray] = reference_sims
    if column_dt_ms is not None:
        options = replace(options, dt_ms=column_dt_ms, record_dt_ms=None, differenced=True)
        runs = [(reference, exts)] + runs
    every = [m for m, s in zip(moved, needs_move) if not s]
    done = simulate_runs(runs + every, calibration, options, pool)
    if column_dt_ms is not None:
        model_sims = done.pop(0)
        r0 = _whitened(model_sims, measured, noise, ids)
    n_refit = len(refit)
    rest = iter(done[n_refit:])
    moving = [t for t in calibration if constant_length(t) is None]
    only = iter(simulate_runs([m for m, s in zip(moved, needs_move) if s], moving, options, pool) if moving else [])
    moved_sims = []
    for needs in needs_move:  # in the order of ``moved``: simulated on every trial, or on the moving ones alone
        if not needs:
            moved_sims.append(next(rest))
        else:
            moved_sims.append({**model_sims, **(next(only) if moving else {})})
    sims = iter(done[:n_refit] + moved_sims)

    def column(h: float) -> np.ndarray:
        return (_whitened(next(sims), measured, noise, ids) - r0) / h

    Jall = np.column_stack([column(h) for _, h in refit]) if refit else np.zeros((r.size, 0))
    names_refit = [n for n, _ in refit]
    bases: dict[tuple[int, ...], float] = {}
    out = []
    for name, setting, _, moves in plans:
        keep = tuple(k for k, n in enumerate(names_refit) if subsets is None or n in subsets.get(name, names_refit))
        Jm = Jall[:, list(keep)]
        unbounded = np.full(Jm.shape[1], np.inf)
        if keep not in bases:
            bases[keep] = _min_sq(r, Jm, -unbounded, unbounded)[0] if model_chi2 is None else model_chi2
        Je = np.column_stack([column(h) for _, h, _ in moves]) if moves else np.zeros((r.size, 0))
        J = np.hstack([Jm, Je])
        lower = np.concatenate([-unbounded, [p.lower - p.neutral for _, _, p in moves]])
        upper = np.concatenate([unbounded, [p.upper - p.neutral for _, _, p in moves]])
        best, d = _min_sq(r, J, lower, upper)
        out.append(Screen(name, max(bases[keep] - best, 0.0), len(moves) * math.log(n_eff),
                          {q: float(p.neutral + x) for (q, _, p), x in zip(moves, d[Jm.shape[1]:])}, dict(setting),
                          at))
    return out


def screen(names: Sequence[str], reference: ParameterSet, reference_sims: Mapping[str, np.ndarray],
           calibration: Sequence[Trial], measured: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
           options: SimulationOptions, pool: TrialPool | None = None, refitted: Sequence[str] = (),
           extensions: tuple[str, ...] = (), subsets: Mapping[str, Sequence[str]] | None = None,
           model_chi2: float | None = None, at: str = "model") -> dict[str, Screen]:
    """The best :class:`Screen` of each extension in ``names`` over its time-constant settings, at the model
    ``reference`` with ``extensions`` whose parameters ``refitted`` each candidate's fit refits (module
    docstring); forces in N.  A tie keeps the defaults."""
    out: dict[str, Screen] = {}
    for s in screen_settings(names, reference, reference_sims, calibration, measured, noise, options, pool,
                             refitted=refitted, extensions=extensions, subsets=subsets, model_chi2=model_chi2,
                             at=at):
        if s.name not in out or s.gain > out[s.name].gain:
            out[s.name] = s
    return out
