"""The length compensation phi1..phi4 of the muscle (eq 18) from twitches at several lengths (Kim et al. 2015,
section 2.2.2).

For each twitch at length X, phi (the K5 scale) such that the simulated twitch peak equals the measured one
(brentq on phi with phi constant: phi1 = phi3 = 0, phi2 = phi4 = phi), then
:func:`~neuromuscle.identification.length_compensation_coefficients` (split at g1 when both sides have two
distinct lengths, one line otherwise).
"""

from __future__ import annotations

from dataclasses import asdict, replace
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..fit import SimulationOptions, trial_simulation
from ..analysis.closed_form import length_compensation_coefficients
from ..analysis.metrics import nrmse_percent
from ..measured import MeasuredData, Trial
from ..parameters import ParameterSet
from .stage import StageResult
from .trials import OPTIMUM_TOLERANCE_MM, all_trials, in_model_units, isometric_length, select_trials


def twitch_trials(data: MeasuredData | Sequence[Trial]) -> list[Trial]:
    """Isometric single-stimulus trials in N/mm."""
    return [t for t in all_trials(data) if in_model_units(t) and isometric_length(t) is not None
            and np.size(t.stimulus_times_s) == 1]


def _with_constant_phi(params: ParameterSet, phi: float) -> ParameterSet:
    return params.with_values(phi1=0.0, phi2=phi, phi3=0.0, phi4=phi)


def calibrate_length_compensation(data: MeasuredData, params: ParameterSet, trials: Sequence[str] | None = None,
                                  *, options: SimulationOptions | None = None,
                                  phi_range: tuple[float, float] = (0.2, 4.0),
                                  xtol: float = 1e-4) -> StageResult:
    """phi1..phi4 (eq 18) from twitches at >= 2 lengths: per twitch, the constant phi whose simulated twitch
    peak equals the measured peak (brentq), then length_compensation_coefficients at x_opt = g1.  options:
    dt and settling (the eq 18 switch is on and movement compensation off whatever they say)."""
    from scipy.optimize import brentq

    chosen = select_trials(data, trials)
    if chosen is None:
        chosen = twitch_trials(data)
    lengths = sorted({round(isometric_length(t), 9) for t in chosen if isometric_length(t) is not None})
    if len(lengths) < 2:
        raise InputError(f"length compensation: twitches at >= 2 lengths are needed, got lengths {lengths}")
    opts = replace(options or SimulationOptions(dt_ms=0.05, settle_ms=300.0), length_compensation=True,
                   movement_compensation=False)

    def sim(p: ParameterSet, t: Trial) -> np.ndarray:
        return trial_simulation(p, t, **asdict(opts))

    points, errors, notes = [], {}, []
    for t in chosen:
        x = float(isometric_length(t))
        f = np.asarray(t.force, dtype=float)
        target = float(np.max(np.convolve(f, np.ones(3) / 3.0, mode="same"))) if f.size >= 3 else float(f.max())

        def gap(phi: float) -> float:  # used within this iteration only
            return float(np.max(sim(_with_constant_phi(params, phi), t))) - target  # noqa: B023

        lo, hi = phi_range
        glo, ghi = gap(lo), gap(hi)
        if glo * ghi > 0:
            raise InputError(f"trial '{t.trial_id}': no phi in [{lo}, {hi}] matches the twitch peak "
                             f"{target:.4g} N (simulated peaks {glo + target:.4g} .. {ghi + target:.4g} N)")
        phi = float(brentq(gap, lo, hi, xtol=xtol))
        points.append((x, phi))
        errors[f"phi_at_{x:g}mm"] = phi
    # the split point: the twitch length nearest g1 when within OPTIMUM_TOLERANCE_MM (a fitted g1 is rarely
    # exactly the length of the optimum trials), else g1 itself
    near = min(lengths, key=lambda x: abs(x - params["g1"]))
    x_split = near if abs(near - params["g1"]) <= OPTIMUM_TOLERANCE_MM else params["g1"]
    split = (sum(1 for x in lengths if x <= x_split) >= 2 and sum(1 for x in lengths if x >= x_split) >= 2)
    coeffs = length_compensation_coefficients(points, x_split, split=split)
    if not split:
        notes.append("fewer than two lengths on one side of g1: one line through all points")
    final = params.with_values(**coeffs)
    for t in chosen:
        errors[f"nrmse_{t.trial_id}"] = nrmse_percent(t.force, sim(final, t))
    notes.append("phi per length makes the simulated twitch peak equal the measured one")
    return StageResult("length-compensation", coeffs, errors, [t.trial_id for t in chosen], notes)
