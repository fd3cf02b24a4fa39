"""The hidden effects of synthetic data: one per canonical cause (docs/reference/diagnosis.md), and one from
outside the catalogue.  docs/guide/synth.md states each form and how it differs from the catalogue extension meant to
find it.

Each effect maps a trial (its spikes, length and velocity on the simulation clock) to time series for the
baseline's modulation ports (``release_gain``, ``uptake_gain`` (1), ``force_offset`` (N)), played into NEURON by
:mod:`.play`, or for ``force_scale`` (1), a scale of the output force (KimForce's output does not feed back into
the contractile element, so this equals playing force_offset = (scale - 1) F into it).  The forms are deliberately
NOT the catalogue's equations (eq 18, eqs 19-20, the extensions in
``neuromuscle/model/extensions``): a diagnosis that names the cause has discovered it, not re-fitted its own
generator.  The strength (0-1) maps linearly onto the amplitude ``a`` between ``low`` and ``high``, a range in which
the effect is physiologically plausible and, at 1-2 % noise, visible in the trials that should show it.

The out-of-catalogue effect, ``transducer_drift``, is a measurement artefact: it is added to the recorded force
after the simulation (:func:`transducer_drift`), not played into the muscle.

Units: time ms, length mm, velocity mm/s (positive = lengthening), force N.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy.signal import fftconvolve

from ..errors import InputError

#: Interval (ms) of the uniform grid on which the series are computed; a step at a spike is a ramp of STEP_MS
#: ending at the spike.
GRID_MS = 1.0
STEP_MS = 0.2


@dataclass(frozen=True)
class TrialInput:
    """One trial as the hidden effects see it, on the simulation clock: spike times (ms), length (mm) and
    velocity (mm/s) sampled on ``t_ms`` (uniform, GRID_MS apart, from 0 to the end), and the preparation's true
    optimum g1 (mm), width g2 (mm) and P0 (N)."""

    t_ms: np.ndarray
    length_mm: np.ndarray
    velocity_mm_s: np.ndarray
    spikes_ms: np.ndarray
    g1_mm: float
    g2_mm: float
    P0_N: float

    @property
    def duration_ms(self) -> float:
        return float(self.t_ms[-1])

    def play_grid(self) -> np.ndarray:
        """The uniform grid plus, for every spike, the spike and STEP_MS before it (where steps are placed)."""
        s = self.spikes_ms
        knots = np.concatenate([s, np.maximum(s - STEP_MS, 0.0)])
        return np.union1d(self.t_ms, knots[knots <= self.duration_ms])


Form = Callable[[TrialInput, float], dict[str, tuple[np.ndarray, np.ndarray]]]


@dataclass(frozen=True)
class HiddenEffect:
    """A hidden effect: its name (a canonical cause, or an out-of-catalogue name), the ports it drives, the
    amplitude range ``low``..``high`` (``unit``) that strength 0..1 maps onto, what the amplitude means, the
    form in one line, and the trials that should show it (``shows_in``: protocol names)."""

    name: str
    ports: tuple[str, ...]
    low: float
    high: float
    unit: str
    meaning: str
    form: str
    shows_in: tuple[str, ...]
    series: Form | None = None
    in_catalogue: bool = True

    def amplitude(self, strength: float) -> float:
        """The amplitude (``unit``) of strength 0..1 (linear between low and high)."""
        return self.low + float(strength) * (self.high - self.low)


# ----------------------------------------------------------------------------------------------- helpers

def _steps(inp: TrialInput, after_each_spike: np.ndarray, before: float) -> tuple[np.ndarray, np.ndarray]:
    """A piecewise-constant series: ``before`` until the first spike, then after_each_spike[k] from spike k on
    (each step a ramp of STEP_MS ending at the spike)."""
    s = inp.spikes_ms
    if s.size == 0:
        return np.array([0.0, inp.duration_ms]), np.array([before, before])
    t = np.concatenate([[0.0], np.ravel(np.column_stack([np.maximum(s - STEP_MS, 0.0), s])), [inp.duration_ms]])
    prev = np.concatenate([[before], after_each_spike[:-1]])
    v = np.concatenate([[before], np.ravel(np.column_stack([prev, after_each_spike])), [after_each_spike[-1]]])
    keep = t <= inp.duration_ms
    return t[keep], v[keep]


def _intervals(spikes: np.ndarray) -> np.ndarray:
    """The interval (ms) before each spike; inf before the first."""
    return np.concatenate([[np.inf], np.diff(spikes)]) if spikes.size else np.zeros(0)


def _leaky_before(spikes: np.ndarray, weights: np.ndarray, tau_ms: float) -> np.ndarray:
    """For each spike k: sum over earlier spikes j of weights[j] exp(-(t_k - t_j)/tau) (spike k excluded)."""
    out = np.zeros(spikes.size)
    acc = 0.0
    for k in range(1, spikes.size):
        acc = (acc + weights[k - 1]) * np.exp(-(spikes[k] - spikes[k - 1]) / tau_ms)
        out[k] = acc
    return out


def _leaky_at(t: np.ndarray, spikes: np.ndarray, weights: np.ndarray, tau_ms: float) -> np.ndarray:
    """sum over spikes t_k <= t of weights[k] exp(-(t - t_k)/tau), at every t."""
    if spikes.size == 0:
        return np.zeros_like(t)
    after = _leaky_before(spikes, weights, tau_ms) + weights  # value just after each spike
    k = np.searchsorted(spikes, t, side="right") - 1
    out = np.zeros_like(t)
    on = k >= 0
    out[on] = after[k[on]] * np.exp(-(t[on] - spikes[k[on]]) / tau_ms)
    return out


def activity_envelope(inp: TrialInput) -> np.ndarray:
    """How active the muscle is (0-1) on ``inp.t_ms``: r^2/(r^2 + 15^2) for the stimulation rate r (Hz, from
    the interval before the latest spike; the first spike takes the next interval, a lone spike counts as
    5 Hz) from the first spike until one interval after the last, then decaying with 80 ms; 0 before."""
    s, t = inp.spikes_ms, inp.t_ms
    env = np.zeros_like(t)
    if s.size == 0:
        return env
    isi = np.diff(s)
    isi_k = np.concatenate([[isi[0] if isi.size else 200.0], isi])  # interval owned by each spike
    rate = 1000.0 / isi_k
    level = rate ** 2 / (rate ** 2 + 15.0 ** 2)
    k = np.searchsorted(s, t, side="right") - 1
    on = k >= 0
    env[on] = level[k[on]]
    end = s[-1] + isi_k[-1]
    late = t > end
    env[late] = level[-1] * np.exp(-(t[late] - end) / 80.0)
    return env


def _kernel_convolve(u: np.ndarray, kernel: Callable[[np.ndarray], np.ndarray], dt_ms: float) -> np.ndarray:
    """Causal convolution of u (per ms) with kernel(lag ms) on a uniform grid: sum_j u_j K(t_i - t_j) dt."""
    lags = np.arange(u.size) * dt_ms
    return fftconvolve(u, kernel(lags))[: u.size] * dt_ms


# ------------------------------------------------------------------------------------ the ten causes

def _length_dependent_activation(inp: TrialInput, a: float):
    d = inp.length_mm - inp.g1_mm
    gain = 1.0 - a * d ** 2 / (d ** 2 + 5.0 ** 2)
    return {"release_gain": (inp.t_ms, gain)}


def _movement_induced_depression(inp: TrialInput, a: float):
    # m' = (|v|/L)(1 - m) - m/tau_r, exact for |v| constant over each grid interval; L = 20 mm, tau_r = 2 s
    drive = np.abs(inp.velocity_mm_s) / 20.0 / 1000.0  # 1/ms
    m = np.zeros_like(inp.t_ms)
    for i in range(1, m.size):
        k = drive[i - 1] + 1.0 / 2000.0
        m_inf = drive[i - 1] / k
        m[i] = m_inf + (m[i - 1] - m_inf) * np.exp(-k * (inp.t_ms[i] - inp.t_ms[i - 1]))
    return {"release_gain": (inp.t_ms, 1.0 - a * m)}


def _lengthening_below_optimum(inp: TrialInput, a: float):
    below = 1.0 / (1.0 + np.exp((inp.length_mm - inp.g1_mm) / 1.0))
    vpos = np.maximum(inp.velocity_mm_s, 0.0)
    gain = 1.0 - a * below * vpos / (vpos + 10.0)
    return {"release_gain": (inp.t_ms, gain)}


def _staircase(inp: TrialInput, a: float):
    isi = _intervals(inp.spikes_ms)
    low_rate = np.where(np.isinf(isi), 1.0, 1.0 - 1.0 / (1.0 + (np.minimum(isi, 1e6) / 100.0) ** 4))
    n = _leaky_before(inp.spikes_ms, low_rate, 1000.0)
    return {"release_gain": _steps(inp, 1.0 + a * n ** 3 / (n ** 3 + 2.5 ** 3), 1.0)}


def _short_interval(isi_ms: np.ndarray) -> np.ndarray:
    """1/(1 + exp((ISI - 12 ms)/2 ms)): near 1 below ~8 ms, 0.5 at 12 ms, near 0 above ~18 ms (0 before the first
    spike)."""
    z = np.minimum((isi_ms - 12.0) / 2.0, 50.0)
    return 1.0 / (1.0 + np.exp(z))


def _doublet_potentiation(inp: TrialInput, a: float):
    s = inp.spikes_ms
    short = _short_interval(_intervals(s))
    previous = np.concatenate([[0.0], short[:-1]])
    f = a * short * (1.0 - previous)  # only the first short interval of a burst
    t = inp.play_grid()
    gain = np.ones_like(t)
    for tk, fk in zip(s[f > 1e-6 * a], f[f > 1e-6 * a]):
        lag = np.maximum(t - tk, 0.0)
        gain += fk * (1.0 - np.exp(-lag / 5.0)) * np.exp(-lag / 200.0)
    return {"release_gain": (t, gain)}


def _post_activation_potentiation(inp: TrialInput, a: float):
    s = inp.spikes_ms
    w = 1.0 / (1.0 + (_intervals(s) / 15.0) ** 6)
    t = inp.play_grid()
    P = 1.0 - np.exp(-_leaky_at(t, s, w, 40_000.0) / 25.0)
    return {"release_gain": (t, 1.0 + a * P), "uptake_gain": (t, 1.0 / (1.0 + 0.8 * a * P))}


def _relaxation_rate(inp: TrialInput, a: float):
    t = inp.play_grid()
    n = _leaky_at(t, inp.spikes_ms, np.ones(inp.spikes_ms.size), 300.0)
    load = n / (n + 10.0)
    return {"uptake_gain": (t, 1.0 / (1.0 + a * load))}


def _force_enhancement_after_stretch(inp: TrialInput, a: float):
    env = activity_envelope(inp)
    stretch = np.maximum(inp.velocity_mm_s, 0.0) / 1000.0 * env  # mm/ms while active
    E = _kernel_convolve(stretch, lambda lag: 0.5 * np.exp(-lag / 500.0) + 0.5 * np.exp(-lag / 10_000.0), GRID_MS)
    return {"force_offset": (inp.t_ms, a * inp.P0_N * E / 10.0 * env)}


def _force_depression_after_shortening(inp: TrialInput, a: float):
    env = activity_envelope(inp)
    g = np.exp(-(((inp.length_mm - inp.g1_mm) / inp.g2_mm) ** 2))
    work = np.maximum(-inp.velocity_mm_s, 0.0) / 1000.0 * g * env  # mm/ms while active, weighted by g(Xm)
    W = _kernel_convolve(work, lambda lag: 1.0 / (1.0 + lag / 1500.0), GRID_MS)
    return {"force_offset": (inp.t_ms, -a * inp.P0_N * W / 10.0 * env)}


def _fatigue(inp: TrialInput, a: float):
    s = inp.spikes_ms
    isi = _intervals(s)
    w = 1.0 / (1.0 + (np.where(np.isinf(isi), 100.0, isi) / 30.0) ** 2)
    c = a * (np.cumsum(w) / 200.0) ** 1.5
    return {"release_gain": _steps(inp, 1.0 / (1.0 + c), 1.0),
            "force_scale": _steps(inp, 1.0 - 0.35 * c / (1.0 + c), 1.0)}


# ------------------------------------------------------------------------------------------ the table

CAUSES: Mapping[str, HiddenEffect] = {e.name: e for e in (
    HiddenEffect("length_dependent_activation", ("release_gain",), 0.3, 0.7, "1",
                 "largest fractional loss of Ca2+ release far from the optimum",
                 "release x [1 - a d^2/(d^2 + (5 mm)^2)], d = Xm - g1 (Hill-type loss of release with the distance "
                 "from the optimum, either side)",
                 ("twitch", "train", "random_length"), _length_dependent_activation),
    HiddenEffect("movement_induced_depression", ("release_gain",), 0.3, 0.7, "1",
                 "largest fractional loss of release after much movement",
                 "release x (1 - a m), m' = (|v|/20 mm)(1 - m) - m/2 s: a depression driven by the distance moved, "
                 "recovering at rest",
                 ("random_length", "isokinetic", "stretch_hold", "shorten_hold"), _movement_induced_depression),
    HiddenEffect("lengthening_below_optimum", ("release_gain",), 0.3, 0.7, "1",
                 "largest fractional loss of release while lengthening well below the optimum",
                 "release x [1 - a s((g1 - Xm)/1 mm) v+/(v+ + 10 mm/s)], s logistic: an instantaneous loss while "
                 "lengthening below the optimum",
                 ("isokinetic", "random_length"), _lengthening_below_optimum),
    HiddenEffect("staircase", ("release_gain",), 0.3, 0.8, "1",
                 "largest fractional gain of release after many recent low-rate stimuli",
                 "release from spike k on x [1 + a n^3/(n^3 + 2.5^3)], n = sum over earlier spikes j of "
                 "w_j exp(-(t_k - t_j)/1 s), w = 1 - 1/(1 + (ISI/100 ms)^4): a positive staircase built by "
                 "low-rate stimuli only (a high-rate burst does not count), saturating after ~4 stimuli",
                 ("train",), _staircase),
    HiddenEffect("doublet_potentiation", ("release_gain",), 1.0, 3.0, "1",
                 "peak extra release after the first short interval of a burst",
                 "release x [1 + sum_k f_k (1 - e^(-s/5 ms)) e^(-s/200 ms)], s = t - t_k, f_k = a q_k (1 - q_(k-1)), "
                 "q = 1/(1 + exp((ISI - 12 ms)/2 ms)): a boost after the first short interval of a burst only",
                 ("doublet",), _doublet_potentiation),
    HiddenEffect("post_activation_potentiation", ("release_gain", "uptake_gain"), 0.15, 0.5, "1",
                 "largest fractional gain of release after high-rate activity (the pump slows by 0.8 a)",
                 "release x (1 + a P), pump / (1 + 0.8 a P), P = 1 - exp(-E/25), E = sum_k w_k exp(-(t - t_k)/40 s), "
                 "w_k = 1/(1 + (ISI_k/15 ms)^6): potentiation by high-rate firing only, lasting tens of seconds",
                 ("potentiation",), _post_activation_potentiation),
    HiddenEffect("relaxation_rate", ("uptake_gain",), 0.8, 2.5, "1",
                 "largest fractional slowing of Ca2+ removal after sustained high-rate activity",
                 "pump / (1 + a n/(n + 10)), n = sum over spikes t_k <= t of exp(-(t - t_k)/300 ms): Ca2+ removal "
                 "slows with the recent spike count (parvalbumin saturating, the SR loading), so a tetanus relaxes "
                 "more slowly than a twitch (at a = 1.5: a twitch's pump / 1.14, 10 Hz / 1.39, 100 Hz / 2.13), "
                 "recovering within ~1 s",
                 ("train", "long_train", "potentiation", "doublet"), _relaxation_rate),
    HiddenEffect("force_enhancement_after_stretch", ("force_offset",), 0.2, 0.6, "P0 per 10 mm",
                 "extra force (fraction of P0) per 10 mm of active stretch, at full activity",
                 "F + a P0 env(t) E/10 mm, E = active stretch (mm) convolved with 0.5 e^(-t/0.5 s) + "
                 "0.5 e^(-t/10 s), env = r^2/(r^2 + (15 Hz)^2) while stimulated at rate r",
                 ("stretch_hold", "isokinetic"), _force_enhancement_after_stretch),
    HiddenEffect("force_depression_after_shortening", ("force_offset",), 0.2, 0.6, "P0 per 10 mm",
                 "lost force (fraction of P0) per 10 mm of active shortening at the optimum, at full activity",
                 "F - a P0 env(t) W/10 mm, W = active shortening weighted by g(Xm), convolved with the hyperbolic "
                 "1/(1 + t/1.5 s)",
                 ("shorten_hold", "isokinetic"), _force_depression_after_shortening),
    HiddenEffect("fatigue", ("release_gain", "force_scale"), 0.6, 2.0, "1",
                 "the decline's coefficient c at 200 rate-weighted stimuli",
                 "release from spike k on / (1 + c_k), force x [1 - 0.35 c_k/(1 + c_k)], c_k = a (N_k/200)^1.5, "
                 "N_k = sum_{j<=k} 1/(1 + (ISI_j/30 ms)^2): a hyperbolic decline of release and of the force "
                 "capacity with the rate-weighted stimulus count, no recovery within a trial",
                 ("long_train",), _fatigue),
)}

#: The out-of-catalogue effect (verdict "unexplained").
OUTSIDE: Mapping[str, HiddenEffect] = {e.name: e for e in (
    HiddenEffect("transducer_drift", (), 0.04, 0.10, "peak force",
                 "amplitude of the drift as a fraction of the file's peak force",
                 "measured F + a F_peak sin(2 pi t/T_i + phi_i), T_i ~ U(2, 6) s, phi_i ~ U(0, 2 pi) per trial: a "
                 "wandering transducer baseline, present at rest",
                 ("all",), None, in_catalogue=False),
)}

ALL: Mapping[str, HiddenEffect] = {**CAUSES, **OUTSIDE}


def hidden_effect(name: str) -> HiddenEffect:
    """The hidden effect called ``name``; InputError listing the known names otherwise."""
    if name not in ALL:
        raise InputError(f"unknown cause {name!r}; known: {', '.join(ALL)} (or 'none')")
    return ALL[name]


def modulation(name: str, inp: TrialInput, amplitude: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The port series of cause ``name`` at ``amplitude`` for one trial ({} for an effect played outside)."""
    effect = hidden_effect(name)
    return {} if effect.series is None else effect.series(inp, amplitude)


def transducer_drift(time_s: np.ndarray, amplitude_N: float, rng: np.random.Generator) -> tuple[np.ndarray, dict]:
    """The drift (N) of one trial at time_s (s) and its drawn period (s) and phase (rad)."""
    period_s = float(rng.uniform(2.0, 6.0))
    phase = float(rng.uniform(0.0, 2.0 * np.pi))
    drift = amplitude_N * np.sin(2.0 * np.pi * np.asarray(time_s) / period_s + phase)
    return drift, {"period_s": period_s, "phase_rad": phase, "amplitude_N": amplitude_N}


#: How two hidden effects' series on one port combine: gains and scales multiply, offsets (N) add.
_COMBINE = {"release_gain": np.multiply, "uptake_gain": np.multiply, "tauA_gain": np.multiply,
            "force_scale": np.multiply, "force_offset": np.add}


def combined_modulation(effects: Sequence[tuple[str, float]], inp: TrialInput) -> dict[str, tuple[np.ndarray,
                                                                                                  np.ndarray]]:
    """The port series of several hidden effects at once, each (name, amplitude): series on the same port are
    combined on the union of their time grids (gains and scales multiply, offsets add; each series is linear
    between its samples, as it is played)."""
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for name, amplitude in effects:
        for port, (t, v) in modulation(name, inp, amplitude).items():
            if port not in out:
                out[port] = (np.asarray(t, dtype=float), np.asarray(v, dtype=float))
                continue
            t0, v0 = out[port]
            grid = np.union1d(t0, t)
            out[port] = (grid, _COMBINE[port](np.interp(grid, t0, v0), np.interp(grid, t, v)))
    return out
