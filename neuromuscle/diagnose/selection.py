"""Forward selection of causes: name the most material cause, fold its fitted extension into the model, search
again on what remains, until no candidate passes the rules.

One step, at the current model M (the baseline, then the baseline plus the causes named so far):

1. **candidates**: every catalogue cause not yet in M that has a calibration trial of its telling kind
   (:func:`.causes.tells`); a cause with none is listed as untestable, never guessed;
2. **screening** (:mod:`.screening`): each candidate's linearised calibration gain at M; those whose gain beats
   their BIC penalty by at least ``FIT_SHARE`` of the best one's are fitted, best first, and, while none of them
   passes, the next ones too, at most ``MAX_FITS`` in all, or ``MAX_FITS_SMALL`` once a fitted candidate fails
   only for being small beside the held-out error left (a real cause, not the main one: the calibration trials
   that rank the candidates are not those that carry the held-out error); and, while none passes, every candidate
   that refits the force-length parameters and beats its penalty is fitted whatever its rank
   (:func:`trades_off_with_length`);
3. **fit** (:func:`.models.fit_model`): M plus the candidate, free in the candidate's own parameters, in those of
   the causes already named and in the baseline parameters any of them interacts with (:func:`refitted`), so that a
   named cause which took up part of the candidate's effect gives it back (eq 18 fitted first takes up part of
   lengthening below the optimum through its length dependence) and the candidate is judged against the best model
   that contains it; from M and from M with the candidate's baseline parameters put back at the base set's values;
   a fit that ends above M's calibration chi-square (worse than the model it contains) is fitted again from M
   itself, the extension neutral (:func:`fit_candidate`);
4. **evidence** (:mod:`.evidence`) on the held-out trials against M, and the rules (:mod:`.rules`).  Where the
   cause is judged (R7): its telling held-out trials, or the held-out samples where its fitted extension changes
   the force by more than ``ACTS_SD`` noise sd when no held-out trial is of its kind (in a pair of step 6) or, as
   a second way through rule R7, when the model before already fits every held-out telling trial to its noise
   there (a model that bent its other parameters to absorb the cause on those trials, which may then not show
   it).  A candidate whose telling trials all calibrate (protocols the file has once, such as one long train, one
   doublet train, one post-tetanic series, one shortening-hold; or the off-optimum trials of protocols at three
   lengths, which the alternate split puts on the calibration side) is judged by **cross-validation over trials**
   (:func:`judge_crossed`): the model before and the candidate's model are fitted again without those trials,
   the candidate from its usual starts (nothing it learnt from them carries over), and both are judged by every
   held-out rule on the held-out trials and those trials together; whether its effect is identified (rule R1) is
   read from its fit on every calibration trial, which holds the trials that tell it.  There, a cause defined
   after a movement is measured from the isometric force at the hold's length, and one that acts through the
   movement from the isometric misfit at every sample's length (:func:`.causes.isometric_level`).  With the
   option ``reach`` (off by default), the held-out forces of the model before and of the candidate's model in all
   of this are those each reaches within its calibration confidence region (:mod:`.reach`, :func:`reached`);
5. the passing candidate with the best whole-file score is named; its model, refitted in every free parameter
   (:func:`consolidate`), becomes M;
6. **two at once** (:func:`joint`), when no candidate passes but one is beyond noise and material alone (rules
   R0, R2, R4) and fails another rule: a second cause in the data can make the first one's held-out gain uneven
   (better where one acts, worse where the other does) and the second one's fit alone lands on the first one's
   misfit.  The material candidate and a second one (the fitted candidate with the best score among those beyond
   noise, else the best-screened one) are fitted together (with the causes already named and the baseline
   parameters any of them interacts with free, from each one's own fit), and each is judged against the model
   with the other alone, by every rule (by cross-validation over trials, as in step 4, when either was judged so
   alone).  When both pass, both are named at this step, the material one first.

The search ends when no candidate passes, none is left, or after ``MAX_STEPS`` causes.  Each step estimates the
trials' noise again from the residuals of the model it starts from (:func:`noise_under`).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field, replace
from typing import Mapping, Sequence

import numpy as np

from ..fit.evaluate import TrialPool
from ..measured import MeasuredData, Trial
from ..model.extensions import LENGTH_PARAMETERS
from ..parameters import ParameterSet, registry
from .baseline import FORCE_PARAMETERS
from .causes import causes, isometric_level, telling_trials, where_defined
from .evidence import Evidence, WindowSamples, excess, gather, heldout_chi2_gain, quiet_window
from .models import (CANDIDATE_TOLERANCE, MODEL_MAX_ITERATIONS, OPTIONS, FittedModel, extension_class,
                     extension_defaults, extension_neutral, fit_model, simulate_all)
from .phases import TrialPhases
from .reach import heldout_reach
from .resize import beyond_resize
from .residuals import Noise, noise_level, rest_trend_z
from .rules import REST_Z, apply_rules
from .screening import Screen, screen

#: Candidates fitted per step: those whose screened score is at least FIT_SHARE of the best one's (a linearised
#: gain is a ranking, not a measurement: close ones are all fitted), at most MAX_FITS, the best first; at most
#: MAX_FITS_SMALL when a fitted candidate fails only for being small beside the error left (SMALL_ONLY): a real
#: cause that is not the main one, so the main one is further down the ranking.
MAX_FITS = 3
MAX_FITS_SMALL = 6
SMALL_ONLY = frozenset({"R4"})
FIT_SHARE = 1.0 / 3.0
#: Causes named at most.
MAX_STEPS = 3
#: Where a fitted extension "acts" in a held-out trial: it changes the force by more than this many noise sd.
ACTS_SD = 0.5
#: A candidate failing some rule is tried together with another one when it passes these alone (step 6).
JOINT_IF_PASSES = ("R0", "R2", "R4")


@dataclass
class Candidate:
    """One cause at one step: its telling trials on each side of the split, why it is untestable (or None), its
    screen, its fitted model and its evidence (None where not fitted)."""

    name: str
    telling_calibration: list[str]
    telling_heldout: list[str]
    untestable: str | None = None
    screen: Screen | None = None
    model: FittedModel | None = None
    evidence: Evidence | None = None

    @property
    def fitted(self) -> bool:
        return self.model is not None


@dataclass
class Joint:
    """Two candidates fitted together at one step (module docstring, step 6): their model, each one's model alone
    and each one's evidence against the model with the other alone."""

    names: tuple[str, str]
    model: FittedModel
    alone: dict[str, FittedModel]
    evidence: dict[str, Evidence]

    @property
    def passed(self) -> bool:
        return all(e.passed for e in self.evidence.values())

    def other(self, name: str) -> str:
        return self.names[1] if name == self.names[0] else self.names[0]


@dataclass
class Step:
    """One step of the forward selection: the model it starts from, every candidate, the cause it names (or None),
    the pair tried together when no candidate passed alone, and the trials' noise it judged with (estimated from
    the model it starts from)."""

    index: int
    before: FittedModel
    candidates: dict[str, Candidate] = field(default_factory=dict)
    named: str | None = None
    noise: dict[str, Noise] = field(default_factory=dict)
    consolidated: FittedModel | None = None
    screen_s: float = 0.0
    joint: Joint | None = None

    @property
    def named_jointly(self) -> bool:
        return self.named is not None and self.joint is not None and self.joint.passed

    @property
    def named_causes(self) -> list[str]:
        """The causes this step names, in order: none, one, or the two named together."""
        if self.named is None:
            return []
        return list(self.joint.names) if self.named_jointly else [self.named]

    def model_of(self, name: str) -> FittedModel:
        """The model that names cause ``name`` at this step (for a pair, both causes')."""
        return self.joint.model if self.named_jointly else self.candidates[name].model

    def before_of(self, name: str) -> FittedModel:
        """The model cause ``name`` was judged against (for a pair, the model with the other cause alone)."""
        return self.joint.alone[self.joint.other(name)] if self.named_jointly else self.before

    def evidence_of(self, name: str) -> Evidence:
        """The evidence that named cause ``name`` (for a pair, against the model with the other cause alone)."""
        return self.joint.evidence[name] if self.named_jointly else self.candidates[name].evidence

    @property
    def after(self) -> FittedModel:
        """The model after this step: the named causes' (refitted in every free parameter when that was done),
        else the model before."""
        if self.named is None:
            return self.before
        return self.consolidated or self.model_of(self.named)


@dataclass
class Context:
    """What every step reads: the data, their descriptions and split, the noise, the measured forces, the base set
    (scaled), the baseline's free parameters and the worker pool."""

    data: MeasuredData
    phases: Mapping[str, TrialPhases]
    calibration: Sequence[str]
    heldout: Sequence[str]
    noise: Mapping[str, Noise]
    base: ParameterSet
    baseline_free: Sequence[str]
    pool: TrialPool | None = None
    progress: bool = False
    baseline: FittedModel | None = None
    crossed: dict[tuple[str, ...], Context] = field(default_factory=dict)
    refits: dict[str, FittedModel] = field(default_factory=dict)
    candidates: dict[str, FittedModel] = field(default_factory=dict)
    reach: bool = False
    reaches: dict[tuple, FittedModel] = field(default_factory=dict)
    contributions: dict[tuple, dict[str, dict[str, np.ndarray]]] = field(default_factory=dict)

    @property
    def trials(self) -> list[Trial]:
        return list(self.data.trials.values())

    @property
    def calibration_trials(self) -> list[Trial]:
        return [self.data.trials[i] for i in self.calibration]

    @property
    def measured(self) -> dict[str, np.ndarray]:
        return {i: np.asarray(t.force, dtype=float) for i, t in self.data.trials.items()}

    def say(self, text: str) -> None:
        if self.progress:
            print(f"[diagnose] {text}", file=sys.stderr, flush=True)


def rest_trends(ctx: Context, simulated: Mapping[str, np.ndarray]) -> dict[str, float | None]:
    """Each trial's rest trend z (None without a rest window) under a model's forces (N)."""
    measured = ctx.measured
    return {i: rest_trend_z(t, simulated[i] - measured[i], simulated[i], ctx.noise[i])
            for i, t in ctx.data.trials.items()}


def calibration_chi2(ctx: Context, simulated: Mapping[str, np.ndarray]) -> float:
    """The calibration chi-square (noise variances) of a model's forces (N) under the step's noise: what its fits
    minimise."""
    measured = ctx.measured
    return sum(float(((simulated[i] - measured[i]) ** 2).sum()) * ctx.noise[i].chi2_weight for i in ctx.calibration)


def noise_under(ctx: Context, model: FittedModel) -> dict[str, Noise]:
    """Every trial's noise estimated from ``model``'s residuals (first differences remove the smooth misfit, but
    a misfit's sharp features inflate them: the better the model, the better the estimate)."""
    measured = ctx.measured
    return {i: noise_level(model.simulated[i] - measured[i]) for i in ctx.data.trials}


def _identified(model: FittedModel, name: str) -> list[str]:
    """The effect parameters of extension ``name`` whose 95 % interval excludes their neutral value."""
    ext = extension_class(name)
    ci = model.ci95(name)
    out = []
    for p in ext.parameters:
        if p.neutral is None:
            continue
        lo, hi = ci[ext.qualified(p.name)]
        if np.isfinite(lo) and np.isfinite(hi) and not lo <= p.neutral <= hi:
            out.append(ext.qualified(p.name))
    return out


def _windows(ctx: Context, name: str, before: FittedModel, model: FittedModel, telling_heldout: Sequence[str],
             fitted: FittedModel | None = None
             ) -> tuple[dict[str, WindowSamples], dict[str, WindowSamples] | None]:
    """Rule R7's held-out samples of cause ``name`` (module docstring, step 4), and its telling trials' samples
    when they are quiet under the model before and the cause is judged where it acts instead (else None).  Where a
    cause is defined by the distance from the optimum (length-dependent activation, lengthening below it), the
    optimum is the candidate's own g1: a model without the cause bends g1 to absorb it, and trials at the true
    optimum would then count as off it, where the cause changes nothing.  Where it acts is read from ``fitted``
    (default ``model``): the candidate's own forces when ``model`` holds those it reaches."""
    ext = extension_class(name)
    g1 = float(model.parameters["g1"])
    measured = ctx.measured
    out: dict[str, WindowSamples] = {}
    for i in ctx.heldout:
        w = where_defined(ext, ctx.phases, i, g1)
        if not w.mask.any():
            continue
        if ext.moves and ctx.phases[i].moves:
            lb = isometric_level(ctx.phases, i, before.simulated, measured)
            la = isometric_level(ctx.phases, i, model.simulated, measured)
            lb, la = (v[w.mask] if isinstance(v, np.ndarray) else v for v in (lb, la))
        else:
            lb = w.level(ctx.phases, {j: before.simulated[j] - measured[j] for j in w.references})
            la = w.level(ctx.phases, {j: model.simulated[j] - measured[j] for j in w.references})
        out[i] = WindowSamples(w.mask, "defined", w.references, lb, la)
    if out and not quiet_window(out, measured, before.simulated, ctx.noise):
        return out, None
    defined, out = out, {}
    neutral = extension_neutral(name)
    held = [ctx.data.trials[i] for i in ctx.heldout]
    off = simulate_all(model.parameters.with_values(neutral), held, model.extensions, pool=ctx.pool)
    for i in ctx.heldout:
        mask = np.abs((fitted or model).simulated[i] - off[i]) > ACTS_SD * ctx.noise[i].sd_N
        if mask.any():
            out[i] = WindowSamples(mask, "acts")
    if not out:
        return defined, None
    return out, defined or None


def calibration_side(ctx: Context, name: str, before: FittedModel, model: FittedModel
                     ) -> tuple[list[str], tuple[float, float]]:
    """Rule R1's numbers of candidate ``name`` (fitted on ``ctx``'s calibration trials: ``model``) against
    ``before``: its effect parameters whose 95 % interval excludes their neutral value, and (calibration chi-square
    gain, its BIC penalty) in noise variances."""
    n_par = len(extension_class(name).parameters)
    n_eff_cal = sum(ctx.noise[i].n_eff for i in ctx.calibration)
    return _identified(model, name), (calibration_chi2(ctx, before.simulated) - model.cost,
                                      n_par * math.log(max(n_eff_cal, 2.0)))


def reached(ctx: Context, model: FittedModel, free: Sequence[str] | None = None) -> FittedModel:
    """``model`` as it enters a candidate's held-out evidence: itself, or with ``ctx.reach`` its held-out forces
    replaced by those it reaches within its calibration confidence region in the parameters ``free`` (default:
    those it was fitted in; :mod:`.reach`; its own where a run of the differences failed); kept per model, free
    parameters and noise estimate."""
    if not ctx.reach:
        return model
    names = tuple(model.free if free is None else free)
    key = (model.name, names, tuple(model.parameters[n] for n in names),
           tuple(ctx.noise[i].sd_N for i in ctx.data.trials))
    if key not in ctx.reaches:
        forces = heldout_reach(model, ctx.calibration_trials, [ctx.data.trials[i] for i in ctx.heldout], ctx.noise,
                               ctx.pool, names)
        if forces is None:
            ctx.say(f"    {model.name}: a run of its reach failed numerically; its own held-out forces are used")
        ctx.reaches[key] = model if forces is None else replace(model, simulated={**model.simulated, **forces})
    return ctx.reaches[key]


def reached_pair(ctx: Context, name: str, before: FittedModel, model: FittedModel
                 ) -> tuple[FittedModel, FittedModel]:
    """``before`` and candidate ``name``'s ``model`` as they enter its held-out numbers (:func:`reached`): the
    candidate's model in the model before's free parameters and its own."""
    ext = extension_class(name)
    own = tuple(ext.qualified(p.name) for p in ext.parameters)
    return reached(ctx, before), reached(ctx, model, tuple(dict.fromkeys(before.free + own)))


def contributions(ctx: Context, model: FittedModel, but: str) -> dict[str, dict[str, np.ndarray]]:
    """The held-out forces (N, by cause then trial) that each cause of ``model`` other than ``but`` adds to it:
    its forces less those with that cause's extension neutral; only causes whose size may differ between trials
    (not ``Extension.static``), the numbers rule R8 resizes (:mod:`.resize`).  Kept per model and held-out set.
    A static candidate is not judged by R8 (:func:`judge`): its effect is itself a size that differs between trials
    at different lengths, which a resize of a cause before it can mimic where the kinds of trial differ in length."""
    named = [c for c in model.extensions if c != but and not extension_class(c).static]
    held = [ctx.data.trials[i] for i in ctx.heldout]
    out = {}
    for c in named:
        key = (model.name, model.cost, c, tuple(ctx.heldout))
        if key not in ctx.contributions:
            off = simulate_all(model.parameters.with_values(extension_neutral(c)), held, model.extensions,
                               pool=ctx.pool)
            ctx.contributions[key] = {i: model.simulated[i] - off[i] for i in ctx.heldout}
        out[c] = ctx.contributions[key]
    return out


def judge(ctx: Context, name: str, before: FittedModel, model: FittedModel,
          telling_heldout: Sequence[str]) -> Evidence:
    """The evidence of candidate ``name`` (fitted: ``model``) against ``before`` (with ``ctx.reach``: what each
    reaches, the candidate in the model before's free parameters and its own), with every rule applied."""
    ext = extension_class(name)
    fitted = model
    resizable = {} if ext.static else contributions(ctx, before, name)
    before, model = reached_pair(ctx, name, before, model)
    n_par = len(ext.parameters)
    identified, calib = calibration_side(ctx, name, before, model)
    window, quiet = _windows(ctx, name, before, model, telling_heldout, fitted)
    ev = gather(ctx.heldout, ctx.measured, before.simulated, model.simulated, ctx.noise, n_par,
                identified, calib, window, quiet=quiet)
    if ctx.baseline is not None:
        ev.baseline_excess = excess(ctx.heldout, ctx.measured, ctx.baseline.simulated, ctx.noise)
    rest = rest_trends(ctx, model.simulated)
    have = {i: z for i, z in rest.items() if z is not None}
    ev.rest_left = [i for i, z in have.items() if abs(z) > REST_Z]
    ev.n_rest = len(have)
    if resizable:
        ev.resize_chi2_gain, ev.beyond_resize_chi2_gain = beyond_resize(
            ctx.heldout, ctx.measured, before.simulated, model.simulated, ctx.noise, resizable,
            {i: ctx.phases[i].movement_kind for i in ctx.heldout})
    apply_rules(ev)
    return ev


def fit_candidate(ctx: Context, name: str, before: FittedModel, screened: Screen | None) -> FittedModel:
    """Model ``before`` plus candidate ``name``, fitted from its starts (:func:`_starts`).  The model contains the
    model before (the extension at its neutral values), so its calibration chi-square can be no higher; when the
    fit stops above it (its starts far from the data's form and the candidate's iterations spent), it is fitted
    again from the model before itself, the extension at its neutral values, and the better fit is kept: a
    candidate is never judged worse than a model it contains."""
    fit = dict(extensions=before.extensions + (name,), baseline_free=refitted(ctx, name, *before.extensions),
               calibration=ctx.calibration_trials, all_trials=ctx.trials, noise=ctx.noise, pool=ctx.pool,
               tolerance=CANDIDATE_TOLERANCE, phases=ctx.phases)
    model = fit_model(starts=_starts(ctx, name, before, screened), **fit)
    floor = calibration_chi2(ctx, before.simulated)
    if model.cost <= floor:
        return model
    neutral = extension_neutral(name)
    values = {**extension_defaults(name), **(screened.time_constants if screened is not None else {}), **neutral}
    ctx.say(f"    {name}: its fit ends above the model before's calibration chi-square ({model.cost:.1f} > "
            f"{floor:.1f}); fitting again from the model before, the extension neutral")
    again = fit_model(starts={"model before, neutral": before.parameters.with_values(values)}, **fit)
    return again if again.cost < model.cost else model


def _starts(ctx: Context, name: str, before: FittedModel, screened: Screen | None) -> dict[str, ParameterSet]:
    """The candidate's starts: the model before with the extension at its defaults (or at the time constants its
    screen found best), and the same with the baseline parameters it interacts with at the base set's values."""
    ext = extension_class(name)
    values = {**extension_defaults(name), **(screened.time_constants if screened is not None else {})}
    first = before.parameters.with_values(values)
    back = at_base(ctx, first, [n for n in ext.interacts if n in ctx.baseline_free])
    return {"model before": first, "base set": back}


def at_base(ctx: Context, params: ParameterSet, names: Sequence[str]) -> ParameterSet:
    """``params`` with ``names`` put back at the base set's values.  When P0 is among them, the other force-valued
    parameters not among them (a0, c0: N) move with it, so the force-velocity curve keeps its shape relative to P0
    (and eq 11's asymptote (2 + c0/P0) Fc stays above Fc); one that would leave its physiological range stops at
    its edge (this is a start or a screening point, not a result: a fitted a0 near its upper bound, scaled up with
    P0, would otherwise make the start inadmissible).  Moving c0 towards 0 keeps the asymptote above Fc."""
    back = {n: ctx.base[n] for n in names}
    if "P0" in back and float(params["P0"]) > 0:
        ratio = float(back["P0"]) / float(params["P0"])
        reg = registry()
        for n in FORCE_PARAMETERS:
            if n not in back:
                spec = reg[reg.resolve(n)]
                back[n] = min(max(float(params[n]) * ratio, spec.lower), spec.upper)
    return params.with_values(back)


def trades_off_with_length(ctx: Context, name: str) -> bool:
    """Whether candidate ``name`` refits force-length parameters (g1, g2, P0) the baseline fitted: its screen,
    linearised at a Module 3 bent to absorb what it can of the effect, ranks it low however large the effect, so
    it is fitted whenever it beats its penalty and nothing has passed."""
    return bool(set(LENGTH_PARAMETERS) & set(refitted(ctx, name)))


def refitted(ctx: Context, *names: str) -> tuple[str, ...]:
    """The baseline parameters a fit of the causes ``names`` refits beside their own: those any of them interacts
    with (``Extension.interacts``) among the baseline's free ones.  The model before it is fitted in all of them,
    so the others stand near their optimum; the candidate's gain is, if anything, underestimated."""
    interacts = {p for n in names for p in extension_class(n).interacts}
    return tuple(n for n in ctx.baseline_free if n in interacts)


def _screens_from_the_base_length(ctx: Context, before: FittedModel, names: Sequence[str]) -> dict[str, Screen]:
    """Candidates that interact with the force-length parameters screened a second time, with those parameters
    put back at the base set's values (their fit's second start).  Eq 18's length dependence of activation and the
    force-length curve of eq 12 trade off: a model without eq 18 bends g1, g2 and P0 to take up what it can of
    it, and at the bent point the extension's linearised gain is small, though from the unbent one its fit gains
    most (module docstring, step 3).  Measured from the model's own chi-square; none when the length parameters
    are not free or are already at the base values."""
    length = [n for n in LENGTH_PARAMETERS if n in ctx.baseline_free]
    chosen = [n for n in names if set(length) & set(extension_class(n).interacts)]
    if not length or not chosen or all(before.parameters[n] == ctx.base[n] for n in length):
        return {}
    point = at_base(ctx, before.parameters, length)
    sims = simulate_all(point, ctx.calibration_trials, before.extensions, pool=ctx.pool)
    return screen(chosen, point, sims, ctx.calibration_trials, ctx.measured, ctx.noise, OPTIONS, pool=ctx.pool,
                  refitted=ctx.baseline_free, extensions=before.extensions,
                  subsets={n: refitted(ctx, n) for n in chosen},
                  model_chi2=calibration_chi2(ctx, before.simulated), at="base force-length")


def step(ctx: Context, index: int, before: FittedModel, max_fits: int = MAX_FITS) -> Step:
    """One step of the forward selection at model ``before`` (module docstring)."""
    out = Step(index, before)
    g1 = float(before.parameters["g1"])
    for name, ext in causes().items():
        if name in before.extensions:
            continue
        cal = telling_trials(ext, ctx.phases, g1, ctx.calibration)
        held = telling_trials(ext, ctx.phases, g1, ctx.heldout)
        why = None if cal else f"no calibration trial of the telling kind ({ext.telling.text})"
        out.candidates[name] = Candidate(name, cal, held, why)
    testable = [n for n, c in out.candidates.items() if c.untestable is None]
    if not testable:
        return out
    ctx.say(f"step {index}: screening {len(testable)} candidates at {before.name}")
    t0 = time.perf_counter()
    screens = screen(testable, before.parameters, before.simulated, ctx.calibration_trials, ctx.measured, ctx.noise,
                     OPTIONS, pool=ctx.pool, refitted=ctx.baseline_free, extensions=before.extensions,
                     subsets={n: refitted(ctx, n) for n in testable})
    for n, s in _screens_from_the_base_length(ctx, before, testable).items():
        if s.score > screens[n].score:
            screens[n] = s
    out.screen_s = time.perf_counter() - t0
    for n, s in screens.items():
        out.candidates[n].screen = s
    ranked = sorted(testable, key=lambda n: -screens[n].score)
    ctx.say("  scores (gain - penalty): " + "; ".join(f"{n} {screens[n].score:.4g}" for n in ranked))
    best = screens[ranked[0]].score
    fitted, budget = 0, max_fits
    for n in [n for n in ranked if screens[n].score > 0]:
        none_passed = not any(c.evidence.passed for c in out.candidates.values() if c.evidence is not None)
        if not (screens[n].score >= FIT_SHARE * best or none_passed):
            break
        if fitted >= budget and not (none_passed and trades_off_with_length(ctx, n)):
            continue
        fitted += 1
        c = out.candidates[n]
        fit_alone(ctx, c, before)
        if c.evidence.failed and set(c.evidence.failed) <= SMALL_ONLY:
            budget = max(budget, MAX_FITS_SMALL)
    passing = [n for n, c in out.candidates.items() if c.evidence is not None and c.evidence.passed]
    if passing:
        out.named = max(passing, key=lambda n: out.candidates[n].evidence.score)
    else:
        out.joint = joint(ctx, out)
        if out.joint is not None and out.joint.passed:
            out.named = out.joint.names[0]
    return out


def fit_alone(ctx: Context, c: Candidate, before: FittedModel) -> None:
    """Fit candidate ``c`` on ``before`` (module docstring, step 3) and judge it (step 4), in place."""
    ctx.say(f"  fitting {before.name} + {c.name}")
    c.model = fit_candidate(ctx, c.name, before, c.screen)
    if c.telling_heldout or not c.telling_calibration:
        c.evidence = judge(ctx, c.name, before, c.model, c.telling_heldout)
    else:
        c.evidence = judge_crossed(ctx, c, before)
    ctx.say(f"    {c.name} (from the {c.model.start}): {c.evidence.text()}")


def crossed(ctx: Context, trials: Sequence[str]) -> Context:
    """The split with the calibration trials ``trials`` moved to the held-out side (module docstring, step 4):
    where a candidate whose telling trials all calibrate is judged.  One per set of trials, kept for the whole
    selection (its refitted models with it, among them the baseline, for the baseline's excess in this
    split); it judges with the step's noise."""
    key = tuple(trials)
    sub = ctx.crossed.get(key)
    if sub is None:
        sub = replace(ctx, calibration=tuple(i for i in ctx.calibration if i not in key),
                      heldout=tuple(ctx.heldout) + key, baseline=None, crossed={}, refits={},
                      candidates={}, reaches={})
        ctx.crossed[key] = sub
    sub.noise = ctx.noise
    if sub.baseline is None and ctx.baseline is not None:
        sub.baseline = refit_on(sub, ctx.baseline)
    return sub


def refit_on(sub: Context, model: FittedModel) -> FittedModel:
    """``model`` (the baseline, or the baseline with named causes) fitted again on ``sub``'s calibration trials,
    in every parameter it was fitted in, from its own values; kept by model name."""
    if model.name not in sub.refits:
        sub.say(f"  fitting {model.name} again on {len(sub.calibration)} calibration trials")
        sub.refits[model.name] = fit_model(model.extensions, sub.baseline_free, {model.name: model.parameters},
                                           sub.calibration_trials, sub.trials, sub.noise, pool=sub.pool,
                                           max_iterations=MODEL_MAX_ITERATIONS, intervals="hac", phases=sub.phases)
    return sub.refits[model.name]


def judge_crossed(ctx: Context, c: Candidate, before: FittedModel) -> Evidence:
    """Candidate ``c``, whose telling trials all calibrate, judged by cross-validation over trials (module
    docstring, step 4): the model before and the candidate's model fitted again without those trials (the
    candidate from its usual starts, so nothing it learnt from them carries over), judged on the held-out trials
    and on them."""
    sub = crossed(ctx, c.telling_calibration)
    ctx.say(f"    {c.name}: every telling trial calibrates; judged with {', '.join(c.telling_calibration)} held "
            "out as well")
    before_cv = refit_on(sub, before)  # kept by name: the baseline's refit itself at the first step
    model = candidate_on(sub, c, before_cv)
    ev = judge(sub, c.name, before_cv, model, c.telling_calibration)
    ev.crossed = tuple(c.telling_calibration)
    return scored_on_every_calibration_trial(ev, ctx, c.name, before, c.model)


def scored_on_every_calibration_trial(ev: Evidence, ctx: Context, name: str, before: FittedModel,
                                      model: FittedModel) -> Evidence:
    """Evidence judged by cross-validation over trials, its calibration side (rule R1, and the score's calibration
    term) and its score's held-out term taken from the candidate's fit on every calibration trial of ``ctx``
    (``model``, against ``before``), the rules applied again.  Whether an effect is identified is a question about
    the calibration data, and the cross-validated fit lacks exactly the trials that tell it (a single post-tetanic
    series, a single long train): asked there, a cause with one telling trial could never be identified.  The
    held-out rules keep the cross-validated fits, which never saw the trials they are judged on.  The score ranks
    this candidate against the others of its step, which are judged against ``before`` on ``ctx``'s held-out trials;
    the cross-validated model before, fitted without some trials, predicts those worse, and a gain measured from it
    would count that loss as the candidate's.  So the score's held-out term is ``model`` against ``before`` on
    ``ctx``'s held-out trials (:func:`.evidence.heldout_chi2_gain`), the model that would be named against the model
    every candidate of the step is scored against."""
    ev.identified, (ev.calibration_chi2_gain, ev.calibration_penalty) = calibration_side(ctx, name, before, model)
    before_r, model_r = reached_pair(ctx, name, before, model)
    ev.ranking_chi2_gain, ev.ranking_penalty = heldout_chi2_gain(ctx.heldout, ctx.measured, before_r.simulated,
                                                                 model_r.simulated, ctx.noise,
                                                                 len(extension_class(name).parameters))
    return apply_rules(ev)


def candidate_on(sub: Context, c: Candidate, before_cv: FittedModel) -> FittedModel:
    """Candidate ``c`` fitted on the cross-validation split ``sub`` from ``before_cv`` (that model refitted there),
    from its usual starts; kept by model name for the whole selection."""
    name = f"{before_cv.name} + {c.name}"
    if name not in sub.candidates:
        sub.candidates[name] = fit_candidate(sub, c.name, before_cv, c.screen)
    return sub.candidates[name]


def pair_for(s: Step) -> tuple[Candidate, Candidate] | None:
    """The two candidates step 6 fits together at step ``s``: the material one (passing R0, R2 and R4 alone) with
    the best score, and the fitted candidate with the best score among those whose held-out gain beats their
    penalty (rule R2: a measured gain), else the one with the best screen (a linearised ranking); None when no
    candidate is material alone or no other one is beyond noise."""
    material = [c for c in s.candidates.values()
                if c.evidence is not None and not set(JOINT_IF_PASSES) & set(c.evidence.failed)]
    if not material:
        return None
    first = max(material, key=lambda c: c.evidence.score)
    measured = [c for c in s.candidates.values()
                if c.name != first.name and c.evidence is not None and "R2" not in c.evidence.failed]
    if measured:
        return first, max(measured, key=lambda c: c.evidence.score)
    others = [c for c in s.candidates.values()
              if c.name != first.name and c.screen is not None and c.screen.score > 0]
    return (first, max(others, key=lambda c: c.screen.score)) if others else None


def fit_together(ctx: Context, before: FittedModel, alone: Mapping[str, FittedModel]) -> FittedModel:
    """``before`` plus the two causes of ``alone`` (name -> that cause's model alone on ``before``), fitted together
    on ``ctx``'s calibration trials: the causes named before them and the baseline parameters any of them
    interacts with free, from each one's own fit with the other's extension parameters added."""
    (a, ma), (b, mb) = alone.items()
    free = refitted(ctx, a, b, *before.extensions)
    own = {n: {q: m.parameters[q] for q in extension_defaults(n)} for n, m in alone.items()}
    starts = {f"{a} model": ma.parameters.with_values(own[b]), f"{b} model": mb.parameters.with_values(own[a])}
    ctx.say(f"  fitting {before.name} + {a} + {b} together")
    return fit_model(before.extensions + (a, b), free, starts, ctx.calibration_trials, ctx.trials, ctx.noise,
                     pool=ctx.pool, tolerance=CANDIDATE_TOLERANCE, phases=ctx.phases)


def joint(ctx: Context, s: Step) -> Joint | None:
    """Step 6 of the module docstring at step ``s`` (where no candidate passed alone): the pair of
    :func:`pair_for`, fitted together and each judged against the model with the other alone; None when there is
    no pair.  When either was judged by cross-validation over trials, both are judged so, on the split that holds
    out every trial either was cross-validated with: the model before, each one alone and the pair fitted again
    there.  The pair's model is the one fitted on all calibration trials."""
    pair = pair_for(s)
    if pair is None:
        return None
    first, second = pair
    if not second.fitted:
        fit_alone(ctx, second, s.before)
    names = (first.name, second.name)
    alone = {first.name: first.model, second.name: second.model}
    model = fit_together(ctx, s.before, alone)
    key = tuple(dict.fromkeys(t for c in pair for t in c.evidence.crossed))
    where, judged, together = ctx, alone, model
    if key:
        where = crossed(ctx, key)
        ctx.say(f"    judged with {', '.join(key)} held out as well")
        before_cv = refit_on(where, s.before)
        judged = {c.name: candidate_on(where, c, before_cv) for c in pair}
        together = fit_together(where, before_cv, judged)
    evidence = {}
    for c in pair:
        other = second if c is first else first
        held = list(c.telling_heldout) + [t for t in c.telling_calibration if t in key]
        evidence[c.name] = judge(where, c.name, judged[other.name], together, held)
        evidence[c.name].crossed = key
        if key:
            scored_on_every_calibration_trial(evidence[c.name], ctx, c.name, alone[other.name], model)
        ctx.say(f"    {c.name} beside {other.name}: {evidence[c.name].text()}")
    return Joint(names, model, alone, evidence)


def consolidate(ctx: Context, model: FittedModel) -> FittedModel:
    """``model`` (the baseline plus the causes named so far) refitted in every baseline free parameter and every
    parameter of its extensions, from its own values: the next step starts from the best model with these causes,
    so every candidate there is judged against a model that no longer carries the compensations the baseline made
    for the causes already named."""
    return fit_model(model.extensions, ctx.baseline_free, {"model with the named causes": model.parameters},
                     ctx.calibration_trials, ctx.trials, ctx.noise, pool=ctx.pool, max_iterations=MODEL_MAX_ITERATIONS,
                     intervals="hac", phases=ctx.phases)


def select(ctx: Context, baseline: FittedModel, max_steps: int = MAX_STEPS, max_fits: int = MAX_FITS) -> list[Step]:
    """The forward selection from ``baseline`` (module docstring): every step, the last one naming nothing unless
    ``max_steps`` causes were named."""
    steps: list[Step] = []
    model = baseline
    ctx.baseline = baseline
    for k in range(1, max_steps + 1):
        ctx.noise = noise_under(ctx, model)
        s = step(ctx, k, model, max_fits)
        s.noise = dict(ctx.noise)
        steps.append(s)
        if s.named is None:
            break
        ctx.say(f"step {k}: named {s.named}; refitting {s.after.name} in every free parameter")
        model = consolidate(ctx, s.after)
        s.consolidated = model
    return steps
