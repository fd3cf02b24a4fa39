"""Playing a hidden effect into NEURON: the SynthPlay component (mod/SynthPlay.mod) and the unit that reads it.

A hidden effect is a set of time series (simulation clock, ms) for some of the baseline's modulation ports
(KimCa.release_gain, KimCa.uptake_gain, KimAct.tauA_gain, KimForce.force_offset).  ``SynthPlay`` holds them and
plays them into its RANGE variables by ``Vector.play`` (continuous: linear interpolation between samples, a step
is two samples close together); :func:`played_models` gives the Kim Modules 1-3 whose modulation ports read those
variables.  Ports with no series stay at their mechanism's neutral value, and an empty
series mapping gives exactly the baseline.  The play costs O(1) per step, in fixed step and CVODE alike.
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any, Mapping

import numpy as np

from ..errors import InputError
from ..model.component import Component
from ..model.kim import KimForce, kim_excitation

#: Modulation port -> the slot of the baseline component that reads it.
PORT_SLOTS = {"release_gain": "ca", "uptake_gain": "ca", "tauA_gain": "act", "force_offset": "force"}
#: The slot SynthPlay takes in a unit.
SLOT = "synth"

Series = Mapping[str, tuple[np.ndarray, np.ndarray]]


class SynthPlay(Component):
    """Played modulation (mod/SynthPlay.mod): ``series`` maps a port name to (t_ms, values) played into the
    RANGE variable of the same name (units: 1 for the gains, N for force_offset)."""

    suffix = "SynthPlay"
    namespace = "synth_play"
    exposes = {"release_gain": "1", "uptake_gain": "1", "tauA_gain": "1", "force_offset": "N"}

    def __init__(self, series: Series) -> None:
        super().__init__()
        unknown = sorted(set(series) - set(PORT_SLOTS))
        if unknown:
            raise InputError(f"SynthPlay: unknown port(s) {unknown}; ports: {', '.join(PORT_SLOTS)}")
        self.series = {k: _checked(k, t, v) for k, (t, v) in series.items()}
        self._vectors: list[tuple[Any, Any]] = []

    def configure(self, params: Mapping[str, float] | None) -> None:
        from neuron import h

        self._vectors = []
        for port, (t, v) in self.series.items():
            tvec, vvec = h.Vector(t), h.Vector(v)
            setattr(self.obj, port, float(v[0]))
            vvec.play(getattr(self.obj, f"_ref_{port}"), tvec, 1)
            self._vectors.append((tvec, vvec))

    def destroy(self) -> None:
        for _, vvec in self._vectors:
            vvec.play_remove()
        self._vectors = []
        super().destroy()


def _checked(port: str, t: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(t, dtype=float)
    v = np.asarray(v, dtype=float)
    if t.ndim != 1 or t.shape != v.shape or t.size < 2:
        raise InputError(f"SynthPlay: port {port!r} needs time and value arrays of one size >= 2, got "
                         f"{t.shape} and {v.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))) or np.any(np.diff(t) < 0):
        raise InputError(f"SynthPlay: port {port!r}: times must be finite and non-decreasing, values finite")
    return t, v


def _reading(component: Component, ports: list[str]) -> Component:
    """A copy of ``component`` whose modulation ports ``ports`` read SynthPlay's variables of the same name."""
    out = copy.copy(component)
    out.reads = tuple(replace(p, source=f"{SLOT}.{p.name}") if p.name in ports else p for p in component.reads)
    return out


def played_models(series: Series, length_compensation: bool = False,
                  movement_compensation: bool = False) -> tuple[dict[str, Component], dict[str, Component]]:
    """(excitation, contraction) for ``MuscleUnit``/``simulate``: Kim Modules 1-2 (eq 18 and eqs 19-20 as given,
    off by default), Module 3, their modulation ports in ``series`` reading a SynthPlay that plays it (none: the
    model without modulation)."""
    excitation = kim_excitation(length_compensation=length_compensation,
                                movement_compensation=movement_compensation)
    contraction: dict[str, Component] = {"force": KimForce()}
    if not series:
        return excitation, contraction
    slots = {**excitation, **contraction}
    for slot in set(PORT_SLOTS[p] for p in series):
        driven = [p for p in series if PORT_SLOTS[p] == slot]
        reading = _reading(slots[slot], driven)
        (excitation if slot in excitation else contraction)[slot] = reading
    contraction[SLOT] = SynthPlay(series)
    return excitation, contraction
