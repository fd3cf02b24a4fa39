"""How much of a candidate's held-out gain a resize of the causes named before it would give: rule R8's numbers.

A catalogue extension is a form, and a preparation's effect of its kind need not follow it.  The commonest
difference is how the effect's size carries from one kind of trial to another: a movement effect fitted on ramps
and random length together, or fatigue fitted on isometric trains and acting in moving ones, takes the average of
what the kinds ask, and what it leaves in each kind is more of the same effect.  A second candidate whose extension
acts in those trials can take that up with a held-out gain well beyond noise.  Before a later cause is named, its
gain is therefore measured beyond what the causes already named would give with a size of their own for each kind
of held-out trial: isometric, ramps, or other movement while stimulated
(:attr:`.phases.TrialPhases.movement_kind`).

One size per kind, not per trial: a size for every trial also stands in for a real second effect that changes each
trial's force in proportion to the first one's contribution there (movement-induced depression beside fatigue or
force enhancement, potentiation beside the staircase), which a trial-by-trial resize takes up.  Within a kind the
trials differ in rate and history, and that dependence is the form's own to carry.

For held-out trial k of kind g, with y_k the measured force, F_k the model before's and delta_k the candidate's
change of it (N), and D_ck = F_k - F_k(c neutral) the contribution of cause c named before (each whose size may
differ between trials: not ``Extension.static``), the resize is the least-squares fit of sum_c b_cg D_ck with
b_cg >= -1 (each cause's size times 1 + b_cg, never below zero), one b_cg for all the held-out trials of kind g:

* the resize's own gain G_r = sum_g (sum_k w_k |r_k|^2 - min_b sum_k w_k |r_k - D_k b|^2), r_k = y_k - F_k, the
  inner sums over the trials of kind g;
* with the candidate, G_rc the same with r_k - delta_k in the second term;
* **beyond the resize**: G_rc - G_r, the candidate's held-out gain that no resize of the causes before it gives;
  rule R8 compares it with the candidate's held-out gain sum_k w_k (|r_k|^2 - |r_k - delta_k|^2).

w_k is the trial's chi-square weight (:attr:`.residuals.Noise.chi2_weight`), so every gain here is in the
units of the evidence's chi-square gain.  The sizes are fitted on the held-out trials themselves, for both models
alike: the resize is a control, as generous to the model before as to the candidate, not a prediction.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np
from scipy.optimize import lsq_linear

from .residuals import Noise

#: A resized cause's size in a trial is its fitted size times 1 + b, b >= LOWEST_RESIZE: never of the other sign.
LOWEST_RESIZE = -1.0


def _left(r: np.ndarray, columns: np.ndarray | None) -> float:
    """The squared residual left when ``r`` is fitted by the columns (b >= LOWEST_RESIZE), N^2."""
    if columns is None:
        return float(r @ r)
    sol = lsq_linear(columns, r, bounds=(np.full(columns.shape[1], LOWEST_RESIZE), np.inf))
    e = r - columns @ sol.x
    return float(e @ e)


def beyond_resize(heldout: Sequence[str], measured: Mapping[str, np.ndarray], before: Mapping[str, np.ndarray],
                  after: Mapping[str, np.ndarray], noise: Mapping[str, Noise],
                  contributions: Mapping[str, Mapping[str, np.ndarray]],
                  kinds: Mapping[str, str]) -> tuple[float, float]:
    """(G_r, G_rc - G_r) of the module docstring: the resize's own held-out gain and the candidate's gain beyond
    it (chi-square units), from the forces (N) by trial of the measurement, the model before and the candidate's
    model, the contributions (N) of the resizable causes before it, by cause then trial, and each held-out trial's
    kind of movement (:attr:`.phases.TrialPhases.movement_kind`): one size per cause and kind."""
    groups: dict[str, list[str]] = {}
    for i in heldout:
        groups.setdefault(kinds[i], []).append(i)
    resize = with_candidate = 0.0
    for trials in groups.values():
        root_w = {i: float(np.sqrt(noise[i].chi2_weight)) for i in trials}
        r = np.concatenate([root_w[i] * (measured[i] - before[i]) for i in trials])
        delta = np.concatenate([root_w[i] * (after[i] - before[i]) for i in trials])
        cols = [col for c in contributions.values()
                if np.any(col := np.concatenate([root_w[i] * c[i] for i in trials]))]
        columns = np.column_stack(cols) if cols else None
        base = float(r @ r)
        resize += base - _left(r, columns)
        with_candidate += base - _left(r - delta, columns)
    return resize, with_candidate - resize
