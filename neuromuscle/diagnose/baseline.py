"""Step 1-2 of the diagnosis: the baseline model calibrated on the calibration trials, and every trial's error.

The baseline is Modules 1-3 with eq 18 and eqs 19-20 switched off (the length and movement extensions are
candidates, not baseline).  Calibration (``calibrate_baseline``), reusing :mod:`neuromuscle.calibration`, uses the
calibration trials of the seed's kind: isometric twitches and sub-tetanic trains (stimuli spanning at most
``MAX_TRAIN_S`` = 1 s, the seed's 1 s trains); longer trains and moving trials calibrate only the candidate
extensions (so a slow effect, e.g. fatigue, does not bend the baseline).  With 0.5 s, a standard ``synth`` file's
baseline saw its twitches and the 100 Hz train only: Module 2's rate dependence was not identified, and the
baseline's 10 Hz trials could sit at ~110 % NRMSE (suite seed 1's doublet case), a misfit that the residual
analysis then ranked as a cause.  When no calibration trial is of the seed's kind (e.g. a
preparation recorded only as long constant-rate tetani, as in stretch experiments), the isometric stimulated
calibration trials of any train length calibrate instead, and only step 2 runs (the seed's Module 2 stage needs
twitches or sub-tetanic trains; at one rate, Module 2's rate dependence is not identified, only the time course
of the tetanus' rise and fall and, with P0, its plateau).  Moving trials never calibrate the baseline: a
force-velocity or series-elastic fit to stretch-hold trials would absorb history effects (a steep eccentric
branch holds force after a stretch).  The one exception is a quick step shortening (protocol "step", a length
trace), the seed's measurement of the series-elastic stiffness: KSE = force drop / step / P0 (seed 2.2.2,
:func:`neuromuscle.calibration.module3.calibrate_kse`), read within 5 ms of the step, before any history effect
can act.  Until stop 28 the step trial was filtered out with the other moving trials, so KSE stayed at the base
set's 0.4 /mm whatever the preparation (synth draws 0.25-0.65 /mm).  In suite seed 1's relaxation preparation
(KSE 0.563 /mm), calibrating KSE lowers the reference's chi-square above noise from 8.9e3 to 2.3e3 noise variances
on its calibration trials and from 6.3e3 to 1.9e3 on the held-out ones, most of it in the moving trials.  After the
refinement moves P0, KSE is rescaled so that P0 x KSE, the stiffness the step measured (N/mm), is kept.

1. the seed's staged calibration (Module 3 from force-length / force-velocity points and a step when the file
   has them; Module 2 (C1, C2, C3, alpha) on isometric trials at the optimum; the eq 18 stage off).  When no
   trial lies at g1, Module 2 uses the isometric length with the most stimulated calibration trials;
2. a refinement of what the isometric calibration trials identify jointly: P0 (with >= 1 length), g2 (>= 2
   lengths), g1 (>= 3 lengths) unless force-length points calibrated them, with C1, C2, C3, alpha (a preparation's
   parameters differ from CT09 by tens of percent in every module).  It starts from the staged estimate and,
   when step 1 left a Module 2 parameter unidentified, also from the base set's Module 2, and keeps the lower
   cost: a stage fitted on few trials can leave Module 2 where the others' gradient vanishes (suite seed 1's
   doublet case with trains up to 0.5 s: the Module 2 stage saw only a 100 Hz tetanus, put alpha at its bound 8
   and C1 at 0.028, unidentified, and the refinement from there left every twitch at ~100 % NRMSE; from CT09's
   Module 2, 10-11 %).

Simulation: fixed step ``DT_MS`` = 0.1 ms (twitch peak error 0.27 % against SciPy, README; well below the 1-2 %
noise of measured force), recorded every 0.5 ms, no settling before the trial's first sample (``SETTLE_MS`` = 0):
every mechanism, extensions included, starts at its resting steady state at the trial's first length
(``MuscleUnit(initial_state="rest")``), so a settling run changes nothing but the cost.  Until stop 31 every run
settled 300 ms first, 10 % of all the steps of a standard file's diagnosis; on a twitch, a train, a ramp, a hold,
the random length and the step, with every extension at its defaults, the force with and without it differs by
at most 7e-5 % of P0 (``tests/diagnose/test_diagnose_baseline.py``).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ..analysis.metrics import nrmse_percent
from ..calibration import MODULE2_FREE, StageResult, calibrate_module2, staged_calibration
from ..calibration.staged import FORCE_LENGTH_PATH
from ..calibration.module3 import kse_from_steps
from ..calibration.trials import OPTIMUM_TOLERANCE_MM, is_step_trial, isometric_length
from ..errors import InputError, NumericalError
from ..fit import FitProblem, SimulationOptions, fit, trial_simulation
from ..fit.evaluate import TrialPool
from ..measured import MeasuredData, Trial
from ..parameters import SPECS, ParameterSet

DT_MS = 0.1
#: Simulated time (ms) before a trial's first sample: none, as the model starts at rest (module docstring).
SETTLE_MS = 0.0
OPTIONS = SimulationOptions(dt_ms=DT_MS, record_dt_ms=0.5, settle_ms=SETTLE_MS, length_compensation=False,
                            movement_compensation=False)
#: Longest stimulus train (s) used to calibrate the baseline.
MAX_TRAIN_S = 1.0
#: Module 2 parameters held at their base values when the baseline is calibrated from tetani at a single rate
#: (they set the plateau's activation at that rate, which only P0 x A is seen of).
TETANIC_ONE_RATE_FIXED = ("C1", "C2")
#: Fewest calibration and held-out trials a diagnosis accepts.
MIN_CALIBRATION, MIN_HELDOUT = 4, 2


@dataclass
class Baseline:
    """The calibrated baseline: parameters, the stages that made them, each trial's simulated force (N) and NRMSE
    (%, eq 17), and the simulation options."""

    parameters: ParameterSet
    stages: list[StageResult]
    simulated: dict[str, np.ndarray]
    nrmse: dict[str, float]
    options: SimulationOptions


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


def check_split_sizes(calibration: Sequence[str], heldout: Sequence[str]) -> None:
    """InputError when there are too few trials to calibrate or to judge."""
    if len(calibration) < MIN_CALIBRATION or len(heldout) < MIN_HELDOUT:
        raise InputError(f"too few trials: {len(calibration)} to calibrate and {len(heldout)} held out; a diagnosis "
                         f"needs at least {MIN_CALIBRATION} and {MIN_HELDOUT} (at least "
                         f"{MIN_CALIBRATION + MIN_HELDOUT} stimulated trials in N and mm)")


def _subset(data: MeasuredData, ids: Sequence[str]) -> MeasuredData:
    return MeasuredData(trials={i: data.trials[i] for i in ids}, attrs=data.attrs, path=data.path,
                        extra_datasets=data.extra_datasets, extra_attrs=data.extra_attrs)


def _seed_kind(t: Trial) -> bool:
    """An isometric trial whose stimuli span at most MAX_TRAIN_S (a twitch or a sub-tetanic train)."""
    s = np.asarray(t.stimulus_times_s, dtype=float)
    return isometric_length(t) is not None and s.size >= 1 and float(s.max() - s.min()) <= MAX_TRAIN_S


def _stimulated_isometric(t: Trial) -> bool:
    """An isometric trial with at least one stimulus (any train length)."""
    return isometric_length(t) is not None and np.size(t.stimulus_times_s) >= 1


def baseline_trials(data: MeasuredData, calibration: Sequence[str]) -> tuple[str, list[str]]:
    """Which calibration trials calibrate the baseline, and the kind: ("seed", the isometric twitches and short
    trains) when there are any, else ("tetanic", every isometric stimulated trial); InputError with neither."""
    seed = [i for i in calibration if _seed_kind(data.trials[i])]
    if seed:
        return "seed", seed
    tetani = [i for i in calibration if _stimulated_isometric(data.trials[i])]
    if tetani:
        return "tetanic", tetani
    raise InputError(f"no calibration trial is isometric and stimulated (a twitch, a train or a tetanus at one "
                     f"length): the baseline cannot be calibrated (calibration trials: {', '.join(calibration)})")


def step_trials(data: MeasuredData, calibration: Sequence[str]) -> list[str]:
    """The calibration trials that measure the series-elastic stiffness: protocol "step" with a length trace, in
    N and mm (the staged calibration's KSE stage reads them)."""
    return [i for i in calibration if is_step_trial(data.trials[i])]


def _isometric(trials: Sequence[Trial]) -> dict[float, list[Trial]]:
    """Isometric trials grouped by length (mm): lengths within OPTIMUM_TOLERANCE_MM of a group's first (shortest)
    length are one length (measured lengths scatter by the transducer's noise)."""
    out: dict[float, list[Trial]] = {}
    for x, t in sorted(((isometric_length(t), t) for t in trials if isometric_length(t) is not None),
                       key=lambda p: p[0]):
        key = next((k for k in out if abs(x - k) <= OPTIMUM_TOLERANCE_MM), round(x, 6))
        out.setdefault(key, []).append(t)
    return out


def _rates_hz(trials: Sequence[Trial]) -> set[float]:
    """The distinct mean stimulation rates (Hz, to 1 Hz) of trials with two stimuli or more."""
    out = set()
    for t in trials:
        s = np.sort(np.asarray(t.stimulus_times_s, dtype=float))
        if s.size >= 2 and s[-1] > s[0]:
            out.add(round((s.size - 1) / (s[-1] - s[0])))
    return out


def _say(progress: bool, text: str) -> None:
    if progress:
        print(f"[diagnose] {text}", file=sys.stderr, flush=True)


def calibrate_baseline(data: MeasuredData, calibration: Sequence[str], base: ParameterSet, *, workers: int = 1,
                       options: SimulationOptions = OPTIONS, progress: bool = False,
                       max_iterations: int = 12, pool: TrialPool | None = None) -> Baseline:
    """Calibrate the baseline on the ``calibration`` trials (module docstring) and simulate every trial of
    ``data``.  pool: a :class:`~neuromuscle.fit.evaluate.TrialPool` of ``data``'s trials for every fit and
    simulation, instead of ``workers`` processes per fit."""
    kind, ids = baseline_trials(data, calibration)
    steps = step_trials(data, calibration)
    cal = _subset(data, ids)
    calibration = list(cal.trials)
    by_length = _isometric(list(cal.trials.values()))
    if kind == "seed":
        _say(progress, f"baseline: staged calibration on {len(calibration)} trials"
                       + (f" (KSE from {', '.join(steps)})" if steps else ""))
        # the step trials reach only the KSE stage: Module 2's and the length stage's trials are isometric
        staged = staged_calibration(_subset(data, ids + steps), base, options=options, workers=workers,
                                    max_iterations=max_iterations, progress=False, name=f"{base.name}-baseline",
                                    length_compensation=False, pool=pool)
        params, stages = staged.parameters, list(staged.stages)
    else:
        params = base
        stages = [StageResult("module2", skipped=(
            f"no isometric twitch or train of <= {MAX_TRAIN_S} s: the seed's Module 2 stage cannot run; Module 2 "
            "is refined jointly with P0 on the isometric tetani (one rate: its rate dependence is not identified)"))]
        if steps:
            stages.append(kse_from_steps([data.trials[i] for i in steps], params["P0"]))
            params = params.with_values(**stages[-1].values)
    kse_calibrated = any(s.stage == "KSE" and not s.skipped for s in stages)
    p0_at_kse = params["P0"]
    m2 = next(s for s in stages if s.stage == "module2")
    if kind == "seed" and m2.skipped:
        x_ref = max(by_length, key=lambda x: (len(by_length[x]), -abs(x - params["g1"])))
        ids = [t.trial_id for t in by_length[x_ref]]
        _say(progress, f"baseline: Module 2 at {x_ref:g} mm (no trial at g1 = {params['g1']:g} mm)")
        r = calibrate_module2(cal, params, ids, options=options, workers=workers, max_iterations=max_iterations,
                              pool=pool)
        r.notes.append(f"no trial at g1: the isometric length with most trials ({x_ref:g} mm) stands for it")
        stages[stages.index(m2)] = r
        params = params.with_values(**r.values)
    free = list(MODULE2_FREE)
    if kind == "tetanic" and len(_rates_hz(list(cal.trials.values()))) <= 1:
        free = [p for p in free if p not in TETANIC_ONE_RATE_FIXED]
        stages[0].notes.append(f"one stimulation rate: {', '.join(TETANIC_ONE_RATE_FIXED)} (the Ca2+ sensitivity "
                               "of the plateau) are confounded with P0 and held at their base values")
    if kind == "tetanic" or FORCE_LENGTH_PATH not in data.extra_datasets:
        n_len = len(by_length)
        free = ["P0"] + (["g2"] if n_len >= 2 else []) + (["g1"] if n_len >= 3 else []) + free
    trials = [t for ts in by_length.values() for t in ts]
    _say(progress, f"baseline: joint refinement of {', '.join(free)} on {len(trials)} isometric trials")
    starts = {"the staged estimate": params}
    m2 = next(s for s in stages if s.stage == "module2")
    if m2.fit is not None and m2.fit.flags:  # a Module 2 the stage's trials did not identify: a second start
        starts[f"{base.name}'s Module 2"] = params.with_values(**{k: base[k] for k in MODULE2_FREE})
    results = {how: fit(FitProblem(trials, start, free, objective="nrmse", options=options),
                        workers=workers if pool is None else 1, pool=pool, progress=False,
                        max_iterations=max_iterations, fd="forward") for how, start in starts.items()}
    how, res = min(results.items(), key=lambda kv: kv[1].cost)
    params = starts[how].with_values(**res.estimates)
    notes = [f"from {how} (cost {', '.join(f'{r.cost:.4g} from {h}' for h, r in results.items())}): "
             f"{res.n_iterations} iterations, {res.n_simulations} simulations: {res.message}"]
    if kse_calibrated and params["P0"] != p0_at_kse:  # keep the stiffness the step measured, P0 x KSE (N/mm)
        params = params.with_values(KSE=params["KSE"] * p0_at_kse / params["P0"])
        notes.append(f"KSE rescaled by P0 {p0_at_kse:.4g} -> {params['P0']:.4g} N (P0 x KSE, the step's "
                     f"stiffness, kept): {params['KSE']:.4g} /mm")
    stages.append(StageResult("refinement", dict(res.estimates),
                              {f"nrmse_{k}": v for k, v in res.nrmse_percent.items()}, [t.trial_id for t in trials],
                              notes, fit=res))
    final = ParameterSet(f"{base.name}-baseline", params.values,
                         f"diagnosis baseline (eq 18, eqs 19-20 off) calibrated from {base.name} on "
                         f"{', '.join(calibration)}")
    _say(progress, f"baseline: simulating {len(data.trials)} trials")
    sims = simulate_all(final, list(data.trials.values()), options, pool=pool)
    return Baseline(final, stages, sims, {k: nrmse_percent(data.trials[k].force, s) for k, s in sims.items()},
                    options)


def simulate_all(params: ParameterSet, trials: Sequence[Trial], options: SimulationOptions,
                 extensions: tuple[str, ...] = (), pool: TrialPool | None = None) -> dict[str, np.ndarray]:
    """Simulated force (N) of every trial, by trial id (on ``pool``'s workers when given)."""
    opts = replace(options, extensions=extensions)
    if pool is not None:
        sims = pool.simulate([params], trials, opts)[0]
        if sims is None:
            raise NumericalError(f"{params.name}: a trial's simulation failed numerically")
        return {t.trial_id: s for t, s in zip(trials, sims)}
    return {t.trial_id: trial_simulation(params, t, opts.dt_ms, record_dt_ms=opts.record_dt_ms,
                                         settle_ms=opts.settle_ms, length_compensation=opts.length_compensation,
                                         movement_compensation=opts.movement_compensation,
                                         extensions=opts.extensions) for t in trials}
