"""Sample measured data for the tests of neuromuscle.measured (imported by the test modules of this folder)."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Callable

import h5py
import numpy as np

from neuromuscle.measured import SCHEMA, MeasuredData, Trial


def make_data() -> MeasuredData:
    """Two trials (ids deliberately not in alphabetical order), one motor unit, extras."""
    t = np.linspace(0.0, 0.5, 501)
    twitch = Trial(trial_id="tw2", protocol="twitch", time_s=t, force=np.exp(-t / 0.05) * t,
                   force_unit="N", length_unit="mm", length_const=-3.0,
                   stimulus_times_s=np.array([0.01]), attrs={"temperature_C": 37.0, "note": "first"})
    t2 = np.cumsum(np.full(200, 1e-3)) + 0.1 * np.sin(np.arange(200)) * 1e-4  # non-uniform sampling
    ramp = Trial(trial_id="tw1", protocol="movement", time_s=t2, force=np.sin(t2 * 10.0), force_unit="N*m",
                 length_unit="rad", length=np.linspace(0.1, 0.4, 200),
                 stimulus_times_s=np.linspace(t2[10], t2[150], 8), attrs={"labels": ["a", "b"]})
    return MeasuredData(trials={"tw2": twitch, "tw1": ramp},
                        attrs={"species": "cat", "muscle": "soleus", "preparation": "in situ",
                               "source": "synthetic", "licence": "CC0", "n_cats": 1},
                        motor_units={"mu1": np.array([0.01, 0.02, 0.02, 0.3])},
                        extra_datasets={"/extra/emg": np.arange(5.0)},
                        extra_attrs={"/extra": {"kind": "emg"}})


def write_raw(path: Path, mutate: Callable[[h5py.File], None] | None = None) -> Path:
    """A valid file built directly with h5py (independent of write_measured), then ``mutate``d."""
    t = np.arange(100) * 0.01
    with h5py.File(path, "w") as h5:
        h5.attrs["schema"] = SCHEMA
        h5.attrs["species"] = "cat"
        trial = h5.create_group("trials/tw1")
        trial.attrs.update(protocol="twitch", force_unit="N", length_unit="mm")
        trial.create_dataset("time", data=t)
        trial.create_dataset("force", data=np.sin(t))
        trial.create_dataset("length", data=np.zeros_like(t))
        trial.create_dataset("stimulus_times", data=np.array([0.1, 0.5]))
        iso = h5.create_group("trials/iso")
        iso.attrs.update(protocol="train", force_unit="N", length_unit="mm", length=2.5)
        iso.create_dataset("time", data=t)
        iso.create_dataset("force", data=np.cos(t))
        iso.create_dataset("stimulus_times", data=np.zeros(0))
        if mutate is not None:
            mutate(h5)
    return path


def set_value(name: str, index: int, value: float) -> Callable[[h5py.File], None]:
    """Mutation: dataset trials/tw1/<name>[index] = value."""
    def mutate(h5: h5py.File) -> None:
        h5[f"trials/tw1/{name}"][index] = value
    return mutate


def replace_dataset(name: str, values: np.ndarray) -> Callable[[h5py.File], None]:
    """Mutation: replace dataset trials/tw1/<name>."""
    def mutate(h5: h5py.File) -> None:
        del h5[f"trials/tw1/{name}"]
        h5[f"trials/tw1/{name}"] = values
    return mutate


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()

