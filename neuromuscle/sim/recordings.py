"""Recordings by name (Brian2's StateMonitor): ``"force.F"``, ``"act.A"``, ``"ca.CaSPT"`` resolved through the
unit's components, sampled every ``record_dt_ms`` by NEURON's Vector.record (no per-step Python)."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..errors import InputError


class Recorder:
    """Vectors recording the named variables of one unit every ``record_dt_ms`` (ms) from t = 0."""

    def __init__(self, unit: Any, names: Sequence[str], record_dt_ms: float) -> None:
        from neuron import h

        if len(set(names)) != len(names):
            raise InputError(f"recorded names repeat: {list(names)}")
        known = unit.recordables()
        unknown = [n for n in names if n not in known]
        if unknown:
            raise InputError(f"{unit.name}: cannot record {unknown}; recordable: {', '.join(known)}")
        self.names = tuple(names)
        self.units = {n: known[n] for n in names}
        self.record_dt_ms = record_dt_ms
        # time itself is not recorded (a record of t belongs to no thread): samples are at k * record_dt_ms
        self._vectors = {n: h.Vector() for n in names}
        for n, v in self._vectors.items():
            v.record(unit.ref(n), record_dt_ms)

    def arrays(self, duration_ms: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Sample times (ms) and the recorded traces, all of the same length."""
        out = {k: np.array(v) for k, v in self._vectors.items()}
        n = min(len(v) for v in out.values())
        out = {k: v[:n] for k, v in out.items()}
        return np.arange(n) * self.record_dt_ms, out
