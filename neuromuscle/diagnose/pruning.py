"""The backward check after the forward selection: every cause named before the last one is judged again, by
every rule, against the final model without it, and dropped when the causes after it explain what it explained.

The forward selection names the most material cause first.  When two causes overlap in what they explain, the
first one named can be the wrong one: it takes up part of the true cause's effect, and the true cause, named
next, then explains the rest and most of what the first one explained.  The first name is redundant in the
final model, though it passed every rule against the model before it.  Each such cause is therefore judged
again as if it were the last candidate proposed: the final model without it, refitted in every free parameter
from the final values (:func:`without`), is its model before; the final model is its candidate model.  A cause
that now fails a rule of redundancy (``rules.REDUNDANCY_RULES``: nothing left to explain, not identified, not
beyond noise, not robust: the later causes explain what it explained) is dropped, the final model becomes the model
without it, and the check runs again on every cause left, until each passes those rules or one cause is left.  In
the first round the causes named at the last naming step are not judged again: they were judged against that very
model.  So every cause the diagnosis names explains, identified, beyond noise and robustly, something the others
do not: none is named for what the others explain.

How much a cause explains (R4) and where and how it acts (R5-R7) were judged when it was named, against the model
before it; they do not drop it here.  Against a model that holds a related cause beside it they read how one effect
is shared between two extensions: the final model without it refits the related one to take up what it can (the
staircase, on random-length trials at one rate, takes up part of movement-induced depression), so what is left to
the cause can fall under a quarter of the error, and a cause that still gains far beyond its penalty on its one
telling trial (potentiation on a post-tetanic series beside the doublet) can show a bootstrap of that trial's gain
below 0.  As in stepwise regression, where a term leaves the model at a laxer threshold than it entered by, a cause
is not dropped on a ground it was not named on.  The report gives every rule's outcome, these included.

A cause the forward selection judged by cross-validation over trials (its telling trials all calibrate) is
judged so here too, as at its own step: on the same split, the model without it fitted again there and the cause
fitted on it from its usual starts, its identification (rule R1) read from the final model on every calibration
trial.  The trials' noise is estimated from the final model's residuals, as each forward step estimates it from
its model before.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

from .evidence import Evidence
from .models import MODEL_MAX_ITERATIONS, FittedModel, fit_model
from .selection import (Context, Step, candidate_on, crossed, scored_on_every_calibration_trial, judge,
                        noise_under, refit_on)
from .rules import REDUNDANCY_RULES


@dataclass
class Check:
    """One named cause judged against the final model without it: that model, refitted (``without``), the
    evidence and the check's round (1, then 2 after a cause was dropped, ...)."""

    name: str
    without: FittedModel
    evidence: Evidence
    round: int

    @property
    def dropped(self) -> bool:
        """Whether it fails a rule of redundancy (module docstring)."""
        return any(r in self.evidence.failed for r in REDUNDANCY_RULES)


@dataclass
class Pruned:
    """The backward check's outcome: the causes kept, in their order, the final model with them, every check."""

    named: list[str]
    final: FittedModel
    checks: list[Check]

    @property
    def dropped(self) -> list[str]:
        return [c.name for c in self.checks if c.dropped]


def without(ctx: Context, model: FittedModel, name: str) -> FittedModel:
    """``model`` without extension ``name``, refitted in every baseline free parameter and every parameter of its
    other extensions, from ``model``'s values."""
    ctx.say(f"  fitting {model.name} without {name}")
    exts = tuple(e for e in model.extensions if e != name)
    return fit_model(exts, ctx.baseline_free, {f"final model without {name}": model.parameters},
                     ctx.calibration_trials, ctx.trials, ctx.noise, pool=ctx.pool,
                     max_iterations=MODEL_MAX_ITERATIONS, intervals="hac", phases=ctx.phases)


def check(ctx: Context, steps: Sequence[Step], name: str, final: FittedModel, rnd: int) -> Check:
    """Named cause ``name`` judged against ``final`` without it (module docstring)."""
    s = next(s for s in steps if name in s.named_causes)
    before = without(ctx, final, name)
    key = s.evidence_of(name).crossed
    if key:
        # as selection.judge_crossed does (module docstring)
        sub = crossed(ctx, key)
        ctx.say(f"    {name}: judged with {', '.join(key)} held out as well, as when it was named")
        before_cv = refit_on(sub, before)
        ev = judge(sub, name, before_cv, candidate_on(sub, s.candidates[name], before_cv), list(key))
        ev.crossed = tuple(key)
        ev = scored_on_every_calibration_trial(ev, ctx, name, before, final)
    else:
        ev = judge(ctx, name, before, final, s.candidates[name].telling_heldout)
    ctx.say(f"    {name} against {before.name}: {ev.text()}")
    return Check(name, before, ev, rnd)


def prune(ctx: Context, steps: Sequence[Step]) -> Pruned:
    """The backward check (module docstring) of the forward selection's ``steps``."""
    named = [n for s in steps for n in s.named_causes]
    final = steps[-1].after if steps else ctx.baseline
    naming = [s for s in steps if s.named is not None]
    last = set(naming[-1].named_causes) if naming else set()
    checks: list[Check] = []
    rnd = 0
    while len(named) > 1:
        judged = [n for n in named if n not in last]
        if not judged:
            break
        rnd += 1
        ctx.noise = noise_under(ctx, final)
        ctx.say(f"backward check {rnd}: {', '.join(judged)} against {final.name} without each")
        now = [check(ctx, steps, n, final, rnd) for n in judged]
        failing = [c for c in now if c.dropped]
        if not failing:
            checks += now
            break
        worst = min(failing, key=lambda c: c.evidence.score)
        checks += [c for c in now if c is worst or not c.dropped]   # the other failing ones are judged again
        ctx.say(f"  dropped {worst.name}: failed {', '.join(worst.evidence.failed)}")
        named.remove(worst.name)
        final = worst.without
        last = set()    # after a drop every cause left is judged against the new final model
    return Pruned(named, final, checks)
