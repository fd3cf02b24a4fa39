"""What an extension's SciPy twin is made of (``neuromuscle.reference`` integrates it with Modules 1-3).

An extension without memory gives its port signals as closed-form functions of t; one with memory gives a
:class:`StateModulation`: extra states, their right-hand side and its ports as functions of those states and of the
:class:`Observables` at t.  Units: t in ms, states per ms.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import numpy as np


@dataclass(frozen=True)
class Observables:
    """What an extension's twin reads at time t: activation A (1), length Xm (mm), the played velocity Vm (mm/s),
    the series-elastic force Fse (N, eq 9) and the parameter set."""

    A: float
    xm_mm: float
    vm_mm_s: float
    fse_N: float
    params: Mapping[str, float]


@dataclass(frozen=True)
class StateModulation:
    """An extension's twin with memory: extra states integrated with Modules 1-3 from ``y0``; ``rhs(t, y,
    obs)`` gives their derivatives (per ms), ``ports[name](t, y, obs)`` the value of a port of NEUTRAL_PORTS."""

    y0: tuple[float, ...]
    rhs: Callable[[float, np.ndarray, Observables], Sequence[float]]
    ports: Mapping[str, Callable[[float, np.ndarray, Observables], float]]
