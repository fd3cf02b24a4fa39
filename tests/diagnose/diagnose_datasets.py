"""Small measured-data sets for the diagnosis tests and (until ``neuromuscle.synth`` lands) the diagnosis bench.

Each preparation is CT09 with C1, C2, C3, alpha, P0 and g2 moved by up to +/-12 % (drawn from the seed), trials
simulated by ``neuromuscle.fit.synthetic_trial`` with eq 18 and eqs 19-20 off, plus AR(1) noise of sd
``noise_pct`` % of each trial's range (lag-1 correlation 0.6 at 1 kHz).  The hidden fatigue-like effect is NOT the
catalogue's ``fatigue`` equations (a depletion state raised by each spike and recovering with tau_rec): the n-th
stimulus of a trial releases with NetCon weight 1 - strength (1 - exp(-(n - 1) / 40)) -- a saturating function of
the stimulus count, with no recovery and no state.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from neuromuscle.fit import synthetic_trial
from neuromuscle.measured import MeasuredData, Trial
from neuromuscle.parameters import load_parameters

SAMPLE_S = 0.001
DT_MS = 0.05
SETTLE_MS = 300.0
RHO = 0.6
VARIED = ("C1", "C2", "C3", "alpha", "P0", "g2")


def preparation(seed: int):
    """CT09 with VARIED moved by a factor in [0.88, 1.12] each."""
    rng = np.random.default_rng(1000 + seed)
    base = load_parameters("CT09")
    return base.with_values({n: base[n] * rng.uniform(0.88, 1.12) for n in VARIED})


def protocols(g1: float, standard: bool) -> list[tuple[str, str, float, np.ndarray, float]]:
    """(trial id, protocol, length (mm), stimulus times (s), duration (s))."""
    def train(rate, n, start=0.05):
        return start + np.arange(n) / rate

    out = [("twitch_opt", "twitch", g1, np.array([0.05]), 0.45),
           ("twitch_short", "twitch", g1 - 6.0, np.array([0.05]), 0.45),
           ("twitch_long", "twitch", g1 + 4.0, np.array([0.05]), 0.45),
           ("train10_opt", "train", g1, train(10, 4), 0.7),
           ("train20_opt", "train", g1, train(20, 8), 0.7),
           ("train40_opt", "train", g1, train(40, 14), 0.7),
           ("train20_short", "train", g1 - 6.0, train(20, 8), 0.7),
           ("long50_opt", "long_train", g1, train(50, 60), 1.5),
           ("long60_opt", "long_train", g1, train(60, 72), 1.5),
           ("long50_short", "long_train", g1 - 6.0, train(50, 60), 1.5)]
    if standard:
        out += [("twitch_opt2", "twitch", g1, np.array([0.05]), 0.45),
                ("twitch_short2", "twitch", g1 - 3.0, np.array([0.05]), 0.45),
                ("train10_short", "train", g1 - 6.0, train(10, 4), 0.7),
                ("train15_opt", "train", g1, train(15, 6), 0.7),
                ("train30_opt", "train", g1, train(30, 11), 0.7),
                ("train40_short", "train", g1 - 3.0, train(40, 14), 0.7),
                ("train20_long", "train", g1 + 4.0, train(20, 8), 0.7),
                ("train80_opt", "train", g1, train(80, 24), 0.7),
                ("train100_opt", "train", g1, train(100, 30), 0.7),
                ("long40_opt", "long_train", g1, train(40, 48), 1.5),
                ("long70_opt", "long_train", g1, train(70, 84), 1.5),
                ("long40_long", "long_train", g1 + 4.0, train(40, 48), 1.5),
                ("long60_short", "long_train", g1 - 3.0, train(60, 72), 1.5),
                ("train25_opt", "train", g1, train(25, 9), 0.7),
                ("long30_opt", "long_train", g1, train(30, 36), 1.5)]
    return out


def weighted_force(params, trial: Trial, strength: float) -> np.ndarray:
    """The trial's force (N) when the n-th stimulus releases with weight 1 - strength (1 - exp(-(n - 1) / 40))."""
    from neuromuscle import MuscleUnit, kim_excitation
    from neuromuscle.sim import Simulator
    from neuron import h

    spikes_ms = SETTLE_MS + 1000.0 * np.asarray(trial.stimulus_times_s)
    weights = 1.0 - strength * (1.0 - np.exp(-np.arange(spikes_ms.size) / 40.0))
    unit = MuscleUnit(params, excitation=kim_excitation(False, False))
    try:
        unit.length.xm = float(trial.length_const)
        receiver = unit.spike_receivers()[0]
        ncs = [h.NetCon(None, receiver) for _ in spikes_ms]
        for nc, w in zip(ncs, weights):
            nc.weight[0] = float(w)
        fih = h.FInitializeHandler(1, lambda: [nc.event(float(t)) for nc, t in zip(ncs, spikes_ms)])
        rec_t, rec_f = h.Vector().record(h._ref_t), h.Vector().record(unit.ref("force.F"))
        Simulator(method="fixed", dt_ms=DT_MS).run(SETTLE_MS + 1000.0 * trial.duration_s + 1.0, units=[unit])
        del fih
        return np.interp(SETTLE_MS + 1000.0 * (trial.time_s - trial.time_s[0]), np.array(rec_t), np.array(rec_f))
    finally:
        unit.destroy()


def ar1_noise(rng: np.random.Generator, n: int, sd: float) -> np.ndarray:
    """Stationary AR(1) noise of sd ``sd`` and lag-1 correlation RHO."""
    e = rng.normal(0.0, sd * np.sqrt(1 - RHO ** 2), n)
    e[0] = rng.normal(0.0, sd)
    return lfilter([1.0], [1.0, -RHO], e) if n else e


def make_data(seed: int = 0, *, fatigue: float = 0.0, noise_pct: float = 1.5, standard: bool = False) -> MeasuredData:
    """A preparation's trials (10, or 25 with ``standard``) with an optional hidden fatigue-like effect."""
    params = preparation(seed)
    rng = np.random.default_rng(seed)
    trials: dict[str, Trial] = {}
    for tid, proto, x, stims, dur in protocols(params["g1"], standard):
        t = np.arange(round(dur / SAMPLE_S)) * SAMPLE_S
        tr = synthetic_trial(params, tid, t, stims, protocol=proto, length_mm=x, dt_ms=DT_MS, record_dt_ms=0.5,
                             settle_ms=SETTLE_MS, length_compensation=False)
        clean = weighted_force(params, tr, fatigue) if fatigue else tr.force
        tr.force = clean + ar1_noise(rng, t.size, noise_pct / 100.0 * float(np.ptp(clean)))
        trials[tid] = tr
    return MeasuredData(trials=trials, attrs={"species": "cat", "muscle": "soleus (synthetic, tests)",
                                              "preparation": f"seed {seed}, hidden fatigue {fatigue}",
                                              "source": "tests/diagnose/diagnose_datasets.py",
                                              "licence": "BSD-3-Clause"})
