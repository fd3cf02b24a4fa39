"""The decision rules of the diagnosis, as a table: a candidate cause is named only when it passes every rule.

Each :class:`Rule` has an id, a short name, its threshold and a statement; its check reads the candidate's
:class:`~.evidence.Evidence` and returns why it fails, or None.  :func:`apply_rules` runs them all and records the
failures by rule id; reports list the rules from ``RULES`` itself, so what a report says is what the code does.

Why these rules.  A held-out gain beyond noise alone does not name a cause: a preparation differs from any model
in ways the calibration trials cannot pin down, and a flexible extension takes up some of that misfit on the
held-out trials too.  The rules ask, beyond the gain, that there be something to explain, that the extension's
effect be identified, that the gain be robust and material, and that it show where the cause acts, with nothing
left where no cause of the catalogue acts (the muscle at rest); and of a cause judged beside causes named before it,
that most of its gain be more than those causes would give with a size of their own for each kind of trial
(isometric, ramps, other movement; :mod:`.resize`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from .evidence import STRUCTURE_RATIO, Evidence

#: R0: a candidate that removes more than this share of the held-out excess passes R0 with no structured trial.
MIN_EXCESS_REMOVED_DIFFUSE = 0.5
#: R4: the least share of the held-out error above noise a named cause removes ...
MIN_EXCESS_REMOVED = 0.25
#: ... or of the error above noise on the held-out trials where it is judged (rule R7's trials).
MIN_WINDOW_EXCESS_REMOVED = 0.5
#: R8: the least share of its held-out chi-square gain a later cause keeps beyond a resize of the causes named
#: before it (one size per cause and kind of held-out trial).
MIN_BEYOND_RESIZE = 0.5
#: R6: a model leaves structure at rest when at least max(REST_MIN_TRIALS, REST_MIN_FRACTION x trials with a
#: rest window) trials trend at rest with |z| > REST_Z.
REST_Z = 3.0
REST_MIN_TRIALS = 3
REST_MIN_FRACTION = 0.2
#: The rules by which the backward check drops a cause named earlier (:mod:`.pruning`): those that ask whether it
#: still explains, identified, beyond noise and robustly, something the causes after it do not.  How much (R4) and
#: where and how it acts (R5-R7) were judged when it was named; against a model that holds a related cause beside
#: it they read how one effect is shared between two extensions, not whether the earlier one is needed.
REDUNDANCY_RULES = ("R0", "R1", "R2", "R3")


def enough_trials(n: int, of: int) -> bool:
    """At least max(REST_MIN_TRIALS, REST_MIN_FRACTION x ``of``) trials: enough to call a structure real."""
    return of > 0 and n >= max(REST_MIN_TRIALS, math.ceil(REST_MIN_FRACTION * of))


@dataclass(frozen=True)
class Rule:
    """One rule: ``id`` (R0...), ``name``, ``statement`` (what must hold) and ``check`` (evidence -> why it
    fails, or None)."""

    id: str
    name: str
    statement: str
    check: Callable[[Evidence], str | None]

    def to_json(self) -> dict[str, str]:
        return {"id": self.id, "name": self.name, "statement": self.statement}


def _something_to_explain(e: Evidence) -> str | None:
    if e.structured_before or e.excess_removed > MIN_EXCESS_REMOVED_DIFFUSE:
        return None
    return (f"no held-out trial has a residual RMS above {STRUCTURE_RATIO:g} noise sd under the model before it, "
            f"and it removes {100 * e.excess_removed:.0f} % <= {100 * MIN_EXCESS_REMOVED_DIFFUSE:.0f} % of the "
            "held-out error above noise")


def _identified(e: Evidence) -> str | None:
    if e.identified or e.calibration_chi2_gain > e.calibration_penalty:
        return None
    return (f"no effect parameter's 95 % interval excludes its neutral value, and the calibration chi2 gain "
            f"{e.calibration_chi2_gain:.1f} <= BIC penalty {e.calibration_penalty:.1f}")


def _beyond_noise(e: Evidence) -> str | None:
    return None if e.chi2_gain > e.bic_penalty else f"held-out chi2 gain {e.chi2_gain:.1f} <= BIC penalty " \
                                                     f"{e.bic_penalty:.1f}"


def _robust(e: Evidence) -> str | None:
    if e.bootstrap_p05 > 0:
        return None
    return f"bootstrap 5th percentile of the held-out gain {e.bootstrap_p05:.3g} <= 0"


def _material(e: Evidence) -> str | None:
    window = e.window_excess_removed
    if e.excess_removed >= MIN_EXCESS_REMOVED or (window is not None and window >= MIN_WINDOW_EXCESS_REMOVED):
        return None
    where = "" if window is None else (f", and {100 * window:.0f} % < {100 * MIN_WINDOW_EXCESS_REMOVED:.0f} % of "
                                       "it on the held-out trials where the cause is judged")
    return (f"removes {100 * e.excess_removed:.0f} % < {100 * MIN_EXCESS_REMOVED:.0f} % of the held-out error "
            f"above noise{where}")


def _nrmse_falls(e: Evidence) -> str | None:
    window = e.window_nrmse
    before, after = window if window is not None else (e.nrmse_before, e.nrmse_after)
    if after < before:
        return None
    where = "on the held-out trials where the cause is judged" if window is not None else "held-out"
    return f"mean NRMSE {where} does not fall ({before:.2f} -> {after:.2f} %)"


def _nothing_at_rest(e: Evidence) -> str | None:
    if not enough_trials(len(e.rest_left), e.n_rest):
        return None
    return (f"leaves a trend at rest (|z| > {REST_Z:g}) in {len(e.rest_left)} of {e.n_rest} trials: "
            f"{', '.join(e.rest_left)}")


def _where_it_acts(e: Evidence) -> str | None:
    if e.window_chi2_gain is None:
        return "no held-out sample where the cause is defined or where its extension changes the force"
    if e.quiet_chi2_gain is not None:
        if e.quiet_chi2_gain > e.quiet_penalty and e.quiet_p05 is not None and e.quiet_p05 > 0:
            return None  # it gains where it is defined, although the model before fitted there to noise
        trials = ", ".join(e.quiet_trials)
        if e.excess_removed <= MIN_EXCESS_REMOVED_DIFFUSE:
            return (f"the model before fits its telling trials ({trials}) to noise, so it is judged where it acts, "
                    f"and there it must remove more than {100 * MIN_EXCESS_REMOVED_DIFFUSE:.0f} % of the held-out "
                    f"error above noise: {100 * e.excess_removed:.0f} %")
        if e.quiet_chi2_gain < -e.quiet_penalty:
            return (f"fits its telling trials ({trials}) worse than the model before, which fits them to noise: chi2 "
                    f"gain {e.quiet_chi2_gain:.1f} < -{e.quiet_penalty:.1f}")
    if e.window_chi2_gain > e.window_penalty and e.window_p05 > 0:
        return None
    where = "defined" if e.window_how == "defined" else "acting"
    trials = ", ".join(map(str, e.window_trials))
    return (f"where the cause is {where} ({trials}) chi2 gain {e.window_chi2_gain:.1f} vs BIC penalty "
            f"{e.window_penalty:.1f}, bootstrap 5th percentile {e.window_p05:.3g}")


def _beyond_resize(e: Evidence) -> str | None:
    beyond = e.beyond_resize_chi2_gain
    if beyond is None or beyond >= MIN_BEYOND_RESIZE * e.chi2_gain:
        return None
    return (f"of its held-out chi2 gain {e.chi2_gain:.1f}, {beyond:.1f} remains beyond a resize of the causes "
            f"named before it, one size for each kind of held-out trial (which alone gains {e.resize_chi2_gain:.1f}); "
            f"at least {100 * MIN_BEYOND_RESIZE:.0f} % must")


RULES: tuple[Rule, ...] = (
    Rule("R0", "something to explain",
         f"under the model before it, a held-out trial has a residual RMS above {STRUCTURE_RATIO:g} noise sd, or "
         f"the candidate removes more than {100 * MIN_EXCESS_REMOVED_DIFFUSE:.0f} % of the held-out error above "
         "noise", _something_to_explain),
    Rule("R1", "identified",
         "an effect parameter's 95 % interval excludes its neutral value, or the calibration chi-square falls by "
         "more than the BIC penalty p ln(N_eff) (a likelihood ratio); for a candidate judged by cross-validation "
         "over trials, in its fit on every calibration trial", _identified),
    Rule("R2", "beyond noise and parameters",
         "the held-out chi-square gain, corrected for the noise's autocorrelation, exceeds the BIC penalty "
         "p ln(N_eff)", _beyond_noise),
    Rule("R3", "robust", "the 5th percentile of a moving-block bootstrap of the held-out gain is above 0", _robust),
    Rule("R4", "material",
         f"the candidate removes at least {100 * MIN_EXCESS_REMOVED:.0f} % of the held-out error above noise, or at "
         f"least {100 * MIN_WINDOW_EXCESS_REMOVED:.0f} % of it on the held-out trials where the cause is judged "
         "(rule R7's trials): a cause whose telling trials are few is material where it acts, beside error it "
         "cannot explain elsewhere", _material),
    Rule("R5", "better where a physiologist looks",
         "the mean NRMSE (eq 17) falls on the held-out trials where the cause is judged (rule R7's trials), or on "
         "every held-out trial when none is: a cause shows in the trials that tell it, and a cause with one telling "
         "trial barely moves a mean over every trial", _nrmse_falls),
    Rule("R6", "nothing left at rest",
         f"under the candidate's model, fewer than max({REST_MIN_TRIALS}, {100 * REST_MIN_FRACTION:.0f} %) of the "
         f"trials with a rest window trend at rest (|z| > {REST_Z:g}); no cause of the catalogue acts where the "
         "muscle is quiet", _nothing_at_rest),
    Rule("R7", "where it acts",
         "on the held-out samples where the cause is defined (its telling trials, held out by cross-validation "
         "when they all calibrate; for force enhancement and depression, the holds after the movement measured "
         "from the isometric force at that length) or, when no held-out trial is of that kind (a pair fitted "
         "together), where its fitted extension changes the force by more than half a noise "
         "sd, the chi-square gain exceeds the BIC penalty there and its bootstrap 5th percentile is above 0.  When "
         f"the model before fits every held-out telling trial to {STRUCTURE_RATIO:g} noise sd (they may not show "
         "the cause), a candidate that does not gain there may instead gain where its extension acts, if it also "
         f"removes more than {100 * MIN_EXCESS_REMOVED_DIFFUSE:.0f} % of the held-out error above noise (as R0 asks "
         "of a diffuse gain) and fits the telling trials no worse than the BIC penalty",
         _where_it_acts),
    Rule("R8", "more than a resize of the causes before it",
         f"at least {100 * MIN_BEYOND_RESIZE:.0f} % of the held-out chi-square gain remains when the causes named "
         "before the candidate may each take another size for each kind of held-out trial (isometric, ramps, other "
         "movement while stimulated), in the model before and in the candidate's alike: the first cause named takes "
         "its effect's average size, and what its form leaves in each kind of trial must not name a second cause.  A "
         "static property of the muscle (length-dependent activation) is neither resized nor asked: its effect is a "
         "size that differs between trials at different lengths",
         _beyond_resize),
)


def apply_rules(evidence: Evidence) -> Evidence:
    """Run every rule of ``RULES`` on ``evidence`` and record the failures (rule id -> why) in it; returns it."""
    evidence.failed = {r.id: why for r in RULES if (why := r.check(evidence)) is not None}
    return evidence


def rule(rule_id: str) -> Rule:
    """The rule with id ``rule_id``."""
    for r in RULES:
        if r.id == rule_id:
            return r
    raise KeyError(rule_id)
