"""A measured trial simulated: the model's force at the trial's own samples, and synthetic trials made that way.

* :func:`trial_simulation`: the trial's clock (s) becomes the simulation clock (ms) with ``time_s[0]`` at
  ``settle_ms`` (:func:`trial_clock`); during the settling the length is held at the trial's first length; the
  force is recorded every ``record_dt_ms`` and interpolated linearly at the trial's samples.  Trials must be in N
  and mm (the model's units): joint moments and angles are refused.
* :func:`synthetic_trial`: a trial simulated from known parameters plus Gaussian noise; :func:`ar1_noise`: the
  autocorrelated noise of a force transducer.  The package's example file, ``neuromuscle bench fit`` and the tests
  make their data this way, so a fit with the same options sees the model the data were made with.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.signal import lfilter

from ..errors import InputError
from ..model.kim import kim_excitation
from ..parameters import ParameterSet
from ..protocols import LengthTrace
from ..sim import Simulator, simulate
from ..sim.unit import Model
from .schema import Trial


def check_trial_units(trial: Trial) -> None:
    """Refuse a trial whose force is not in N or whose length is not in mm."""
    if trial.force_unit != "N" or trial.length_unit != "mm":
        raise InputError(f"trial '{trial.trial_id}': force in {trial.force_unit!r} and length in "
                         f"{trial.length_unit!r}; the muscle model needs 'N' and 'mm' (convert joint moments "
                         "and angles first)")


def constant_length(trial: Trial) -> float | None:
    """The trial's length (mm) when it is held exactly constant (a constant length, or every length sample equal):
    it is then simulated as a constant, and no extension that acts through or after a movement changes its force.
    None when the length varies."""
    if trial.length is None:
        return None if trial.length_const is None else float(trial.length_const)
    x = np.asarray(trial.length, dtype=float)
    return float(x[0]) if x.size and np.all(x == x[0]) else None


def trial_clock(trial: Trial, settle_ms: float) -> tuple[np.ndarray, float, np.ndarray, LengthTrace | float]:
    """The trial on the simulation clock: sample times (ms), duration (ms), stimulus times (ms) and the length
    (mm, constant or a trace), time_s[0] at settle_ms."""
    check_trial_units(trial)
    if not np.isfinite(settle_ms) or settle_ms < 0:
        raise InputError(f"settle_ms must be finite and >= 0, got {settle_ms}")
    t0 = float(trial.time_s[0])
    t_ms = settle_ms + (np.asarray(trial.time_s, dtype=float) - t0) * 1000.0
    spikes_ms = settle_ms + (np.asarray(trial.stimulus_times_s, dtype=float) - t0) * 1000.0
    length: LengthTrace | float
    if trial.length is None:
        if trial.length_const is None:
            raise InputError(f"trial '{trial.trial_id}': neither a length dataset nor a constant length")
        length = float(trial.length_const)
    else:
        x = np.asarray(trial.length, dtype=float)
        lt, lx = (t_ms, x) if settle_ms == 0 else (np.concatenate([[0.0], t_ms]), np.concatenate([[x[0]], x]))
        still = constant_length(trial)
        length = still if still is not None else LengthTrace(lt, lx, name=f"trial {trial.trial_id}")
    return t_ms, float(t_ms[-1]), spikes_ms, length


def trial_simulation(params: ParameterSet, trial: Trial, dt_ms: float = 0.05, *,
                     record_dt_ms: float | None = None, settle_ms: float = 500.0,
                     length_compensation: bool = True, movement_compensation: bool = False,
                     extensions: tuple[str, ...] = (), excitation: Model = None,
                     contraction: Model = None, differenced: bool = False) -> np.ndarray:
    """Simulated force (N) of a measured trial at the trial's own time points (``trial.time_s``, s).

    The trial's time_s[0] is placed at settle_ms (ms) of simulated time; the length (constant or played) is
    held at its first value before that.  Stimulus times (s) are converted to ms on the same clock.
    extensions: canonical names of catalogue extensions to switch on, valued from ``params``.
    excitation/contraction: as ``MuscleUnit`` (default: Kim Modules 1-2 with the two switches, Module 3).
    differenced: the force is only differenced against a run at the same step (``Simulator.differenced``).
    """
    t_ms, duration_ms, spikes_ms, length = trial_clock(trial, settle_ms)
    rec = dt_ms if record_dt_ms is None else record_dt_ms
    res = simulate(params, spikes_ms, length, duration_ms, record_dt_ms=rec, record=("force.F",),
                   simulator=Simulator(method="fixed", dt_ms=dt_ms, differenced=differenced),
                   excitation=kim_excitation(length_compensation, movement_compensation) if excitation is None
                   else excitation, contraction=contraction,
                   extensions={name: {} for name in extensions} or None)
    return np.interp(t_ms, res.t_ms, res.force_N)


def synthetic_trial(params: ParameterSet, trial_id: str, time_s: np.ndarray, stimulus_times_s: Sequence[float], *,
                    protocol: str = "twitch", length_mm: float | None = None, length: np.ndarray | None = None,
                    noise_N: float = 0.0, rng: np.random.Generator | None = None, dt_ms: float = 0.05,
                    **simulation: Any) -> Trial:
    """A measured-data Trial (N, mm) at time_s (s): the force of ``params`` simulated by ``trial_simulation``
    (dt_ms, and its keyword options ``simulation``: record_dt_ms, settle_ms, ...) plus Gaussian noise of sd
    noise_N (N) drawn from ``rng`` (required with noise, so that the data are reproducible; no draw when
    noise_N is 0).  Isometric at length_mm (mm), or the sampled ``length`` (mm, one value per time sample)."""
    if noise_N and rng is None:
        raise InputError(f"trial '{trial_id}': noise_N = {noise_N} N needs rng (np.random.default_rng(seed))")
    time_s = np.asarray(time_s, dtype=float)
    tr = Trial(trial_id=trial_id, protocol=protocol, time_s=time_s, force=np.zeros_like(time_s), force_unit="N",
               length_unit="mm", length_const=length_mm, length=length,
               stimulus_times_s=np.asarray(stimulus_times_s, dtype=float))
    force = trial_simulation(params, tr, dt_ms, **simulation)
    if noise_N:
        force = force + rng.normal(0.0, noise_N, force.size)
    tr.force = force
    return tr


def ar1_noise(n: int, sd_N: float, tau_ms: float, sample_ms: float, rng: np.random.Generator) -> np.ndarray:
    """n samples (every sample_ms, ms) of stationary AR(1) noise with marginal sd sd_N (N) and correlation time
    tau_ms (ms; lag-1 correlation exp(-sample_ms / tau_ms); 0: white), as force transducers give."""
    phi = float(np.exp(-sample_ms / tau_ms)) if tau_ms > 0 else 0.0
    x = sd_N * rng.standard_normal(n)
    x[1:] *= np.sqrt(1.0 - phi * phi)
    return lfilter([1.0], [1.0, -phi], x)
