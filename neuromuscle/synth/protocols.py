"""The protocol sets of one synthetic preparation (standard, 28 trials; extended, 36, the default of ``synth`` since
stop 36): what each trial is, on the trial's clock (s).

Lengths are set relative to the preparation's optimum (as an experimenter sets them after a length-tension scan):
"optimal" at the optimum, "short" SHORT_MM below it, "long" LONG_MM above it.  Every stimulated trial starts with
PRE_S of rest before its first stimulus.  The standard set: 28 trials, about 92 s of simulated time in all
(``total_duration_s``):

* twitches at the three lengths; 10 and 40 Hz trains (1 s) at the three lengths; 3 Hz (4 s), 20 Hz (1 s) and
  100 Hz (0.5 s) trains at the optimum;
* doublets: a 10 Hz train (1 s) at the optimum whose first stimulus is followed by one more 5, 10 or 15 ms later;
* long 30 Hz and 40 Hz trains (12 s) at the optimum (fatigue; two, so that a split can calibrate on one and
  judge on the other);
* potentiation: three twitches 1 s apart, a 100 Hz conditioning train (1 s, or 0.5 s in a second trial, so that a
  split can calibrate on one dose and judge on the other), four twitches 2 s apart;
* isokinetic ramps between short and optimal, lengthening and shortening, during a 10 Hz (10 mm/s) or a 40 Hz
  (20 mm/s) train;
* stretch-hold (optimal -> long) and shortening-hold (long -> optimal) at 20 mm/s during a 40 Hz train (2.5 s);
* random length (band 2 Hz, between short and long, fixed seeds) during 10 and 20 Hz trains (4 s);
* a 0.5 mm step shortening in 0.5 ms during a 100 Hz train (the series-elastic stiffness), sampled at 10 kHz.

The **extended** set (``extended_protocols``, ``synth --protocols extended``: 36 trials, about 127 s) adds three
protocols of two trials each, so that each has one trial on either side of a diagnosis's split and the standard
trials keep their split; they target the causes whose weak cases the standard set leaves within a preparation's
calibration misfit (docs/diagnosis.md, stop 36); and (stop 39) a second hold of each kind:

* twitch series at the optimum: 6 twitches at 1 Hz and 10 at 2 Hz (a staircase, or treppe, is measured this way);
* post-tetanic probes at the optimum: a 100 Hz (0.3 s) or 50 Hz (0.5 s) conditioning train, then twitches 0.15,
  0.4, 1 and 2.5 s after its last stimulus (relaxation that recovers within a second after activity, against a
  potentiation that lasts tens of seconds; the 50 Hz train loads activity with few intervals under 15 ms);
* cyclic length: a sinusoid between short and optimal, 1 Hz during a 10 Hz train or 0.5 Hz during a 20 Hz
  train (4 s; movement at low rates and lengthening below the optimum, every cycle);
* long holds (``_long_holds``): the stretch-hold and shortening-hold ramps during 4 s 40 Hz trains, held about 3 s,
  ordered after the standard holds by the split, so that one hold of each kind is judged (force enhancement and
  depression are defined by the force in the hold).

The sampling interval is SAMPLE_S (1 kHz) except for the step.  Trial attributes say what each trial is:
``kind`` (as ``protocol``), ``rate_hz``, ``length_label`` or ``lengths``, ``doublet_isi_ms``, ``velocity_mm_s``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ..errors import InputError
from ..protocols import isokinetic_ramp, random_length, step_shortening

SAMPLE_S = 0.001
STEP_SAMPLE_S = 0.0001
PRE_S = 0.1
POST_S = 0.4
SHORT_MM = 6.0
LONG_MM = 5.0
#: Seeds of the random-length trials: part of the standard protocol, the same in every preparation.
RANDOM_LENGTH_SEEDS = {10: 11, 20: 12}


@dataclass(frozen=True)
class PlannedTrial:
    """One trial of the protocol set: id, protocol, duration (s), stimulus times (s), and either a constant
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


def _clock(duration_s: float, sample_s: float = SAMPLE_S) -> np.ndarray:
    return np.arange(int(round(duration_s / sample_s)) + 1) * sample_s


def _isometric(tid: str, protocol: str, stims: np.ndarray, x_mm: float, label: str, **attrs: Any) -> PlannedTrial:
    end = float(stims[-1]) + POST_S
    return PlannedTrial(tid, protocol, _clock(end), stims, length_mm=x_mm,
                        attrs={"kind": protocol, "length_label": label, **attrs})


def _moving(tid: str, protocol: str, stims: np.ndarray, t_s: np.ndarray, x_mm: np.ndarray,
            **attrs: Any) -> PlannedTrial:
    return PlannedTrial(tid, protocol, t_s, stims, length_trace_mm=x_mm, attrs={"kind": protocol, **attrs})


def standard_protocols(optimum_mm: float) -> list[PlannedTrial]:
    """The standard protocol set around the preparation's optimum ``optimum_mm`` (mm)."""
    opt = float(optimum_mm)
    lengths = {"short": opt - SHORT_MM, "opt": opt, "long": opt + LONG_MM}
    labels = {"short": "short", "opt": "optimal", "long": "long"}
    trials: list[PlannedTrial] = []
    for key, x in lengths.items():
        trials.append(_isometric(f"twitch_{key}", "twitch", np.array([PRE_S]), x, labels[key], rate_hz=0.0))
    for rate, dur in ((3, 4.0), (10, 1.0), (20, 1.0), (40, 1.0), (100, 0.5)):
        trials.append(_isometric(f"train{rate}_opt", "train", _train(rate, dur), opt, "optimal", rate_hz=rate))
    for key in ("short", "long"):
        for rate in (10, 40):
            trials.append(_isometric(f"train{rate}_{key}", "train", _train(rate, 1.0), lengths[key], labels[key],
                                     rate_hz=rate))
    for isi in (5, 10, 15):
        stims = np.sort(np.concatenate([_train(10, 1.0), [PRE_S + isi / 1000.0]]))
        trials.append(_isometric(f"doublet{isi}_opt", "doublet", stims, opt, "optimal", rate_hz=10,
                                 doublet_isi_ms=float(isi)))
    for rate in (30, 40):  # two, so that the diagnosis's split can hold one out
        trials.append(_isometric(f"long_train{rate}_opt", "long_train", _train(rate, 12.0), opt, "optimal",
                                 rate_hz=rate))
    for tid, train_s in (("potentiation_opt", 1.0), ("potentiation_half_opt", 0.5)):  # two doses, so that a
        # split can calibrate on one and judge on the other (with one, post-activation potentiation was untestable)
        pap = np.concatenate([PRE_S + np.arange(3.0), _train(100, train_s, PRE_S + 3.0),
                              PRE_S + 4.0 + train_s + 2.0 * np.arange(4)])
        trials.append(_isometric(tid, "potentiation", pap, opt, "optimal", rate_hz=100,
                                 twitch_times_s=np.concatenate([pap[:3], pap[-4:]])))
    trials += _ramps(lengths) + _holds(lengths) + _random(lengths) + [_step(opt)]
    return trials


def extended_protocols(optimum_mm: float) -> list[PlannedTrial]:
    """The standard set around ``optimum_mm`` (mm), unchanged and first, then twitch series, post-tetanic probes,
    cyclic length and (since stop 39) the long stretch- and shortening-holds (module docstring)."""
    opt = float(optimum_mm)
    lengths = {"short": opt - SHORT_MM, "opt": opt, "long": opt + LONG_MM}
    return (standard_protocols(opt) + _twitch_series(opt) + _post_tetanic(opt) + _cyclic(opt - SHORT_MM, opt)
            + _long_holds(lengths))


#: The protocol sets ``synth`` can write, by name.
PROTOCOL_SETS = {"standard": standard_protocols, "extended": extended_protocols}


def protocol_builder(name: str) -> Callable[[float], list[PlannedTrial]]:
    """The function that builds protocol set ``name`` (``PROTOCOL_SETS``) around an optimum (mm); InputError
    naming the known sets otherwise (so a caller can refuse a bad name before any work)."""
    if name not in PROTOCOL_SETS:
        raise InputError(f"unknown protocol set {name!r}; known: {', '.join(PROTOCOL_SETS)}")
    return PROTOCOL_SETS[name]


def protocol_set(name: str, optimum_mm: float) -> list[PlannedTrial]:
    """The protocol set called ``name`` (``PROTOCOL_SETS``) around ``optimum_mm`` (mm); InputError otherwise."""
    return protocol_builder(name)(optimum_mm)


def _twitch_series(opt: float) -> list[PlannedTrial]:
    out = []
    for rate, n in ((1.0, 6), (2.0, 10)):
        out.append(_isometric(f"twitch_series{rate:g}_opt", "twitch_series", _train(rate, n / rate), opt, "optimal",
                              rate_hz=rate))
    return out


def _post_tetanic(opt: float) -> list[PlannedTrial]:
    out = []
    for rate, train_s in ((100, 0.3), (50, 0.5)):
        conditioning = _train(rate, train_s)
        probes = float(conditioning[-1]) + np.array([0.15, 0.4, 1.0, 2.5])
        out.append(_isometric(f"post_tetanic{rate}_opt", "post_tetanic", np.concatenate([conditioning, probes]), opt,
                              "optimal", rate_hz=rate, twitch_times_s=probes))
    return out


def _cyclic(short: float, opt: float) -> list[PlannedTrial]:
    out = []
    t = _clock(PRE_S + 4.0 + POST_S)
    for rate, cycle_hz in ((10, 1.0), (20, 0.5)):
        x = short + (opt - short) * 0.5 * (1.0 - np.cos(2.0 * np.pi * cycle_hz * t))
        out.append(_moving(f"cyclic{rate}", "cyclic_length", _train(rate, 4.0), t, x, rate_hz=rate,
                           cycle_hz=cycle_hz, lengths="short <-> optimal"))
    return out


def _ramps(lengths: dict[str, float]) -> list[PlannedTrial]:
    out = []
    for rate, speed in ((10, 10.0), (40, 20.0)):
        ramp_s = (lengths["opt"] - lengths["short"]) / speed
        stim_s = 0.5 + ramp_s + 0.5
        t = _clock(PRE_S + stim_s + POST_S)
        for direction, (a, b) in (("lengthen", ("short", "opt")), ("shorten", ("opt", "short"))):
            trace = isokinetic_ramp(lengths[a], lengths[b], speed, (PRE_S + 0.4) * 1000.0, t[-1] * 1000.0)
            out.append(_moving(f"ramp_{direction}{rate}", "isokinetic", _train(rate, stim_s), t,
                               trace.at(t * 1000.0), rate_hz=rate, velocity_mm_s=speed if direction == "lengthen"
                               else -speed, lengths=f"{a} -> {b}"))
    return out


def _hold(tid: str, protocol: str, lengths: dict[str, float], a: str, b: str, train_s: float,
          ramp_after_s: float) -> PlannedTrial:
    """A 40 Hz train of ``train_s`` (s) during which the length moves from ``a`` to ``b`` at 20 mm/s, starting
    ``ramp_after_s`` (s) after the first stimulus, and is then held."""
    speed = 20.0
    t = _clock(PRE_S + train_s + POST_S)
    trace = isokinetic_ramp(lengths[a], lengths[b], speed, (PRE_S + ramp_after_s) * 1000.0, t[-1] * 1000.0)
    return _moving(tid, protocol, _train(40, train_s), t, trace.at(t * 1000.0), rate_hz=40,
                   velocity_mm_s=speed if b == "long" else -speed, lengths=f"{a} -> {b}")


def _holds(lengths: dict[str, float]) -> list[PlannedTrial]:
    return [_hold("stretch_hold40", "stretch_hold", lengths, "opt", "long", 2.5, 0.5),
            _hold("shorten_hold40", "shorten_hold", lengths, "long", "opt", 2.5, 0.5)]


def _long_holds(lengths: dict[str, float]) -> list[PlannedTrial]:
    """The extended set's second stretch-hold and shortening-hold: the same ramps, held longer (4 s trains), so
    that one of each is held out by the diagnosis's split (ordered after the standard ones by their mean length:
    the stretch comes 0.5 s into the train, the shortening after 1 s at the long length).  Residual force
    enhancement and depression last as long as the activation (seconds); a force-velocity transient after the
    ramp fades within ~0.1 s."""
    return [_hold("stretch_hold40_4s", "stretch_hold", lengths, "opt", "long", 4.0, 0.5),
            _hold("shorten_hold40_4s", "shorten_hold", lengths, "long", "opt", 4.0, 1.0)]


def _random(lengths: dict[str, float]) -> list[PlannedTrial]:
    out = []
    t = _clock(PRE_S + 4.0 + POST_S)
    for rate, seed in RANDOM_LENGTH_SEEDS.items():
        trace = random_length(t[-1] * 1000.0, seed, centre_mm=lengths["opt"], low_mm=lengths["short"],
                              high_mm=lengths["long"], band_hz=2.0, sample_rate_hz=1000.0)
        out.append(_moving(f"random_length{rate}", "random_length", _train(rate, 4.0), t, trace.at(t * 1000.0),
                           rate_hz=rate, length_seed=seed))
    return out


def _step(opt: float) -> PlannedTrial:
    t = _clock(0.2, STEP_SAMPLE_S)
    trace = step_shortening(opt, 0.5, 150.0, t[-1] * 1000.0, ramp_ms=0.5, sample_ms=STEP_SAMPLE_S * 1000.0)
    return _moving("step100", "step", np.arange(0.0, 0.2, 0.01), t, trace.at(t * 1000.0), rate_hz=100,
                   step_mm=0.5)


def total_duration_s(trials: list[PlannedTrial]) -> float:
    """Simulated time of the protocol set (s), settling excluded."""
    return float(sum(t.duration_s for t in trials))
