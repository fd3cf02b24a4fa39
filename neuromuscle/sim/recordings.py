"""Recordings by name (Brian2's StateMonitor): ``"force.F"``, ``"act.A"``, ``"ca.CaSPT"`` resolved through the
unit's components, sampled every ``record_dt_ms`` by NEURON's Vector.record (no per-step Python)."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..errors import InputError


def on_time_grid(t_ms: np.ndarray) -> np.ndarray:
    """Times (ms) rounded to the 1e-9 ms grid that recordings and played lengths share."""
    return np.round(np.asarray(t_ms, dtype=float), 9)


def sample_count(duration_ms: float, record_dt_ms: float) -> int:
    """How many samples k * record_dt_ms (ms) lie in 0..duration_ms (ms), both ends included."""
    return int(np.floor(duration_ms / record_dt_ms + 1e-9)) + 1


def sample_times_ms(record_dt_ms: float, n: int) -> np.ndarray:
    """The n sample times k * record_dt_ms (ms), rounded to 1e-9 ms: the same grid as played lengths (run.py),
    so a sample and a breakpoint meant to coincide are the same double."""
    return on_time_grid(np.arange(n) * record_dt_ms)


class Recorder:
    """Vectors recording the named variables of one unit every ``record_dt_ms`` (ms) from t = 0.

    The unit is anything with ``name``, ``recordables()`` ({name: unit}), ``ref(name)`` (the NEURON reference)
    and ``owner(name)`` (the point process or section holding the variable): a MuscleUnit, or a pool's unit
    with its motoneuron (``neuromuscle.pool.recording``).

    With ``every_step_dt_ms`` (the fixed step, ms) NEURON records every step and the samples are taken every
    record_dt_ms afterwards: with more than one thread, NEURON 9's interval recording samples the variables of
    the second thread at the wrong moments (measured in tests/sim/test_unit.py), stepwise recording does not;
    CoreNEURON records only every step.  ``take()`` moves the samples out of the every-step vectors (call it
    between the parts of a run made in chunks, so that memory holds one chunk's steps, not the run's).
    """

    def __init__(self, unit: Any, names: Sequence[str], record_dt_ms: float,
                 every_step_dt_ms: float | None = None, at_times_until_ms: float | None = None) -> None:
        from neuron import h, nrn

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
        self._refs = {n: unit.ref(n) for n in names}
        self._stride = 1
        self._taken: dict[str, list[np.ndarray]] = {n: [] for n in names}
        self._steps_taken = 0  # every-step values already moved out of the vectors
        if every_step_dt_ms is not None:
            self._stride = max(1, int(round(record_dt_ms / every_step_dt_ms)))
            if abs(self._stride * every_step_dt_ms - record_dt_ms) > 1e-9 * record_dt_ms:
                raise InputError(f"record_dt_ms = {record_dt_ms} ms must be a multiple of dt_ms = "
                                 f"{every_step_dt_ms} ms when NEURON runs on several threads or CoreNEURON runs")
        self._tvec = None
        if at_times_until_ms is not None:
            # explicit sample times, rounded to 1e-9 ms like the played length's times: NEURON 9.0.2's CVODE
            # aborts the process (an assertion in NetCvode::global_microstep) when an interval recording's
            # accumulated time, k * 0.025 ms, falls a rounding error short of a time where the integrator stopped
            self._tvec = h.Vector(sample_times_ms(record_dt_ms, sample_count(at_times_until_ms, record_dt_ms)))
        for n, v in self._vectors.items():
            when = (self._tvec,) if self._tvec is not None else (record_dt_ms,) if every_step_dt_ms is None else ()
            # the owner first (a point process, or the section of a membrane variable): it tells NEURON which
            # thread owns the variable
            owner = unit.owner(n)
            if isinstance(owner, nrn.Section):
                v.record(unit.ref(n), *when, sec=owner)
            else:
                v.record(owner, unit.ref(n), *when)

    def arrays(self, duration_ms: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Sample times (ms) k * record_dt_ms for k = 0 .. floor(duration_ms / record_dt_ms), the end included
        whatever the integrator (NEURON's interval recording may stop one sample short of tstop, depending on
        rounding and on the method), and the traces at those times.  Call right after the run: a missing last
        sample is the variable's value at the end of the run."""
        n = sample_count(duration_ms, self.record_dt_ms)
        out = {}
        self.take()
        for k in self._vectors:
            a = np.concatenate(self._taken[k]) if self._taken[k] else np.zeros(0)
            if a.size < n:
                a = np.concatenate([a, np.full(n - a.size, float(self._refs[k][0]))]) if a.size == n - 1 else a
            out[k] = a[:n]
        short = [k for k, v in out.items() if v.size != n]
        if short:
            raise RuntimeError(f"recording of {short} holds fewer samples than 0..{duration_ms} ms every "
                               f"{self.record_dt_ms} ms")
        return np.arange(n) * self.record_dt_ms, out

    def take(self) -> None:
        """Move the samples recorded so far out of NEURON's vectors (every stride-th value of every-step
        recordings, counted from t = 0 across calls) and empty the vectors."""
        size = None
        for k, v in self._vectors.items():
            a = np.array(v)
            first = (-self._steps_taken) % self._stride  # the first value of this part that is a sample
            self._taken[k].append(a[first::self._stride])
            size = a.size
            v.resize(0)
        self._steps_taken += size or 0
