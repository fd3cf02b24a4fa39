"""A synthetic preparation as a measured-data file: varied parameters, the standard protocols, one hidden effect,
AR(1) transducer noise, and the generator's truth kept apart in ``/synth``.

Randomness comes from four independent streams of ``seed``: parameters, noise, drift and the static calibration
points.  So the files of one seed share the preparation and the noise whatever the cause: a cause's file minus the
null file of the same seed is the effect itself.
"""

from __future__ import annotations

import json
import numbers
from dataclasses import replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..analysis.module3 import force_length, hill_tension, mashima_tension
from ..calibration.staged import FORCE_LENGTH_PATH, FORCE_VELOCITY_PATH
from ..errors import InputError
from ..fit.evaluate import candidate_map, trial_simulation
from ..fit.synthetic import ar1_noise
from ..measured import MeasuredData, Trial
from ..measured.hdf5 import write_measured
from ..parameters import ParameterSet, load_parameters, registry
from ..reports.outdir import refuse_existing_file
from .effects import ALL, GRID_MS, TrialInput, hidden_effect, modulation, transducer_drift
from .play import played_models
from .protocols import PlannedTrial, protocol_builder
from .variation import draw_preparation

TRUTH_PATH = "/synth"
SCHEMA = "neuromuscle.synth/1"
DT_MS = 0.025
SETTLE_MS = 300.0
RECORD_DT_MS = 0.5
#: Static calibration points (extra datasets read by the staged calibration): lengths relative to the optimum
#: (mm) and velocities (mm/s) at full activation.
FORCE_LENGTH_OFFSETS_MM = (-12.0, -9.0, -6.0, -3.0, 0.0, 3.0, 5.0)
FORCE_VELOCITY_MM_S = (-160.0, -80.0, -40.0, -10.0, -1.0, 1.0, 10.0, 40.0, 80.0)


def cause_names() -> list[str]:
    """Every name ``make_dataset`` accepts besides None: the ten canonical causes, then the out-of-catalogue
    effect(s)."""
    return list(ALL)


def _check_settings(cause: str | None, strength: float, seed: int, noise_pct: float, noise_tau_ms: float,
                    workers: int) -> str | None:
    if cause is not None and not isinstance(cause, str):
        raise InputError(f"cause must be a cause name or None, got {cause!r}")
    name = None if cause in (None, "none") else cause
    if name is not None:
        hidden_effect(name)
    for label, v, lo, hi in (("strength", strength, 0.0, 1.0), ("noise_pct", noise_pct, 0.0, 20.0),
                             ("noise_tau_ms", noise_tau_ms, 0.0, 1000.0)):
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not (lo <= float(v) <= hi):
            raise InputError(f"{label} must be a number in [{lo:g}, {hi:g}], got {v!r}")
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {seed!r}")
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise InputError(f"workers must be an integer >= 1, got {workers!r}")
    return name


def _empty_trial(plan: PlannedTrial) -> Trial:
    attrs = {**plan.attrs, "sample_rate_hz": float(round(1.0 / float(plan.time_s[1] - plan.time_s[0])))}
    return Trial(trial_id=plan.trial_id, protocol=plan.protocol, time_s=plan.time_s.copy(),
                 force=np.zeros_like(plan.time_s), force_unit="N", length_unit="mm", length_const=plan.length_mm,
                 length=None if plan.length_trace_mm is None else plan.length_trace_mm.copy(),
                 stimulus_times_s=plan.stimulus_times_s.copy(), attrs=attrs)


def trial_input(trial: Trial, params: ParameterSet, settle_ms: float = SETTLE_MS) -> TrialInput:
    """What a hidden effect sees of ``trial`` on the simulation clock of ``trial_simulation`` (time_s[0] at
    settle_ms, the length held at its first value before)."""
    t0 = float(trial.time_s[0])
    duration_ms = settle_ms + (float(trial.time_s[-1]) - t0) * 1000.0
    t_ms = np.append(np.arange(0.0, duration_ms, GRID_MS), duration_ms)
    trial_s = np.clip((t_ms - settle_ms) / 1000.0 + t0, t0, float(trial.time_s[-1]))
    x = trial.length_at(trial_s)
    v = np.gradient(x, t_ms) * 1000.0 if x.size > 1 else np.zeros_like(x)
    spikes = settle_ms + (np.asarray(trial.stimulus_times_s, dtype=float) - t0) * 1000.0
    return TrialInput(t_ms, x, v, spikes, float(params["g1"]), float(params["g2"]), float(params["P0"]))


def _run(params: ParameterSet, trial: Trial, series: dict, dt_ms: float) -> np.ndarray:
    """Force (N) of ``trial`` at its samples, the port ``series`` played into the baseline."""
    excitation, contraction = played_models(series)
    sample_ms = 1000.0 * float(trial.time_s[1] - trial.time_s[0])
    return trial_simulation(params, trial, dt_ms, record_dt_ms=min(RECORD_DT_MS, sample_ms), settle_ms=SETTLE_MS,
                            excitation=excitation, contraction=contraction)


def _simulate(job: tuple) -> np.ndarray:
    """Clean force (N) of one trial under one hidden effect (module level, for worker processes).  A
    ``force_scale`` series multiplies the output force: KimForce's output does not feed back into the CE, so this
    equals playing force_offset = (scale - 1) F into it, without a second run."""
    params, trial, cause, amplitude, dt_ms = job
    series = {} if cause is None else modulation(cause, trial_input(trial, params), amplitude)
    scale = series.pop("force_scale", None)
    force = _run(params, trial, series, dt_ms)
    if scale is None:
        return force
    t_ms = SETTLE_MS + (np.asarray(trial.time_s) - float(trial.time_s[0])) * 1000.0
    return force * np.interp(t_ms, *scale)


def _static_points(params: ParameterSet, optimum_mm: float, sd_N: float,
                   rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Force-length and force-velocity points at full activation (eqs 10-12 of the true Module 3) plus noise."""
    x = optimum_mm + np.asarray(FORCE_LENGTH_OFFSETS_MM)
    fl = force_length(x, params["g1"], params["g2"], params["P0"])
    v = np.asarray(FORCE_VELOCITY_MM_S)
    fv = np.where(v < 0, hill_tension(v, params["a0"], params["b0"], params["P0"]),
                  mashima_tension(v, params["c0"], params["d0"], params["P0"]))
    return {FORCE_LENGTH_PATH: np.column_stack([x, fl + rng.normal(0.0, sd_N, x.size)]),
            FORCE_VELOCITY_PATH: np.column_stack([v, fv + rng.normal(0.0, sd_N, v.size)])}


def make_dataset(cause: str | None, strength: float, seed: int, noise_pct: float = 1.5, variation: float = 0.2, *,
                 noise_tau_ms: float = 5.0, base: str = "CT09", dt_ms: float = DT_MS, workers: int = 1,
                 trials: Sequence[str] | None = None, protocols: str = "extended") -> MeasuredData:
    """A synthetic preparation in the measured-data layout (write it with ``write_measured`` or
    :func:`write_dataset`).

    cause: a canonical cause, an out-of-catalogue effect (``cause_names()``), or None/"none" for no effect.
    strength: 0-1, mapped linearly onto the effect's amplitude range (``effects.ALL[cause].low/high``).
    seed: integer >= 0 (parameters, noise and drift come from independent streams of it).  noise_pct: sd of
    the AR(1) transducer noise in % of the preparation's P0 (N), correlation time noise_tau_ms (ms).
    variation: log-sd of the per-parameter factors around ``base``.  dt_ms: the fixed step (ms) of the NEURON
    runs.  workers: processes simulating trials.  protocols: the protocol set (``protocols.PROTOCOL_SETS``:
    "extended", 36 trials (34 until stop 39), the default since stop 36, or "standard", its first 28, with the same noise).
    trials: ids of a subset of the set (all when None).  The truth (cause, strength, parameters, settings) goes
    into the ``/synth`` group.
    """
    name = _check_settings(cause, strength, seed, noise_pct, noise_tau_ms, workers)
    build_plan = protocol_builder(protocols)  # an unknown set refused before the preparation is drawn
    params, n_draws = draw_preparation(load_parameters(base), variation, np.random.default_rng([seed, 0]),
                                       name=f"synth-seed{seed}")
    optimum = round(float(params["g1"]), 1)
    plan = build_plan(optimum)
    if trials is not None:
        unknown = sorted(set(trials) - {p.trial_id for p in plan})
        if unknown:
            raise InputError(f"trial(s) {unknown} are not in the {protocols} protocol set "
                             f"({', '.join(p.trial_id for p in plan)})")
        plan = [p for p in plan if p.trial_id in set(trials)]
    effect = None if name is None else hidden_effect(name)
    amplitude = 0.0 if effect is None else effect.amplitude(float(strength))
    played = name if effect is not None and effect.series is not None else None
    empty = [_empty_trial(p) for p in plan]
    with candidate_map(None, min(int(workers), len(empty))) as map_fn:
        clean = list(map_fn(_simulate, [(params, tr, played, amplitude, dt_ms) for tr in empty]))
    P0 = float(params["P0"])
    sd_N = noise_pct / 100.0 * P0
    noise_rng, drift_rng = np.random.default_rng([seed, 1]), np.random.default_rng([seed, 2])
    drifts: dict[str, Any] = {}
    out = []
    for tr, force in zip(empty, clean):
        if effect is not None and not effect.in_catalogue:
            d, drifts[tr.trial_id] = transducer_drift(tr.time_s, amplitude * P0, drift_rng)
            force = force + d
        sample_ms = 1000.0 * float(tr.time_s[1] - tr.time_s[0])
        out.append(replace(tr, force=force + ar1_noise(tr.n_samples, sd_N, noise_tau_ms, sample_ms, noise_rng)))
    truth = _truth(name, effect, float(strength), amplitude, seed, noise_pct, sd_N, noise_tau_ms, variation, base,
                   dt_ms, params, drifts, protocols)
    truth["parameter_draws"] = n_draws
    return MeasuredData(
        trials={t.trial_id: t for t in out},
        attrs={"species": "cat", "muscle": "soleus-like motor unit (synthetic)",
               "preparation": f"synthetic preparation, seed {seed}, made by neuromuscle synth; {TRUTH_PATH} holds "
                              "the generator's settings and hidden truth, for tests only: a diagnosis must not "
                              "read it",
               "source": "neuromuscle.synth.make_dataset", "licence": "BSD-3-Clause"},
        extra_datasets=_static_points(params, optimum, sd_N, np.random.default_rng([seed, 3])),
        extra_attrs={TRUTH_PATH: truth})


def _truth(name: str | None, effect: Any, strength: float, amplitude: float, seed: int, noise_pct: float,
           sd_N: float, noise_tau_ms: float, variation: float, base: str, dt_ms: float, params: ParameterSet,
           drifts: dict[str, Any], protocols: str) -> dict[str, Any]:
    from .. import __version__
    from ..model.mechanisms import loaded_mechanism_hash

    reg = registry()
    return {
        "schema": SCHEMA, "generator": "neuromuscle.synth.make_dataset", "neuromuscle_version": __version__,
        "mechanism_sha256": loaded_mechanism_hash(),
        "cause": name or "none", "strength": strength, "amplitude": amplitude,
        "amplitude_unit": effect.unit if effect else "", "amplitude_meaning": effect.meaning if effect else "",
        "hidden_form": effect.form if effect else "none", "in_catalogue": bool(effect.in_catalogue) if effect
        else True,
        "seed": int(seed), "noise_kind": "AR(1)", "noise_pct_of_P0": float(noise_pct), "noise_sd_N": sd_N,
        "noise_tau_ms": float(noise_tau_ms), "variation_log_sd": float(variation), "base_parameters": base,
        "true_parameters": json.dumps({reg.alias(k): v for k, v in params.items()}),
        "true_parameter_units": json.dumps({reg.alias(k): reg[k].unit for k in params}),
        "model": "Kim Modules 1-3, eq 18 and eqs 19-20 off",
        "simulation": json.dumps({"method": "fixed", "dt_ms": dt_ms, "settle_ms": SETTLE_MS,
                                  "record_dt_ms": RECORD_DT_MS}),
        "protocol_set": f"neuromuscle.synth.protocols.protocol_set({protocols!r})",
        "drift": json.dumps(drifts),
    }


def truth(data: MeasuredData) -> dict[str, Any]:
    """The generator's settings and hidden truth of a synthetic file (``/synth``), JSON fields decoded; the true
    parameters as a ParameterSet under "parameters".  InputError if the data hold none."""
    raw = data.extra_attrs.get(TRUTH_PATH)
    if raw is None:
        raise InputError(f"{data.path or 'data'}: no {TRUTH_PATH} group: not a file made by neuromuscle synth")
    out = dict(raw)
    for key in ("true_parameters", "true_parameter_units", "simulation", "drift"):
        out[key] = json.loads(out[key])
    out["parameters"] = ParameterSet(f"synth-seed{out['seed']}", out["true_parameters"], "the generator's truth")
    return out


def without_truth(data: MeasuredData) -> MeasuredData:
    """The same data without the generator's ``/synth`` group: what a blind diagnosis may see."""
    return replace(data, extra_attrs={k: v for k, v in data.extra_attrs.items() if k != TRUTH_PATH})


def write_dataset(path: str | Path, cause: str | None, strength: float, seed: int, *, overwrite: bool = False,
                  **settings: Any) -> Path:
    """:func:`make_dataset` written to ``path`` (measured-data layout); an existing file is refused before any
    work unless overwrite.  Returns the path."""
    refuse_existing_file(path, overwrite)
    out = Path(path)
    if not out.parent.is_dir():
        raise InputError(f"{out}: directory '{out.parent}' does not exist")
    return write_measured(out, make_dataset(cause, strength, seed, **settings), overwrite=overwrite)

