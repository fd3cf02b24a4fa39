"""How much of a candidate's held-out gain a resize of the causes named before it would give: rule R8's numbers.

A catalogue extension is a form, and a preparation's effect of its kind need not follow it.  The commonest
difference is the effect's size from one trial to the next: a dependence on the stimulation rate, on the
movement's amplitude or on what the muscle did before that the form lacks.  Fitted first, a cause takes the
effect's average size; what it leaves in each trial is more of the same effect, and a second candidate whose
extension acts in those trials can take that up with a held-out gain well beyond noise.  Before a later cause is
named, its gain is therefore measured beyond what the causes already named would give with a size of their own in
every held-out trial.

For held-out trial k, with y_k the measured force, F_k the model before's and delta_k the candidate's change of it
(N), and D_ck = F_k - F_k(c neutral) the contribution of cause c named before (each whose size may differ between
trials: not ``Extension.static``), the resize is the least-squares fit of sum_c b_ck D_ck with b_ck >= -1 (each
cause's size times 1 + b_ck, never below zero):

* the resize's own gain G_r = sum_k w_k (|r_k|^2 - min_b |r_k - D_k b|^2), r_k = y_k - F_k;
* with the candidate, G_rc = sum_k w_k (|r_k|^2 - min_b |r_k - delta_k - D_k b|^2);
* **beyond the resize**: G_rc - G_r, the candidate's held-out gain that no resize of the causes before it gives;
  rule R8 compares it with the candidate's held-out gain sum_k w_k (|r_k|^2 - |r_k - delta_k|^2).

w_k is the trial's chi-square weight (:attr:`.residuals.Noise.chi2_weight`), so every gain here is in the
units of the evidence's chi-square gain.  The sizes are fitted on the held-out trial itself, for both models
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
                  contributions: Mapping[str, Mapping[str, np.ndarray]]) -> tuple[float, float]:
    """(G_r, G_rc - G_r) of the module docstring: the resize's own held-out gain and the candidate's gain beyond
    it (chi-square units), from the forces (N) by trial of the measurement, the model before and the candidate's
    model, and the contributions (N) of the resizable causes before it, by cause then trial."""
    resize = with_candidate = 0.0
    for i in heldout:
        cols = [c[i] for c in contributions.values() if np.any(c[i])]
        columns = np.column_stack(cols) if cols else None
        r = measured[i] - before[i]
        base = float(r @ r)
        w = noise[i].chi2_weight
        resize += w * (base - _left(r, columns))
        with_candidate += w * (base - _left(r - (after[i] - before[i]), columns))
    return resize, with_candidate - resize
