"""The protocol sets of a synthetic preparation: what each trial is, on the trial's clock (s).

Lengths are set relative to the preparation's optimum, as an experimenter sets them after a length-tension scan.
Every stimulated trial starts with PRE_S of rest before its first stimulus.  Four sets (``PROTOCOL_SETS``):

* **standard** (28 trials, about 92 s of simulated time): twitches at three lengths (optimum, SHORT_MM below,
  LONG_MM above); 10 and 40 Hz trains (1 s) at the three lengths; 3 Hz (4 s), 20 Hz (1 s) and 100 Hz (0.5 s)
  trains at the optimum; doublets (a 10 Hz train whose first stimulus is followed by one more 5, 10 or 15 ms
  later); long 30 and 40 Hz trains (12 s); potentiation (three twitches 1 s apart, a 100 Hz conditioning train of
  1 or 0.5 s, four twitches 2 s apart); isokinetic ramps between short and optimal during 10 Hz (10 mm/s) and 40 Hz
  (20 mm/s) trains; a stretch-hold (optimal -> long) and a shortening-hold (long -> optimal) at 20 mm/s during a
  40 Hz train; random length (band 2 Hz) during 10 and 20 Hz trains (4 s); a 0.5 mm step shortening during a
  100 Hz train, sampled at 10 kHz (the series-elastic stiffness).  Most protocols have two trials, so that a
  diagnosis's split puts one on each side.
* **extended** (36 trials, about 127 s): the standard set unchanged, then twitch series (6 twitches at 1 Hz, 10 at
  2 Hz: a staircase is measured this way), post-tetanic probes (a 100 Hz or 50 Hz conditioning train, then twitches
  0.15, 0.4, 1 and 2.5 s after it), cyclic length (short <-> optimal at 1 Hz during 10 Hz, or 0.5 Hz during
  20 Hz, 4 s) and a second, longer stretch-hold and shortening-hold (4 s trains).
* **reduced** (26 trials, about 52 s): the design of a typical in situ study, most protocols with a single trial:
  twitches and 4-40 Hz trains at the optimum and REDUCED_MM either side, two 2 s low-rate trains, one doublet train,
  100 Hz isokinetic ramps (lengthening and shortening), random length during 10, 20 and 30 Hz trains and during a
  train of random intervals, one 30 Hz stretch-hold and one shortening-hold, one 4 s 40 Hz train, and twitches
  around a tetanus.  No step, and the file carries no force-length or force-velocity points.
* **ramps** (8 trials): the design of many eccentric-contraction studies, with no separate isometric trial: 30 Hz
  stimulation, a hold, a ramp to one final length (stretch from two shorter lengths, shortening from two longer
  ones, each at two speeds), and a hold to the end of stimulation.

The sampling interval is ``sample_s`` (1 ms by default; the step keeps 0.1 ms).  Trial attributes say what each
trial is: ``kind`` (as ``protocol``), ``rate_hz``, ``length_label`` or ``lengths``, ``doublet_isi_ms``,
``velocity_mm_s``.  ``protocol_set(..., drop=...)`` leaves out whole protocols.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError
from ..protocols import isokinetic_ramp, random_length, step_shortening

SAMPLE_S = 0.001
STEP_SAMPLE_S = 0.0001
PRE_S = 0.1
POST_S = 0.4
SHORT_MM = 6.0
LONG_MM = 5.0
#: The reduced set's short and long lengths lie this far (mm) either side of the optimum.
REDUCED_MM = 8.0
#: Seeds of the random-length trials and of the random-interval train: the same in every preparation.
RANDOM_LENGTH_SEEDS = {10: 11, 20: 12, 30: 13}
RANDOM_INTERVAL_SEED = 14


@dataclass(frozen=True)
class PlannedTrial:
    """One trial of the protocol set: id, protocol, clock (s), stimulus times (s), and either a constant
    length (mm) or a sampled one (mm, at ``time_s``); ``attrs`` are written into the trial group."""

    trial_id: str
    protocol: str
    time_s: np.ndarray
    stimulus_times_s: np.ndarray
    length_mm: float | None = None
    length_trace_mm: np.ndarray | None = None
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1])


def _train(rate_hz: float, duration_s: float, start_s: float = PRE_S) -> np.ndarray:
    n = int(round(duration_s * rate_hz))
    return start_s + np.arange(n) / rate_hz


def _clock(duration_s: float, sample_s: float) -> np.ndarray:
    return np.arange(int(round(duration_s / sample_s)) + 1) * sample_s


@dataclass(frozen=True)
class _Builder:
    """Makes trials on one sampling interval (s)."""

    sample_s: float = SAMPLE_S

    def isometric(self, tid: str, protocol: str, stims: np.ndarray, x_mm: float, label: str,
                  **attrs: Any) -> PlannedTrial:
        end = float(stims[-1]) + POST_S
        return PlannedTrial(tid, protocol, _clock(end, self.sample_s), stims, length_mm=x_mm,
                            attrs={"kind": protocol, "length_label": label, **attrs})

    def moving(self, tid: str, protocol: str, stims: np.ndarray, duration_s: float,
               trace: Callable[[np.ndarray, float], np.ndarray], **attrs: Any) -> PlannedTrial:
        """A trial whose length is ``trace(t_ms, duration_ms)`` (mm) on its clock."""
        t = _clock(duration_s, self.sample_s)
        t_ms = t * 1000.0
        return PlannedTrial(tid, protocol, t, stims, length_trace_mm=trace(t_ms, float(t_ms[-1])),
                            attrs={"kind": protocol, **attrs})

    def ramp(self, tid: str, protocol: str, stims: np.ndarray, duration_s: float, x_from: float, x_to: float,
             speed_mm_s: float, start_s: float, **attrs: Any) -> PlannedTrial:
        """Hold ``x_from`` until ``start_s``, move to ``x_to`` at ``speed_mm_s``, hold (mm, s)."""
        def trace(t_ms: np.ndarray, end_ms: float) -> np.ndarray:
            return isokinetic_ramp(x_from, x_to, speed_mm_s, start_s * 1000.0, end_ms).at(t_ms)

        sign = 1.0 if x_to > x_from else -1.0
        return self.moving(tid, protocol, stims, duration_s, trace, velocity_mm_s=sign * abs(speed_mm_s), **attrs)

    def random(self, tid: str, protocol: str, stims: np.ndarray, duration_s: float, seed: int,
               lengths: dict[str, float], **attrs: Any) -> PlannedTrial:
        def trace(t_ms: np.ndarray, end_ms: float) -> np.ndarray:
            return random_length(end_ms, seed, centre_mm=lengths["opt"], low_mm=lengths["short"],
                                 high_mm=lengths["long"], band_hz=2.0, sample_rate_hz=1000.0).at(t_ms)

        return self.moving(tid, protocol, stims, duration_s, trace, length_seed=seed, **attrs)


def _lengths(opt: float, short_mm: float, long_mm: float) -> dict[str, float]:
    return {"short": opt - short_mm, "opt": opt, "long": opt + long_mm}


_LABELS = {"short": "short", "opt": "optimal", "long": "long"}


def standard_protocols(optimum_mm: float, sample_s: float = SAMPLE_S) -> list[PlannedTrial]:
    """The standard set around the preparation's optimum ``optimum_mm`` (mm), sampled every ``sample_s`` (s)."""
    b = _Builder(sample_s)
    opt = float(optimum_mm)
    lengths = _lengths(opt, SHORT_MM, LONG_MM)
    trials: list[PlannedTrial] = []
    for key, x in lengths.items():
        trials.append(b.isometric(f"twitch_{key}", "twitch", np.array([PRE_S]), x, _LABELS[key], rate_hz=0.0))
    for rate, dur in ((3, 4.0), (10, 1.0), (20, 1.0), (40, 1.0), (100, 0.5)):
        trials.append(b.isometric(f"train{rate}_opt", "train", _train(rate, dur), opt, "optimal", rate_hz=rate))
    for key in ("short", "long"):
        for rate in (10, 40):
            trials.append(b.isometric(f"train{rate}_{key}", "train", _train(rate, 1.0), lengths[key], _LABELS[key],
                                      rate_hz=rate))
    for isi in (5, 10, 15):
        stims = np.sort(np.concatenate([_train(10, 1.0), [PRE_S + isi / 1000.0]]))
        trials.append(b.isometric(f"doublet{isi}_opt", "doublet", stims, opt, "optimal", rate_hz=10,
                                  doublet_isi_ms=float(isi)))
    for rate in (30, 40):
        trials.append(b.isometric(f"long_train{rate}_opt", "long_train", _train(rate, 12.0), opt, "optimal",
                                  rate_hz=rate))
    for tid, train_s in (("potentiation_opt", 1.0), ("potentiation_half_opt", 0.5)):
        pap = np.concatenate([PRE_S + np.arange(3.0), _train(100, train_s, PRE_S + 3.0),
                              PRE_S + 4.0 + train_s + 2.0 * np.arange(4)])
        trials.append(b.isometric(tid, "potentiation", pap, opt, "optimal", rate_hz=100,
                                  twitch_times_s=np.concatenate([pap[:3], pap[-4:]])))
    for rate, speed in ((10, 10.0), (40, 20.0)):
        ramp_s = (lengths["opt"] - lengths["short"]) / speed
        stim_s = 0.5 + ramp_s + 0.5
        for direction, (a, z) in (("lengthen", ("short", "opt")), ("shorten", ("opt", "short"))):
            trials.append(b.ramp(f"ramp_{direction}{rate}", "isokinetic", _train(rate, stim_s), PRE_S + stim_s + POST_S,
                                 lengths[a], lengths[z], speed, PRE_S + 0.4, rate_hz=rate, lengths=f"{a} -> {z}"))
    trials += _holds(b, lengths, (("stretch_hold40", "opt", "long", 2.5, 0.5),
                                  ("shorten_hold40", "long", "opt", 2.5, 0.5)))
    for rate in (10, 20):
        trials.append(b.random(f"random_length{rate}", "random_length", _train(rate, 4.0), PRE_S + 4.0 + POST_S,
                               RANDOM_LENGTH_SEEDS[rate], lengths, rate_hz=rate))
    trials.append(_step(opt))
    return trials


def extended_protocols(optimum_mm: float, sample_s: float = SAMPLE_S) -> list[PlannedTrial]:
    """The standard set around ``optimum_mm`` (mm), unchanged and first, then twitch series, post-tetanic probes,
    cyclic length and the long stretch- and shortening-holds (module docstring)."""
    b = _Builder(sample_s)
    opt = float(optimum_mm)
    lengths = _lengths(opt, SHORT_MM, LONG_MM)
    out = standard_protocols(opt, sample_s)
    for rate, n in ((1.0, 6), (2.0, 10)):
        out.append(b.isometric(f"twitch_series{rate:g}_opt", "twitch_series", _train(rate, n / rate), opt,
                               "optimal", rate_hz=rate))
    for rate, train_s in ((100, 0.3), (50, 0.5)):
        out.append(_post_tetanic(b, f"post_tetanic{rate}_opt", rate, train_s, opt))
    short = lengths["short"]
    for rate, cycle_hz in ((10, 1.0), (20, 0.5)):
        def cyclic(t_ms: np.ndarray, _end_ms: float, f: float = cycle_hz) -> np.ndarray:
            return short + (opt - short) * 0.5 * (1.0 - np.cos(2.0 * np.pi * f * t_ms / 1000.0))
        out.append(b.moving(f"cyclic{rate}", "cyclic_length", _train(rate, 4.0), PRE_S + 4.0 + POST_S, cyclic,
                            rate_hz=rate, cycle_hz=cycle_hz, lengths="short <-> optimal"))
    # held longer: residual force enhancement and depression last as long as the activation; the transient after
    # the ramp fades within ~0.1 s
    out += _holds(b, lengths, (("stretch_hold40_4s", "opt", "long", 4.0, 0.5),
                               ("shorten_hold40_4s", "long", "opt", 4.0, 1.0)))
    return out


def reduced_protocols(optimum_mm: float, sample_s: float = SAMPLE_S) -> list[PlannedTrial]:
    """The reduced set around ``optimum_mm`` (mm): the design of a typical in situ study (module docstring)."""
    b = _Builder(sample_s)
    opt = float(optimum_mm)
    lengths = _lengths(opt, REDUCED_MM, REDUCED_MM)
    out: list[PlannedTrial] = []
    for key, x in lengths.items():
        out.append(b.isometric(f"twitch_{key}", "twitch", np.array([PRE_S]), x, _LABELS[key], rate_hz=0.0))
    out.append(b.isometric("train4_opt", "train", _train(4, 1.0), opt, "optimal", rate_hz=4))
    for key, x in lengths.items():
        for rate in (10, 20, 40):
            out.append(b.isometric(f"train{rate}_{key}", "train", _train(rate, 1.0), x, _LABELS[key], rate_hz=rate))
    for rate in (3, 6):
        out.append(b.isometric(f"low_rate{rate}_opt", "low_rate_train", _train(rate, 2.0), opt, "optimal",
                               rate_hz=rate))
    stims = np.sort(np.concatenate([_train(20, 1.0), [PRE_S + 0.008]]))
    out.append(b.isometric("doublet_opt", "doublet", stims, opt, "optimal", rate_hz=20, doublet_isi_ms=8.0))
    for direction, (a, z) in (("lengthen", ("short", "long")), ("shorten", ("long", "short"))):
        speed = 40.0
        stim_s = 0.3 + (lengths["long"] - lengths["short"]) / speed + 0.3
        out.append(b.ramp(f"ramp100_{direction}", "isokinetic", _train(100, stim_s), PRE_S + stim_s + POST_S,
                          lengths[a], lengths[z], speed, PRE_S + 0.3, rate_hz=100, lengths=f"{a} -> {z}"))
    for rate in (10, 20, 30):
        out.append(b.random(f"random_length{rate}", "random_length", _train(rate, 3.0), PRE_S + 3.0 + POST_S,
                            RANDOM_LENGTH_SEEDS[rate], lengths, rate_hz=rate))
    out.append(b.random("random_length_random_rate", "random_length", _random_intervals(25.0, 3.0),
                        PRE_S + 3.0 + POST_S, RANDOM_LENGTH_SEEDS[20] + 10, lengths, rate_hz=25))
    out += _holds(b, lengths, (("stretch_hold30", "opt", "long", 3.0, 0.5),
                               ("shorten_hold30", "long", "opt", 3.0, 0.5)), rate_hz=30)
    out.append(b.isometric("long_train40_opt", "long_train", _train(40, 4.0), opt, "optimal", rate_hz=40))
    out.append(_post_tetanic(b, "post_tetanic_opt", 100, 0.5, opt, before=3))
    return out


def ramps_protocols(optimum_mm: float, sample_s: float = SAMPLE_S) -> list[PlannedTrial]:
    """The ramps-only set around ``optimum_mm`` (mm): 30 Hz trains with one ramp each to the final length
    optimum + 4 mm, from 2 and 6 mm below it (stretch) or above it (shortening), at 4 and 12 mm/s."""
    b = _Builder(sample_s)
    final = float(optimum_mm) + 4.0
    out: list[PlannedTrial] = []
    for direction, sign in (("stretch", -1.0), ("shorten", 1.0)):
        for dist in (2.0, 6.0):
            for speed in (4.0, 12.0):
                start = final + sign * dist
                stim_s = 1.0 + dist / speed + 1.5
                out.append(b.ramp(f"{direction}{dist:g}mm_{speed:g}mm_s", f"{direction}_ramp", _train(30, stim_s),
                                  PRE_S + stim_s + POST_S, start, final, speed, PRE_S + 1.0, rate_hz=30,
                                  lengths=f"{start:g} -> {final:g} mm"))
    return out


#: The protocol sets ``synth`` can write, by name.
PROTOCOL_SETS: dict[str, Callable[..., list[PlannedTrial]]] = {
    "standard": standard_protocols, "extended": extended_protocols, "reduced": reduced_protocols,
    "ramps": ramps_protocols}


def protocol_builder(name: str) -> Callable[..., list[PlannedTrial]]:
    """The function that builds protocol set ``name`` (``PROTOCOL_SETS``) around an optimum (mm); InputError
    naming the known sets otherwise (so a caller can refuse a bad name before any work)."""
    if name not in PROTOCOL_SETS:
        raise InputError(f"unknown protocol set {name!r}; known: {', '.join(PROTOCOL_SETS)}")
    return PROTOCOL_SETS[name]


def protocol_set(name: str, optimum_mm: float, sample_rate_hz: float = 1.0 / SAMPLE_S,
                 drop: Sequence[str] = ()) -> list[PlannedTrial]:
    """Protocol set ``name`` around ``optimum_mm`` (mm), sampled at ``sample_rate_hz`` (Hz, 100-20000), without
    the protocols named in ``drop``; InputError for an unknown set or protocol, a bad rate, or nothing left."""
    build = protocol_builder(name)
    if isinstance(sample_rate_hz, bool) or not isinstance(sample_rate_hz, (int, float)) or \
            not 100.0 <= float(sample_rate_hz) <= 20000.0:
        raise InputError(f"sample_rate_hz must be a number in [100, 20000] Hz, got {sample_rate_hz!r}")
    plan = build(optimum_mm, 1.0 / float(sample_rate_hz))
    known = sorted({p.protocol for p in plan})
    unknown = sorted(set(drop) - set(known))
    if unknown:
        raise InputError(f"cannot drop protocol(s) {unknown}: the {name} set has {', '.join(known)}")
    kept = [p for p in plan if p.protocol not in set(drop)]
    if not kept:
        raise InputError(f"dropping {', '.join(drop)} leaves no trial of the {name} set")
    return kept


def _holds(b: _Builder, lengths: dict[str, float], specs: Sequence[tuple[str, str, str, float, float]],
           rate_hz: float = 40.0) -> list[PlannedTrial]:
    """For each (id, from, to, train s, ramp after s): a ``rate_hz`` train during which the length moves between
    the named lengths at 20 mm/s, starting the given time after the first stimulus, and is then held."""
    out = []
    for tid, a, z, train_s, after_s in specs:
        protocol = "stretch_hold" if lengths[z] > lengths[a] else "shorten_hold"
        out.append(b.ramp(tid, protocol, _train(rate_hz, train_s), PRE_S + train_s + POST_S, lengths[a], lengths[z],
                          20.0, PRE_S + after_s, rate_hz=rate_hz, lengths=f"{a} -> {z}"))
    return out


def _post_tetanic(b: _Builder, tid: str, rate_hz: float, train_s: float, opt: float,
                  before: int = 0) -> PlannedTrial:
    """``before`` twitches 1 s apart, a conditioning train, then twitch probes 0.15, 0.4, 1 and 2.5 s after it."""
    lead = PRE_S + np.arange(float(before))
    conditioning = _train(rate_hz, train_s, PRE_S + before)
    probes = float(conditioning[-1]) + np.array([0.15, 0.4, 1.0, 2.5])
    return b.isometric(tid, "post_tetanic", np.concatenate([lead, conditioning, probes]), opt, "optimal",
                       rate_hz=rate_hz, twitch_times_s=np.concatenate([lead, probes]))


def _random_intervals(mean_rate_hz: float, duration_s: float) -> np.ndarray:
    """Stimuli at intervals uniform between 10 ms and twice the mean interval, for ``duration_s`` (s)."""
    rng = np.random.default_rng(RANDOM_INTERVAL_SEED)
    mean = 1.0 / mean_rate_hz
    isi = rng.uniform(0.010, 2.0 * mean - 0.010, size=int(3 * duration_s * mean_rate_hz))
    t = PRE_S + np.concatenate([[0.0], np.cumsum(isi)])
    return t[t < PRE_S + duration_s]


def _step(opt: float) -> PlannedTrial:
    t = np.arange(int(round(0.2 / STEP_SAMPLE_S)) + 1) * STEP_SAMPLE_S
    trace = step_shortening(opt, 0.5, 150.0, t[-1] * 1000.0, ramp_ms=0.5, sample_ms=STEP_SAMPLE_S * 1000.0)
    return PlannedTrial("step100", "step", t, np.arange(0.0, 0.2, 0.01), length_trace_mm=trace.at(t * 1000.0),
                        attrs={"kind": "step", "rate_hz": 100, "step_mm": 0.5})


def total_duration_s(trials: list[PlannedTrial]) -> float:
    """Simulated time of the protocol set (s), settling excluded."""
    return float(sum(t.duration_s for t in trials))
