"""What a model reaches on the held-out trials by moving its own parameters within their calibration confidence
region, to first order: the held-out forces of the model before and of the candidate's model that every rule
reads when the diagnosis runs with ``reach=True`` (an option, off by default: it removed a false alarm and named
missed causes on the development files it came from, and on held-out files named what the default names, at more
cost; docs/validation/diagnosis.md).

Where the calibration trials leave a valley of equal fit (parameters they do not determine), the fitted model sits
somewhere on it, and its prediction of a held-out trial that depends on those parameters is as uncertain as the
valley is long.  A candidate whose fit moves the shared parameters along the valley then gains on that trial
without describing any effect.  The model before could have moved there itself; that gain is no evidence for the
candidate.  So the held-out forces of the model before, and those of the candidate's model, are replaced by those
each reaches after the move d of its free parameters (in the fits' search coordinates z) that minimises

    |r_h - J_h d|^2    subject to    d^T J_c^T J_c d + q |d|^2 / MAX_MOVE^2 <= q,    q = chi2(k, CONFIDENCE),

where r_h are its weighted held-out residuals (each trial's residual times sqrt of its chi-square weight,
``Noise.chi2_weight``), J_h and J_c the Jacobians of the weighted held-out and calibration forces in z (forward
differences at the fits' Jacobian step), and k its free parameters: the calibration chi-square rises by less than
the 95 % quantile for k parameters, and no coordinate moves by more than MAX_MOVE (a log-scaled parameter by a
factor of at most e^0.5), within the reach of a linearisation.  Without the confidence bound the move would trade
calibration fit for held-out fit.  Both models reach, in the same parameters (the model before's free ones, and
the candidate's own besides for the candidate): measured from the model before's reach alone, a real cause whose
effect the model before's parameters can partly imitate would lose what the model before gains that way, though
its own model reaches further still.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Mapping, Sequence

import numpy as np
from scipy.stats import chi2

from ..errors import NumericalError
from ..fit import FitProblem
from ..fit.evaluate import TrialPool, batched_residuals
from ..fit.optimizers import fd_jacobian
from ..measured import Trial
from .models import DIFFERENCE_DT_MS, OPTIONS, FittedModel, chi2_weights, extension_bounds
from .residuals import Noise

#: The calibration confidence region the move stays in.
CONFIDENCE = 0.95
#: The largest move of the search vector (Euclidean norm, search coordinates).
MAX_MOVE = 0.5
#: The finite-difference step in the search coordinates (one-sided inwards at a bound, :func:`fd_jacobian`).
STEP = 1e-3


def constrained_move(jc: np.ndarray, jh: np.ndarray, r: np.ndarray, q: float, max_move: float = MAX_MOVE
                     ) -> np.ndarray:
    """The move d minimising |r - jh d|^2 subject to d^T (jc^T jc + (q / max_move^2) I) d <= q (module
    docstring): the unconstrained least-squares move when it meets the bound, else the one on the bound (the
    trust-region subproblem, solved in the bound's own metric by bisection on its multiplier)."""
    k = jc.shape[1]
    metric = jc.T @ jc + (q / max_move ** 2) * np.eye(k)
    w, v = np.linalg.eigh(metric)
    lift = v / np.sqrt(w)                      # d = lift @ u, and d^T metric d = |u|^2
    u_, s, vt = np.linalg.svd(jh @ lift, full_matrices=False)
    b = u_.T @ r

    def u_at(lam: float) -> np.ndarray:
        denom = s ** 2 + lam
        return vt.T @ np.divide(s * b, denom, out=np.zeros_like(b), where=denom > 0)

    def size(lam: float) -> float:
        u = u_at(lam)
        return float(u @ u)

    lam = 0.0
    if size(0.0) > q:
        lo, hi = 0.0, 1.0
        while size(hi) > q:
            hi *= 4.0
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if size(mid) > q else (lo, mid)
        lam = hi
    return lift @ u_at(lam)


def heldout_reach(model: FittedModel, calibration: Sequence[Trial], heldout: Sequence[Trial],
                  noise: Mapping[str, Noise], pool: TrialPool | None = None,
                  free: Sequence[str] | None = None) -> dict[str, np.ndarray] | None:
    """The held-out forces (N, by trial id) ``model`` reaches by the move of the module docstring in the parameters
    ``free`` (default: those it was fitted in; a trial without a stimulus keeps the model's own), None when a run
    of the differences failed numerically (the model's own forces are then the reference)."""
    names = list(model.free if free is None else free)
    own = {t.trial_id: model.simulated[t.trial_id] for t in heldout}
    # a trial without a stimulus carries nothing on the parameters that activation sets: its force stays the model's
    calibration = [t for t in calibration if np.size(t.stimulus_times_s) > 0]
    heldout = [t for t in heldout if np.size(t.stimulus_times_s) > 0]
    if not names or not heldout or not calibration:
        return own
    bounds = extension_bounds(model.extensions)
    trials = list(calibration) + list(heldout)
    options = replace(OPTIONS, extensions=model.extensions, dt_ms=DIFFERENCE_DT_MS, differenced=True)
    problem = FitProblem(trials, model.parameters, {n: bounds.get(n) for n in names}, objective="sse",
                         weights=chi2_weights(trials, noise), options=options)
    lo, hi = problem.z_bounds()

    def run_all(zs: list[np.ndarray]) -> list[np.ndarray]:
        return pool.residuals(problem, zs) if pool is not None else batched_residuals(problem, zs)

    try:
        jac, _ = fd_jacobian(problem.to_z(model.parameters), lo, hi, run_all, "forward", STEP, None)
    except NumericalError:
        return None
    n_cal = sum(t.n_samples for t in calibration)
    # the residuals at the model's own forces (its step), the Jacobian's columns at the fits' Jacobian step
    r = problem.residuals_from([model.simulated[t.trial_id] for t in trials])[n_cal:]
    jh = jac[n_cal:]
    shift = jh @ constrained_move(jac[:n_cal], jh, -r, float(chi2.ppf(CONFIDENCE, len(names))))
    out, pos = own, 0
    for t in heldout:
        n = t.n_samples
        out[t.trial_id] = model.simulated[t.trial_id] + shift[pos:pos + n] / np.sqrt(noise[t.trial_id].chi2_weight)
        pos += n
    return out
