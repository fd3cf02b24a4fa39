"""The package's example preparation: a small measured-data file made from stated parameters.

``example_path()`` is the shipped file (``neuromuscle/data/example/cat_unit.h5``); :func:`write_example` makes
it.  A synthetic cat soleus unit: the CT09 set with C1, C2, C3 and alpha moved to ``TRUE_VALUES``; a twitch and
10/20/40 Hz trains at the optimum g1 and a twitch and a 20 Hz train 8 mm shorter (``PROTOCOLS``), 0.6 s at
1 kHz, each simulated at dt 0.025 ms after 500 ms of settling, plus Gaussian noise (sd 0.02 N, seed 1).  A fit of
C1, C2, C3, alpha from CT09 should find ``TRUE_VALUES``.  All of this is written into the file (root attributes
and the ``/provenance`` group).  tests/measured/test_example.py checks that the shipped file equals a new one;
after a change of the model's numbers, write it again::

    from neuromuscle.measured import example_path, write_example
    write_example(example_path(), overwrite=True)
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import Mapping

import numpy as np

from .hdf5 import write_measured
from .schema import MeasuredData, PathLike

BASE = "CT09"
TRUE_VALUES: Mapping[str, float] = {"C1": 0.135, "C2": 0.11, "C3": 55.0, "alpha": 1.8}
SEED = 1
NOISE_N = 0.02
DURATION_S = 0.6
SAMPLE_S = 0.001
FIRST_STIMULUS_S = 0.05
TRAIN_S = 0.3
DT_MS = 0.025
SETTLE_MS = 500.0
#: trial id, length relative to the optimum g1 (mm), stimulus rate (Hz; None: one stimulus, a twitch)
PROTOCOLS: tuple[tuple[str, float, float | None], ...] = (
    ("twitch_opt", 0.0, None), ("train10_opt", 0.0, 10.0), ("train20_opt", 0.0, 20.0), ("train40_opt", 0.0, 40.0),
    ("twitch_short", -8.0, None), ("train20_short", -8.0, 20.0))


def example_path() -> Path:
    """The example measured-data file shipped with the package (read it with ``read_measured``)."""
    return Path(str(resources.files("neuromuscle.data.example").joinpath("cat_unit.h5")))


def stimulus_times_s(rate_hz: float | None) -> np.ndarray:
    """Stimulus times (s) of a protocol: one at FIRST_STIMULUS_S, or TRAIN_S of them at rate_hz (Hz)."""
    n = 1 if rate_hz is None else int(round(TRAIN_S * rate_hz))
    return FIRST_STIMULUS_S + np.arange(n) / (1.0 if rate_hz is None else rate_hz)


def example_data(true_values: Mapping[str, float] = TRUE_VALUES, seed: int = SEED,
                 noise_N: float = NOISE_N) -> MeasuredData:
    """The example preparation in memory: ``PROTOCOLS`` simulated from BASE with ``true_values`` (parameter
    units) plus Gaussian noise of sd noise_N (N) from ``seed``, with its provenance attributes."""
    from .simulation import synthetic_trial  # loads NEURON: imported when data are made, not at import
    from ..parameters import SPECS, load_parameters

    params = load_parameters(BASE).with_values(true_values)
    rng = np.random.default_rng(seed)
    time_s = np.arange(round(DURATION_S / SAMPLE_S)) * SAMPLE_S
    trials = [synthetic_trial(params, tid, time_s, stimulus_times_s(rate), protocol="twitch" if rate is None
                              else "train", length_mm=params["g1"] + offset_mm, noise_N=noise_N, rng=rng,
                              dt_ms=DT_MS, settle_ms=SETTLE_MS)
              for tid, offset_mm, rate in PROTOCOLS]
    provenance = {
        "generator": "neuromuscle.measured.example.write_example",
        "base_parameters": BASE,
        "true_values": json.dumps(dict(true_values)),
        "true_values_units": json.dumps({n: SPECS[n].unit for n in true_values}),
        "seed": seed, "noise_sd_N": noise_N, "sample_interval_s": SAMPLE_S, "simulation_dt_ms": DT_MS,
        "settle_ms": SETTLE_MS,
        "protocols": "; ".join(_protocol_text(tid, params["g1"] + off, rate) for tid, off, rate in PROTOCOLS),
    }
    return MeasuredData(
        trials={t.trial_id: t for t in trials},
        attrs={"species": "cat", "muscle": "soleus (synthetic unit)",
               "preparation": f"simulated by neuromuscle from {BASE} with {_values_text(true_values)} plus "
                              f"noise; see /provenance",
               "source": "neuromuscle.measured.example.write_example", "licence": "BSD-3-Clause"},
        extra_attrs={"/provenance": provenance})


def write_example(path: PathLike, true_values: Mapping[str, float] = TRUE_VALUES, seed: int = SEED,
                  noise_N: float = NOISE_N, overwrite: bool = False) -> Path:
    """Write :func:`example_data` to ``path`` (refused if it exists, unless overwrite); returns the path."""
    return write_measured(path, example_data(true_values, seed, noise_N), overwrite=overwrite)


def _protocol_text(trial_id: str, length_mm: float, rate_hz: float | None) -> str:
    stims = stimulus_times_s(rate_hz)
    what = "1 stimulus" if rate_hz is None else f"{stims.size} stimuli at {rate_hz:g} Hz"
    return f"{trial_id}: {what} from {FIRST_STIMULUS_S:g} s, isometric at {length_mm:g} mm"


def _values_text(values: Mapping[str, float]) -> str:
    return ", ".join(f"{k} = {v:g}" for k, v in values.items())
