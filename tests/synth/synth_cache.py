"""Datasets shared by the synth tests, made once per session (dt 0.05 ms and a subset of trials keep them fast)."""

from functools import cache

from neuromuscle.synth import make_dataset

SEED = 4
NOISE_PCT = 1.0


@cache
def dataset(cause, strength, trials, seed=SEED, noise_pct=NOISE_PCT):
    """make_dataset at dt 0.05 ms on the given trial ids (a tuple)."""
    return make_dataset(cause, strength, seed, noise_pct=noise_pct, trials=list(trials), dt_ms=0.05)
