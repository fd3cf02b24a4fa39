"""A synthetic preparation as a measured-data file: varied parameters, a world's protocols and base model, up to
two hidden effects, AR(1) transducer noise, and the generator's truth kept apart in ``/synth``.

Randomness comes from independent streams of ``seed``: parameters, noise, drift, the static calibration points and
the uneven sampling of digitised worlds.  So the files of one seed and world share the preparation and the noise
whatever the hidden effects: a cause's file minus the null file of the same seed is the effect itself.
"""

from __future__ import annotations

import json
import numbers
from dataclasses import replace
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ..analysis.module3 import force_length, hill_tension, mashima_tension
from ..calibration.staged import FORCE_LENGTH_PATH, FORCE_VELOCITY_PATH
from ..errors import InputError
from ..fit.evaluate import candidate_map
from ..measured.simulation import ar1_noise, trial_simulation
from ..measured import MeasuredData, Trial
from ..measured.hdf5 import write_measured
from ..parameters import ParameterSet, load_parameters, registry
from ..reports.outdir import refuse_existing_file
from .effects import ALL, GRID_MS, TrialInput, combined_modulation, hidden_effect, transducer_drift
from .play import played_models
from .protocols import PlannedTrial, protocol_builder, protocol_set
from .variation import draw_preparation
from .worlds import World, world as find_world

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


def _number(label: str, v: Any, lo: float, hi: float) -> float:
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not (lo <= float(v) <= hi):
        raise InputError(f"{label} must be a number in [{lo:g}, {hi:g}], got {v!r}")
    return float(v)


def hidden_effects(cause: str | None, strength: float,
                   also: Mapping[str, float] | None = None) -> list[tuple[str, float]]:
    """The hidden effects as (name, strength 0-1), checked (InputError names the bad one): the first from
    cause/strength, then ``also``."""
    if cause is not None and not isinstance(cause, str):
        raise InputError(f"cause must be a cause name or None, got {cause!r}")
    out = [] if cause in (None, "none") else [(cause, _number("strength", strength, 0.0, 1.0))]
    if also is not None and not isinstance(also, Mapping):
        raise InputError(f"also must map cause names to strengths, got {also!r}")
    for name, st in (also or {}).items():
        out.append((name, _number(f"strength of {name!r}", st, 0.0, 1.0)))
    names = [n for n, _ in out]
    for n in names:
        hidden_effect(n)
    if len(set(names)) != len(names):
        raise InputError(f"each hidden effect at most once, got {names}")
    if len(out) > 1 and any(not hidden_effect(n).in_catalogue for n in names):
        raise InputError("an out-of-catalogue effect is made alone, not beside another hidden effect")
    return out


def _check_settings(seed: int, noise_pct: float, noise_tau_ms: float, workers: int) -> None:
    _number("noise_pct", noise_pct, 0.0, 20.0)
    _number("noise_tau_ms", noise_tau_ms, 0.0, 1000.0)
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {seed!r}")
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise InputError(f"workers must be an integer >= 1, got {workers!r}")


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


def _run(params: ParameterSet, trial: Trial, series: dict, dt_ms: float, length_compensation: bool,
         movement_compensation: bool) -> np.ndarray:
    """Force (N) of ``trial`` at its samples, the port ``series`` played into the model."""
    excitation, contraction = played_models(series, length_compensation, movement_compensation)
    sample_ms = 1000.0 * float(np.min(np.diff(trial.time_s)))
    return trial_simulation(params, trial, dt_ms, record_dt_ms=min(RECORD_DT_MS, sample_ms), settle_ms=SETTLE_MS,
                            excitation=excitation, contraction=contraction)


def _simulate(job: tuple) -> np.ndarray:
    """Clean force (N) of one trial under its hidden effects (module level, for worker processes).  A
    ``force_scale`` series multiplies the output force: KimForce's output does not feed back into the CE, so this
    equals playing force_offset = (scale - 1) F into it, without a second run."""
    params, trial, played, dt_ms, length_compensation, movement_compensation = job
    series = combined_modulation(played, trial_input(trial, params)) if played else {}
    scale = series.pop("force_scale", None)
    force = _run(params, trial, series, dt_ms, length_compensation, movement_compensation)
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


def _with_world_model(params: ParameterSet, w: World) -> ParameterSet:
    """The drawn preparation as the world's model uses it: with eq 18 on, its intercepts set so that phi(g1) = 1
    (the drawn slopes kept: activation is unchanged at the optimum and falls or rises away from it)."""
    if not w.length_dependence:
        return params
    g1 = float(params["g1"])
    return params.with_values(phi2=1.0 - float(params["phi1"]) * g1, phi4=1.0 - float(params["phi3"]) * g1)


def _uneven(trial: Trial, n: int, rng: np.random.Generator) -> np.ndarray:
    """Indices of ``n`` samples of ``trial``'s clock, first and last included, the others one uniform draw in each
    of n - 2 equal spans (as points picked off a digitised figure)."""
    m = trial.time_s.size
    if n >= m:
        return np.arange(m)
    edges = np.linspace(1, m - 1, n - 1)
    inner = [int(rng.integers(int(lo), max(int(lo) + 1, int(hi)))) for lo, hi in zip(edges[:-1], edges[1:])]
    return np.unique(np.concatenate([[0], inner, [m - 1]]))


def _resampled(trial: Trial, force: np.ndarray, idx: np.ndarray) -> tuple[Trial, np.ndarray]:
    attrs = {**trial.attrs, "sample_rate_hz": 0.0, "samples": int(idx.size)}
    return (replace(trial, time_s=trial.time_s[idx], force=trial.force[idx],
                    length=None if trial.length is None else trial.length[idx], attrs=attrs), force[idx])


def make_dataset(cause: str | None, strength: float, seed: int, noise_pct: float = 1.5, variation: float = 0.2, *,
                 noise_tau_ms: float = 5.0, world: str | World = "B", also: Mapping[str, float] | None = None,
                 base: str | None = None, protocols: str | None = None, dt_ms: float = DT_MS, workers: int = 1,
                 trials: Sequence[str] | None = None) -> MeasuredData:
    """A synthetic preparation in the measured-data layout (write it with ``write_measured`` or
    :func:`write_dataset`).

    cause: a canonical cause, an out-of-catalogue effect (``cause_names()``), or None/"none" for no effect.
    strength: 0-1, mapped linearly onto the effect's amplitude range (``effects.ALL[cause].low/high``).
    also: a second hidden effect (or more) as {cause: strength}, played with the first (gains multiply, force
    offsets add).  seed: integer >= 0 (parameters, noise, drift and sampling come from independent streams of
    it).  noise_pct: sd of the AR(1) transducer noise in % of the preparation's P0 (N), correlation time
    noise_tau_ms (ms).  variation: log-sd of the per-parameter factors around the world's base set.
    world: a :class:`~.worlds.World` or its name (``worlds.WORLDS``): base model (eq 18, eqs 19-20), protocol set,
    dropped protocols, sampling, static points; ``base`` and ``protocols`` override its base set and protocol set.
    dt_ms: the fixed step (ms) of the NEURON runs.  workers: processes simulating trials.  trials: ids of a subset
    of the protocol set (all when None).  The truth (causes, strengths, parameters, world) goes into ``/synth``.
    """
    effects = hidden_effects(cause, strength, also)
    _check_settings(seed, noise_pct, noise_tau_ms, workers)
    w = find_world(world)
    w = w.with_settings(base=base or w.base, protocols=protocols or w.protocols)
    protocol_builder(w.protocols)  # an unknown set refused before the preparation is drawn
    params, n_draws = draw_preparation(load_parameters(w.base), variation, np.random.default_rng([seed, 0]),
                                       name=f"synth-seed{seed}")
    params = _with_world_model(params, w)
    optimum = round(float(params["g1"]), 1)
    plan = protocol_set(w.protocols, optimum, w.sample_rate_hz, w.drop)
    if trials is not None:
        unknown = sorted(set(trials) - {p.trial_id for p in plan})
        if unknown:
            raise InputError(f"trial(s) {unknown} are not in the {w.protocols} protocol set "
                             f"({', '.join(p.trial_id for p in plan)})")
        plan = [p for p in plan if p.trial_id in set(trials)]
    hidden = [(n, hidden_effect(n), hidden_effect(n).amplitude(st), st) for n, st in effects]
    played = [(n, a) for n, e, a, _ in hidden if e.series is not None]
    empty = [_empty_trial(p) for p in plan]
    with candidate_map(None, min(int(workers), len(empty))) as map_fn:
        clean = list(map_fn(_simulate, [(params, tr, played, dt_ms, w.length_dependence, w.movement_terms)
                                        for tr in empty]))
    P0 = float(params["P0"])
    sd_N = noise_pct / 100.0 * P0
    noise_rng, drift_rng = np.random.default_rng([seed, 1]), np.random.default_rng([seed, 2])
    sample_rng = np.random.default_rng([seed, 4])
    drifts: dict[str, Any] = {}
    out = []
    for tr, force in zip(empty, clean):
        for _, e, a, _ in hidden:
            if not e.in_catalogue:
                d, drifts[tr.trial_id] = transducer_drift(tr.time_s, a * P0, drift_rng)
                force = force + d
        if w.samples_per_trial is not None:
            tr, force = _resampled(tr, force, _uneven(tr, w.samples_per_trial, sample_rng))
        sample_ms = 1000.0 * float(np.median(np.diff(tr.time_s)))
        out.append(replace(tr, force=force + ar1_noise(tr.n_samples, sd_N, noise_tau_ms, sample_ms, noise_rng)))
    truth = _truth(hidden, seed, noise_pct, sd_N, noise_tau_ms, variation, w, dt_ms, params, drifts)
    truth["parameter_draws"] = n_draws
    extra = _static_points(params, optimum, sd_N, np.random.default_rng([seed, 3])) if w.static_points else {}
    return MeasuredData(
        trials={t.trial_id: t for t in out},
        attrs={"species": "cat", "muscle": "soleus-like motor unit (synthetic)",
               "preparation": f"synthetic preparation, seed {seed}, world {w.name}, made by neuromuscle synth; "
                              f"{TRUTH_PATH} holds the generator's settings and hidden truth, for tests only: a "
                              "diagnosis must not read it",
               "source": "neuromuscle.synth.make_dataset", "licence": "BSD-3-Clause"},
        extra_datasets=extra, extra_attrs={TRUTH_PATH: truth})


def _truth(hidden: list[tuple[str, Any, float, float]], seed: int, noise_pct: float, sd_N: float, noise_tau_ms: float,
           variation: float, w: World, dt_ms: float, params: ParameterSet, drifts: dict[str, Any]) -> dict[str, Any]:
    from .. import __version__
    from ..model.mechanisms import loaded_mechanism_hash

    reg = registry()
    first = hidden[0] if hidden else None
    model = "Kim Modules 1-3" + (", eq 18 on" if w.length_dependence else ", eq 18 off") + \
        (", eqs 19-20 on" if w.movement_terms else ", eqs 19-20 off")
    return {
        "schema": SCHEMA, "generator": "neuromuscle.synth.make_dataset", "neuromuscle_version": __version__,
        "mechanism_sha256": loaded_mechanism_hash(),
        "cause": first[0] if first else "none",
        "strength": float(first[3]) if first else 0.0,
        "amplitude": first[2] if first else 0.0,
        "amplitude_unit": first[1].unit if first else "", "amplitude_meaning": first[1].meaning if first else "",
        "hidden_form": first[1].form if first else "none",
        "in_catalogue": bool(first[1].in_catalogue) if first else True,
        "causes": json.dumps([{"name": n, "strength": st, "amplitude": a, "unit": e.unit,
                               "in_catalogue": e.in_catalogue} for n, e, a, st in hidden]),
        "background_causes": json.dumps(list(w.background_causes)),
        "world": json.dumps(w.to_json()),
        "seed": int(seed), "noise_kind": "AR(1)", "noise_pct_of_P0": float(noise_pct), "noise_sd_N": sd_N,
        "noise_tau_ms": float(noise_tau_ms), "variation_log_sd": float(variation), "base_parameters": w.base,
        "true_parameters": json.dumps({reg.alias(k): v for k, v in params.items()}),
        "true_parameter_units": json.dumps({reg.alias(k): reg[k].unit for k in params}),
        "model": model,
        "simulation": json.dumps({"method": "fixed", "dt_ms": dt_ms, "settle_ms": SETTLE_MS,
                                  "record_dt_ms": RECORD_DT_MS}),
        "protocol_set": f"neuromuscle.synth.protocols.protocol_set({w.protocols!r})",
        "drift": json.dumps(drifts),
    }


def truth(data: MeasuredData) -> dict[str, Any]:
    """The generator's settings and hidden truth of a synthetic file (``/synth``), JSON fields decoded; the true
    parameters as a ParameterSet under "parameters".  InputError if the data hold none."""
    raw = data.extra_attrs.get(TRUTH_PATH)
    if raw is None:
        raise InputError(f"{data.path or 'data'}: no {TRUTH_PATH} group: not a file made by neuromuscle synth")
    out = dict(raw)
    for key in ("true_parameters", "true_parameter_units", "simulation", "drift", "causes", "background_causes",
                "world"):
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

