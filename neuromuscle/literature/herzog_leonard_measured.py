"""Herzog & Leonard (2002) cat soleus traces converted for the muscle model: stimulus times, the model's length
reference and the passive force removed, each step stated (the file's attributes carry the same text).

    data = herzog_leonard_measured("../shared/real_data/cat_soleus_herzog_leonard_2002")
    write_measured("hl2002.h5", data)            # or: python networks/herzog_leonard_to_measured.py --out hl2002.h5

Preprocessing (units: s, mm, N):

1. **Trials.** The Figure 7 trials (one preparation: 3, 9 and 27 mm/s stretches, isometric references at 0 and
   +9 mm).  Figure 5 is another preparation (isometric plateau 32.7 N against 22 N) and is left out unless asked.
   The unstimulated (passive) stretches are not trials of the output (the model has no passive element and a
   diagnosis compares stimulated responses); they serve step 4 and are kept under ``/preprocessing/passive``.
2. **Stimulus times.** The paper stimulated the tibial nerve supramaximally at 30 Hz (its abstract: activation
   frequencies 5 and 30 Hz; these smooth ~22 N plateaus are the 30 Hz trials) from about 1 s to the end of the
   hold; the files carry no stimulus times.  The train is placed by matching the CT09 model's own 30 Hz response
   to the measured force: the first stimulus lies ``rise lag`` before the trial's 50 % rise crossing (the time
   CT09 takes from its first stimulus to 50 % of its plateau, ~108 ms), the last one ``fall lag`` before the
   50 % fall crossing of the figure's isometric trials (CT09: ~119 ms from the last stimulus to 50 % of its
   plateau; the stretch trials' fall is blurred by the passive force enhancement, the protocol's stimulation
   window is the same for every trial of a figure).  Stimuli at onset + k / 30 s up to the last.
3. **Length.** Paper mm + ``shift_mm`` (default -8 mm): the paper's 0 mm is placed at the CT09 optimum g1 =
   -8 mm (the model's Xm is relative to the physiological maximum).  The paper puts these stretches on the
   descending limb of the force-length relation, so the optimum lies at or below its 0 mm; with two isometric
   lengths g1 cannot be identified and stays at -8 mm, so the shift states "optimum at the paper's 0 mm".
   The transducer noise (sd ~0.03 mm, i.e. ~3 mm/s of apparent velocity at 100 Hz, ~0.3 N through the series
   elasticity) is removed: isometric trials get their median length as a constant, ramps the hold-ramp-hold
   trajectory fitted to the measured length by least squares (start and end times; holds at the median lengths).
4. **Passive force.** The model has no parallel elastic element, so a static passive force-length curve
   F_p(x) = A exp(x / lambda) + C (x paper mm) is fitted to the unstimulated samples: every trial's samples
   before activation (at its start length) and the passive stretches' final 2 s (at +9 mm); F_p(x(t)) of the
   fitted length is subtracted from every trial.  What it leaves: the passive stress relaxation (~1 N over a
   trial) and the passive force enhancement after active stretch (force after deactivation above F_p).
5. **Window.** Each trial is cut ``tail_s`` (default 0.5 s) after its last stimulus: the force after that is
   passive force enhancement (Herzog & Leonard's main finding: several N of passive force that outlasts the
   activation), which a model without a passive element cannot produce by any extension; it is reported, not
   fitted (attr ``passive_force_enhancement_N``: force above F_p in the last 0.5 s of the source trace).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.optimize import curve_fit, least_squares

from ..errors import InputError
from ..measured import MeasuredData, Trial, validate_measured
from ..measured.schema import PathLike
from ..parameters import ParameterSet, load_parameters
from .herzog_leonard_2002 import load_herzog_leonard_2002

STIMULUS_RATE_HZ = 30.0
LENGTH_SHIFT_MM = -8.0
TAIL_S = 0.5
DEFAULT_FIGURES = ("Figure7A", "Figure7B", "Figure7C")
#: Samples before this time ahead of the activation count as unstimulated (s).
_PRE_ACTIVATION_GAP_S = 0.1
_PASSIVE_HOLD_S = 2.0
_ISOMETRIC_PAD_S = 0.3


@dataclass(frozen=True)
class PassiveFit:
    """F_p(x) = A exp(x / lambda) + C, x in paper mm, force in N; RMS residual (N) over n points."""

    A_N: float
    lambda_mm: float
    C_N: float
    rms_N: float
    n_points: int

    def __call__(self, x_mm: np.ndarray) -> np.ndarray:
        return self.A_N * np.exp(np.asarray(x_mm, dtype=float) / self.lambda_mm) + self.C_N

    def text(self) -> str:
        return (f"F_p(x) = {self.A_N:.4g} N exp(x / {self.lambda_mm:.4g} mm) + {self.C_N:.4g} N (x paper mm), "
                f"RMS {self.rms_N:.3g} N over {self.n_points} unstimulated samples")


@dataclass(frozen=True)
class ModelTiming:
    """Delays (ms) of the model's constant-rate response: first stimulus -> 50 % of the plateau, last stimulus ->
    back down to 50 %."""

    rise50_ms: float
    fall50_ms: float
    parameters: str
    rate_hz: float


def _crossing(t: np.ndarray, f: np.ndarray, level: float, rising: bool, start: int = 0) -> float:
    """First time at or after index ``start`` where f crosses ``level`` (linear interpolation)."""
    above = f[start:] >= level if rising else f[start:] <= level
    if not np.any(above):
        return float("nan")
    i = start + int(np.argmax(above))
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (level - f[i - 1]) / (f[i] - f[i - 1]) * (t[i] - t[i - 1]))


def model_timing(params: ParameterSet, rate_hz: float = STIMULUS_RATE_HZ) -> ModelTiming:
    """The 50 % rise and fall delays (ms) of ``params`` under a 3 s train at ``rate_hz``, isometric at g1."""
    from ..protocols import constant_rate
    from ..sim import simulate

    spikes = constant_rate(rate_hz, 3000.0, start_ms=500.0)
    r = simulate(params, spikes, float(params["g1"]), 4500.0, dt_ms=0.025, record_dt_ms=0.1)
    t, f = np.asarray(r.t_ms), np.asarray(r.force_N)
    plateau = float(np.median(f[(t > 2500.0) & (t < spikes[-1])]))
    rise = _crossing(t, f, 0.5 * plateau, True) - spikes[0]
    fall = _crossing(t, f, 0.5 * plateau, False, int(np.searchsorted(t, spikes[-1]))) - spikes[-1]
    return ModelTiming(rise, fall, params.name, rate_hz)


def _hold_ramp_hold(t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """The hold-ramp-hold trajectory fitted to a measured ramp (holds at the median of the first and last 20 %
    of samples); returns (trajectory, ramp start s, ramp end s, RMS residual mm)."""
    n = x.size
    x0, x1 = float(np.median(x[: n // 5])), float(np.median(x[-n // 5:]))
    ta0 = _crossing(t, (x - x0) * np.sign(x1 - x0), 0.1 * abs(x1 - x0), True)
    tb0 = _crossing(t, (x - x0) * np.sign(x1 - x0), 0.9 * abs(x1 - x0), True)
    span = (tb0 - ta0) / 0.8
    ta0, tb0 = ta0 - 0.1 * span, tb0 + 0.1 * span

    def path(p: np.ndarray) -> np.ndarray:
        return np.interp(t, [p[0], max(p[1], p[0] + 1e-6)], [x0, x1])

    fit = least_squares(lambda p: path(p) - x, [ta0, tb0], x_scale=[0.01, 0.01])
    traj = path(fit.x)
    return traj, float(fit.x[0]), float(fit.x[1]), float(np.sqrt(np.mean((traj - x) ** 2)))


def _rise50(trial: Trial) -> float:
    """The 50 % rise crossing (s) of a stimulated trial's force: halfway from its resting level (first 0.8 s) to
    its early plateau (median of 0.5-1.2 s after it first exceeds rest + 5 N, before any ramp starts)."""
    t, f = trial.time_s, trial.force
    base = float(np.median(f[t < t[0] + 0.8]))
    t5 = _crossing(t, f, base + 5.0, True)
    if not np.isfinite(t5):
        raise InputError(f"trial '{trial.trial_id}': force never rises 5 N above rest; no activation to time")
    top = float(np.median(f[(t > t5 + 0.5) & (t < t5 + 1.2)]))
    return _crossing(t, f, base + 0.5 * (top - base), True)


def _isometric_fall50(trial: Trial) -> float:
    """The 50 % fall crossing (s) of an isometric trial: between the plateau before the fall and the final level."""
    t, f = trial.time_s, trial.force
    end = float(np.median(f[-50:]))
    start = float(np.median(f[t < t[0] + 0.8]))
    mid = 0.5 * (float(np.percentile(f, 90)) + max(start, end))
    last_high = int(np.flatnonzero(f > mid)[-1])
    top = float(np.median(f[(t > t[last_high] - 0.6) & (t < t[last_high] - 0.2)]))
    return _crossing(t, f, end + 0.5 * (top - end), False, int(np.searchsorted(t, t[last_high] - 0.5)))


def fit_passive(unstimulated: Sequence[tuple[np.ndarray, np.ndarray]]) -> PassiveFit:
    """Fit F_p(x) = A exp(x / lambda) + C to (length paper mm, force N) sample arrays."""
    x = np.concatenate([np.asarray(a, dtype=float) for a, _ in unstimulated])
    f = np.concatenate([np.asarray(b, dtype=float) for _, b in unstimulated])
    if x.size < 3 or np.ptp(x) < 1.0:
        raise InputError("passive force fit: unstimulated samples span less than 1 mm; cannot fit F_p(x)")
    p, _ = curve_fit(lambda xx, a, lam, c: a * np.exp(xx / lam) + c, x, f, p0=[0.4, 3.0, 0.0],
                     bounds=([0.0, 0.3, -5.0], [50.0, 100.0, 5.0]))
    fit = PassiveFit(float(p[0]), float(p[1]), float(p[2]), 0.0, int(x.size))
    return PassiveFit(fit.A_N, fit.lambda_mm, fit.C_N, float(np.sqrt(np.mean((fit(x) - f) ** 2))), int(x.size))


def herzog_leonard_measured(folder: PathLike, *, figures: Sequence[str] = DEFAULT_FIGURES,
                            shift_mm: float = LENGTH_SHIFT_MM, rate_hz: float = STIMULUS_RATE_HZ,
                            tail_s: float = TAIL_S, timing_params: ParameterSet | None = None) -> MeasuredData:
    """The Herzog & Leonard 2002 trials of ``figures`` in the measured-data layout, preprocessed as the module
    docstring says (force N with the passive force removed, length mm in the model's reference, stimulus times s
    of a ``rate_hz`` train).  The unstimulated trials and each trial's source force and length are kept as extra
    datasets under ``/preprocessing``."""
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise InputError(f"rate_hz must be > 0, got {rate_hz}")
    if not np.isfinite(tail_s) or tail_s <= 0:
        raise InputError(f"tail_s must be > 0, got {tail_s}")
    src = load_herzog_leonard_2002(folder)
    known = sorted({t.attrs["figure"] for t in src.trials.values()})
    unknown = [f for f in figures if f not in known]
    if unknown or not figures:
        raise InputError(f"figures {list(figures)}: unknown {unknown} (have: {', '.join(known)})")
    chosen = [t for t in src.trials.values() if t.attrs["figure"] in figures]
    active = [t for t in chosen if t.protocol != "passive"]
    passive = [t for t in chosen if t.protocol == "passive"]
    timing = model_timing(timing_params or load_parameters("CT09"), rate_hz)

    onset = {t.trial_id: _rise50(t) - timing.rise50_ms / 1000.0 for t in active}
    offset: dict[str, float] = {}
    for fig in figures:
        falls = [_isometric_fall50(t) for t in active if t.attrs["figure"] == fig and t.protocol == "isometric"]
        if not falls:
            raise InputError(f"{fig}: no isometric trial to time the end of the stimulation")
        offset[fig] = float(np.median(falls)) - timing.fall50_ms / 1000.0

    lengths = {t.trial_id: _length_trajectory(t) for t in chosen}
    samples = [(lengths[t.trial_id][0][m], t.force[m]) for t in active
               for m in [t.time_s < onset[t.trial_id] - _PRE_ACTIVATION_GAP_S]]
    samples += [(lengths[t.trial_id][0][m], t.force[m]) for t in passive
                for m in [t.time_s > t.time_s[-1] - _PASSIVE_HOLD_S]]
    fp = fit_passive(samples)

    trials: dict[str, Trial] = {}
    extra: dict[str, np.ndarray] = {}
    extra_attrs: dict[str, dict] = {}
    for t in active:
        tid = t.trial_id
        fig = t.attrs["figure"]
        stim = onset[tid] + np.arange(int(np.floor((offset[fig] - onset[tid]) * rate_hz + 1e-9)) + 1) / rate_hz
        keep = t.time_s <= stim[-1] + tail_s
        x_paper, ramp_text = lengths[tid]
        passive_N = fp(x_paper)
        tail = t.time_s > t.time_s[-1] - 0.5
        attrs = {k: v for k, v in t.attrs.items() if k not in ("stimulation", "stimulus_times_known",
                                                                "length_reference")}
        attrs.update(
            stimulus_times_known=False,
            stimulation=(f"{rate_hz:g} Hz train, {stim.size} stimuli from {stim[0]:.4f} to {stim[-1]:.4f} s: "
                         f"first = 50 % rise crossing - {timing.rise50_ms:.1f} ms, last = {fig}'s isometric 50 % "
                         f"fall crossing - {timing.fall50_ms:.1f} ms ({timing.parameters} at {rate_hz:g} Hz)"),
            length_reference=f"model Xm = paper mm + ({shift_mm:g} mm): paper 0 mm at the optimum g1 = -8 mm",
            length_preprocessing=ramp_text,
            passive_subtracted=fp.text(),
            passive_force_enhancement_N=float(np.mean(t.force[tail] - passive_N[tail])),
            window_s=np.array([float(t.time_s[0]), float(t.time_s[keep][-1])]),
        )
        iso = t.protocol == "isometric"
        trials[tid] = Trial(trial_id=tid, protocol=t.protocol, time_s=t.time_s[keep],
                            force=t.force[keep] - passive_N[keep], force_unit="N", length_unit="mm",
                            length=None if iso else x_paper[keep] + shift_mm,
                            length_const=float(x_paper[0] + shift_mm) if iso else None,
                            stimulus_times_s=stim, attrs=attrs)
        extra[f"/preprocessing/source/{tid}/force_N"] = t.force
        extra[f"/preprocessing/source/{tid}/length_mm"] = t.length
        extra[f"/preprocessing/source/{tid}/time_s"] = t.time_s
        extra[f"/preprocessing/source/{tid}/passive_force_N"] = passive_N
    for t in passive:
        for name, arr in (("time_s", t.time_s), ("force_N", t.force), ("length_mm", t.length)):
            extra[f"/preprocessing/passive/{t.trial_id}/{name}"] = arr
    extra_attrs["/preprocessing"] = {
        "description": __doc__.split("Preprocessing (units: s, mm, N):", 1)[1].strip(),
        "figures": np.array(list(figures)), "stimulus_rate_hz": rate_hz, "length_shift_mm": shift_mm,
        "tail_s": tail_s, "model_rise50_ms": timing.rise50_ms, "model_fall50_ms": timing.fall50_ms,
        "timing_parameters": timing.parameters, "passive_fit": fp.text(), "passive_A_N": fp.A_N,
        "passive_lambda_mm": fp.lambda_mm, "passive_C_N": fp.C_N, "passive_rms_N": fp.rms_N,
        "passive_trials": np.array([t.trial_id for t in passive] or [""]),
    }
    data = MeasuredData(trials=trials, attrs={**src.attrs, "preparation": src.attrs["preparation"] + (
        f"; {', '.join(figures)}; preprocessed by neuromuscle.literature.herzog_leonard_measured (see "
        "/preprocessing attrs)"), "length_reference": f"model Xm = paper mm + ({shift_mm:g} mm)"},
        extra_datasets=extra, extra_attrs=extra_attrs)
    validate_measured(data, source=str(folder))
    return data


def _length_trajectory(t: Trial) -> tuple[np.ndarray, str]:
    """Noise-free length (paper mm) at the trial's samples, and how it was made."""
    x = np.asarray(t.length, dtype=float)
    if t.protocol == "isometric":
        xm = float(np.median(x))
        return np.full(x.shape, xm), (f"constant: median of the measured length {xm:.3f} mm (RMS deviation "
                                      f"{np.sqrt(np.mean((x - xm) ** 2)):.3f} mm)")
    traj, ta, tb, rms = _hold_ramp_hold(t.time_s, x)
    return traj, (f"hold-ramp-hold fitted to the measured length: {traj[0]:.3f} -> {traj[-1]:.3f} mm from "
                  f"{ta:.4f} to {tb:.4f} s ({(traj[-1] - traj[0]) / (tb - ta):.3f} mm/s), RMS residual {rms:.3f} mm")
