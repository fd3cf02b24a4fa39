"""The baseline: the Kim, Sandercock & Heckman 2015 muscle without eq 18 and eqs 19-20 (those are the extensions of
``length_dependent_activation``, ``movement_induced_depression`` and ``lengthening_below_optimum``), calibrated on
the calibration trials, converged or saying that it did not.

1. **Scale.**  The base set (CT09 or CT95) is simulated once on the calibration trials and its force-like
   parameters (P0, a0, c0, N) are scaled by the median ratio of measured to simulated peak force, so a start is
   never a decade off for a muscle of another size.
2. **Staged estimate** (Kim, Sandercock & Heckman 2015, section 2.2.2; ``neuromuscle.calibration``): Module 3 from
   the file's force-length and force-velocity points and a step shortening (KSE) when it has them, then Module 2
   on the isometric stimulated trials at the optimum (or at the isometric length with most trials).
3. **Joint fit** (:func:`.models.fit_model`) of the parameters the file identifies (:func:`free_parameters`) on
   every calibration trial, from the staged estimate and from the scaled base set; the better start continues to
   convergence.  Module 3 comes from what the file offers: its static points when it has them (those parameters
   then stay as the points measured them), otherwise the isometric phases of the trials at several lengths and
   the ramps.  KSE and the force-velocity coefficients are fitted off the stimulated holds after movement, then
   held while the rest is fitted on every sample (:func:`.models.fit_model`): in those holds the baseline's force is
   isometric, and a history effect there would otherwise be taken up by a bent series element or force-velocity
   curve.

Moving trials, long trains and every other calibration trial take part in the joint fit: an effect in them may
bend the baseline, and the candidate that explains it is fitted with the same baseline freedom
(:mod:`.models`), so it unbends it.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from ..calibration import MODULE2_FREE, StageResult, calibrate_module2, staged_calibration
from ..errors import InputError
from ..fit.evaluate import TrialPool
from ..measured import MeasuredData, Trial
from ..parameters import SPECS, ParameterSet
from .models import MODEL_MAX_ITERATIONS, OPTIONS, FittedModel, fit_model, simulate_all
from .phases import TrialPhases
from .residuals import Noise, noise_level

#: Fewest calibration and held-out trials a diagnosis accepts.
MIN_CALIBRATION, MIN_HELDOUT = 4, 2
#: Parameters in N, scaled with the muscle's size in the scaled start.
FORCE_PARAMETERS = ("P0", "a0", "c0")
#: Module 2 and Module 1 parameters every baseline fit frees (the time course and rate dependence of activation).
ACTIVATION = ("C1", "C2", "C3", "alpha", "Umax", "tau2")
#: Lengths (mm) closer than this count as one.
LENGTH_TOL_MM = 0.5


@dataclass
class Baseline:
    """The calibrated baseline: the fitted model, its free parameters and why others are held, the base set scaled
    to the file's force, the staged estimate and its stages, and the noise of every trial (from the staged
    estimate's residuals)."""

    model: FittedModel
    free: tuple[str, ...]
    held: dict[str, str]
    scaled: ParameterSet
    staged: ParameterSet
    stages: list[StageResult]
    noise: dict[str, Noise]
    notes: list[str] = field(default_factory=list)

    @property
    def parameters(self) -> ParameterSet:
        return self.model.parameters

    @property
    def simulated(self) -> dict[str, np.ndarray]:
        return self.model.simulated


def check_trials(data: MeasuredData) -> None:
    """Refuse data a diagnosis cannot use, naming the trials: force not in N or length not in mm, a force too large
    to be in N (beyond 10 x the largest admissible P0: mN or g written as N), no stimulus times."""
    where = data.path or "the data"
    wrong = [f"'{t.trial_id}' ({t.force_unit}, {t.length_unit})" for t in data.trials.values()
             if t.force_unit != "N" or t.length_unit != "mm"]
    if wrong:
        raise InputError(f"{where}: trial(s) {', '.join(wrong)}: the muscle model needs force in N and length in mm; "
                         "convert joint moments and angles first")
    limit = 10.0 * SPECS["P0"].upper
    big = [f"'{t.trial_id}' (peak {np.max(np.abs(t.force)):.4g})" for t in data.trials.values()
           if np.max(np.abs(t.force)) > limit]
    if big:
        raise InputError(f"{where}: force of trial(s) {', '.join(big)} exceeds {limit:g} N (10 x the largest "
                         "admissible P0): the force channel is not in N (mN? g?); convert it to N")
    silent = [t.trial_id for t in data.trials.values() if np.size(t.stimulus_times_s) == 0]
    if silent:
        raise InputError(f"{where}: trial(s) {silent} have no stimulus times: the diagnosis compares stimulated "
                         "responses; remove passive trials (or add their stimulus times)")
    few = [t.trial_id for t in data.trials.values() if t.n_samples < 8]
    if few:
        raise InputError(f"{where}: trial(s) {few} have fewer than 8 samples: too few to estimate their noise")


def check_split_sizes(calibration: Sequence[str], heldout: Sequence[str]) -> None:
    """InputError when there are too few trials to calibrate or to judge."""
    if len(calibration) < MIN_CALIBRATION or len(heldout) < MIN_HELDOUT:
        raise InputError(f"too few trials: {len(calibration)} to calibrate and {len(heldout)} held out; a diagnosis "
                         f"needs at least {MIN_CALIBRATION} and {MIN_HELDOUT} (at least "
                         f"{MIN_CALIBRATION + MIN_HELDOUT} stimulated trials in N and mm)")


def _lengths(values: Sequence[float]) -> list[float]:
    """Distinct lengths (mm) among ``values``: within LENGTH_TOL_MM of a kept one count as it."""
    out: list[float] = []
    for x in sorted(values):
        if not out or x - out[-1] > LENGTH_TOL_MM:
            out.append(x)
    return out


def free_parameters(data: MeasuredData, phases: Mapping[str, TrialPhases],
                    calibration: Sequence[str]) -> tuple[tuple[str, ...], dict[str, str]]:
    """The baseline parameters the calibration trials identify, and those held with the reason.

    Always Module 2's C1, C2, C3, alpha, Module 1's Umax and tau2 and P0; C1 and C2 held when every stimulated
    calibration trial is a tetanus at one rate (they set the plateau's activation, of which only P0 x A is seen).
    g2 with isometric phases at two lengths or more or with active movement, g1 with three or more or with active
    movement.  With active movement: KSE and the force-velocity coefficients, a0 and b0 with shortening, c0 and d0
    with lengthening.  A file's force-length and force-velocity points and its step shortening give the staged
    estimate these start from, and the trials refine them: the points carry their own noise, force-length points
    near the optimum say little of the curve's width (seven points at 0.8-1 P0 and 1.8 % noise can miss g2 by a
    quarter, and trains at the long length then miss by far more than their noise), and the step's direct estimate
    of KSE reads low by the contractile element's shortening during the step."""
    cal = [phases[i] for i in calibration]
    held: dict[str, str] = {}
    free = list(ACTIVATION)
    rates = {round(p.regular_rate_hz) for p in cal if p.regular_rate_hz > 0}
    twitches = any(p.n_stimuli == 1 or p.regular_rate_hz == 0 for p in cal)
    if len(rates) <= 1 and not twitches:
        for n in ("C1", "C2"):
            free.remove(n)
            held[n] = "every calibration trial is a tetanus at one rate: the plateau's activation is confounded with P0"
    free.append("P0")
    lengths = _lengths([float(p.length_mm[m].mean()) for p in cal for m in [p.isometric_stimulated()] if m.any()])
    moving = [p for p in cal if p.active_movement]
    if len(lengths) >= 2 or moving:
        free.append("g2")
    else:
        held["g2"] = "isometric force at one length only"
    if len(lengths) >= 3 or moving:
        free.append("g1")
    else:
        held["g1"] = f"isometric force at {len(lengths)} length(s) and no movement"
    if not moving:
        for n in ("KSE", "a0", "b0", "c0", "d0"):
            held[n] = "no active movement in the calibration trials"
        return tuple(free), held
    free.append("KSE")
    shortening = any(np.any(p.moving & p.stimulated & (p.velocity_mm_s < 0)) for p in moving)
    lengthening = any(np.any(p.moving & p.stimulated & (p.velocity_mm_s > 0)) for p in moving)
    for names, ok, what in ((("a0", "b0"), shortening, "shortening"), (("c0", "d0"), lengthening, "lengthening")):
        for n in names:
            if ok:
                free.append(n)
            else:
                held[n] = f"no active {what} in the calibration trials"
    return tuple(free), held


def _peak_ratio(data: MeasuredData, ids: Sequence[str], sims: Mapping[str, np.ndarray]) -> float:
    """Median over trials of measured / simulated peak force."""
    r = [float(np.max(data.trials[i].force)) / float(np.max(sims[i])) for i in ids if float(np.max(sims[i])) > 0]
    return float(np.median(r)) if r else 1.0


def scaled_base(data: MeasuredData, calibration: Sequence[str], base: ParameterSet,
                pool: TrialPool | None) -> ParameterSet:
    """``base`` with its force parameters (FORCE_PARAMETERS, N) scaled by the median ratio of measured to
    simulated peak force over the calibration trials, kept inside P0's admissible range."""
    trials = [data.trials[i] for i in calibration]
    sims = simulate_all(base, trials, pool=pool)
    k = _peak_ratio(data, calibration, sims)
    lo, hi = SPECS["P0"].lower, SPECS["P0"].upper
    k = float(np.clip(k, lo / base["P0"] * 1.001, hi / base["P0"] * 0.999))
    return base.with_values(**{n: base[n] * k for n in FORCE_PARAMETERS})


def _say(progress: bool, text: str) -> None:
    if progress:
        print(f"[diagnose] {text}", file=sys.stderr, flush=True)


def calibrate_baseline(data: MeasuredData, phases: Mapping[str, TrialPhases], calibration: Sequence[str],
                       base: ParameterSet, *, pool: TrialPool | None = None, progress: bool = False) -> Baseline:
    """Calibrate the baseline on the ``calibration`` trials (module docstring) and simulate every trial of
    ``data`` with it.  pool: a TrialPool holding ``data``'s trials for every fit and simulation."""
    trials = list(data.trials.values())
    cal = [data.trials[i] for i in calibration]
    free, held = free_parameters(data, phases, calibration)
    _say(progress, f"baseline: scaling {base.name} to the file's force")
    scaled = scaled_base(data, calibration, base, pool)
    stage_ids = [i for i in calibration if phases[i].isometric_length_mm is not None or phases[i].protocol == "step"]
    notes = [f"{base.name} scaled to the file's force: P0 {base['P0']:.4g} -> {scaled['P0']:.4g} N"]
    if stage_ids:
        _say(progress, f"baseline: staged estimate on {len(stage_ids)} trials")
        sub = MeasuredData(trials={i: data.trials[i] for i in stage_ids}, attrs=data.attrs, path=data.path,
                           extra_datasets=data.extra_datasets, extra_attrs={})
        module2 = tuple(n for n in MODULE2_FREE if n in free)
        staged_cal = staged_calibration(sub, scaled, module2_free=module2, options=OPTIONS, max_iterations=8,
                                        progress=False, name=f"{base.name}-staged", length_compensation=False,
                                        pool=pool)
        staged, stages = staged_cal.parameters, list(staged_cal.stages)
        m2 = next(k for k, st in enumerate(stages) if st.stage == "module2")
        if stages[m2].skipped:  # no trial at the optimum: the isometric length with the most trials stands for it
            by_length: dict[float, list[str]] = {}
            for i in stage_ids:
                x = phases[i].isometric_length_mm
                if x is not None and phases[i].n_stimuli:
                    key = next((k for k in by_length if abs(k - x) <= LENGTH_TOL_MM), x)
                    by_length.setdefault(key, []).append(i)
            if by_length:
                x_ref = max(by_length, key=lambda k: (len(by_length[k]), -abs(k - staged["g1"])))
                r = calibrate_module2(sub, staged, by_length[x_ref], free=module2, options=OPTIONS, max_iterations=8,
                                      pool=pool)
                r.notes.append(f"no trial at g1 = {staged['g1']:g} mm: the isometric length with the most trials "
                               f"({x_ref:g} mm) stands for it")
                stages[m2] = r
                staged = staged.with_values(**r.values)
    else:
        staged, stages = scaled, [StageResult("staged", skipped="no isometric calibration trial: the scaled base "
                                                                "set starts the joint fit alone")]
    sims = simulate_all(staged, trials, pool=pool)
    noise = {i: noise_level(sims[i] - np.asarray(t.force, dtype=float)) for i, t in data.trials.items()}
    _say(progress, f"baseline: joint fit of {', '.join(free)} on {len(cal)} calibration trials, from the staged "
                   "estimate and the scaled base set")
    model = fit_model((), free, {"staged estimate": staged, f"scaled {base.name}": scaled}, cal, trials, noise,
                      pool=pool, max_iterations=MODEL_MAX_ITERATIONS, intervals="hac", phases=phases)
    if not model.converged:
        notes.append(f"the joint fit did not converge: {model.message}")
    return Baseline(model, free, held, scaled, staged, stages, noise, notes)


def calibration_trials(trials: Mapping[str, Trial], ids: Sequence[str]) -> list[Trial]:
    """The trials ``ids`` of ``trials``, in that order."""
    return [trials[i] for i in ids]
