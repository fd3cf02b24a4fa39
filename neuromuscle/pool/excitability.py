"""Current-clamp measurements of one motoneuron: rheobase, AHP duration, f-I slope, hysteresis on a triangle.

Each builds its own IClamp at the soma, runs through the Simulator (fixed step, from ``v_init_mV``) and removes
the clamp.  Units: nA, ms, mV, Hz.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..sim import Simulator
from .motoneuron import Motoneuron

_THRESHOLD_MV = -10.0


def clamp_run(cell: Motoneuron, times_ms: Sequence[float], amps_nA: Sequence[float], duration_ms: float,
              *, steps: bool, dt_ms: float = 0.025) -> tuple[np.ndarray, np.ndarray]:
    """Inject a current at the soma: ``amps_nA`` at ``times_ms`` held piecewise constant (``steps``) or linearly
    interpolated; returns (spike times ms, soma potential mV every dt_ms)."""
    from neuron import h

    ic = h.IClamp(cell.soma(0.5))
    ic.delay, ic.dur = 0.0, 1e9
    tv, av = h.Vector(np.asarray(times_ms, float)), h.Vector(np.asarray(amps_nA, float))
    av.play(ic._ref_amp, tv, 0 if steps else 1)
    spikes = h.Vector()
    nc = h.NetCon(cell.spike_source(), None, sec=cell.soma)
    nc.threshold = _THRESHOLD_MV
    nc.record(spikes)
    v = h.Vector().record(cell.soma(0.5)._ref_v)
    Simulator(method="fixed", dt_ms=dt_ms, v_init_mV=cell.params.e_leak_mV).run(duration_ms)
    out = np.array(spikes), np.array(v)
    av.play_remove()
    del nc, ic
    return out


def step_spikes(cell: Motoneuron, amp_nA: float, duration_ms: float = 200.0, onset_ms: float = 100.0) -> np.ndarray:
    """Spike times (ms) during and just after a current step of amp_nA from onset_ms for duration_ms."""
    sp, _ = clamp_run(cell, [0.0, onset_ms, onset_ms + duration_ms], [0.0, amp_nA, 0.0],
                      onset_ms + duration_ms + 5.0, steps=True)
    return sp[sp >= onset_ms]


def rheobase_nA(cell: Motoneuron, upper_nA: float = 100.0, tolerance_nA: float = 0.05,
                duration_ms: float = 200.0) -> float:
    """Smallest step current (nA, within tolerance_nA) that fires the cell within a duration_ms step (bisection)."""
    lo, hi = 0.0, upper_nA
    if step_spikes(cell, hi, duration_ms).size == 0:
        raise ValueError(f"{cell.name}: no spike even at {upper_nA} nA")
    while hi - lo > tolerance_nA:
        mid = 0.5 * (lo + hi)
        if step_spikes(cell, mid, duration_ms).size:
            hi = mid
        else:
            lo = mid
    return hi


def ahp_duration_ms(cell: Motoneuron, pulse_nA: float = 30.0, pulse_ms: float = 1.0, recovery: float = 0.9) -> float:
    """Duration (ms) of the afterhyperpolarisation after one spike evoked by a brief pulse: from the spike until the
    potential has recovered ``recovery`` of the way from the AHP trough back to rest."""
    onset = 200.0
    sp, v = clamp_run(cell, [0.0, onset, onset + pulse_ms], [0.0, pulse_nA, 0.0], onset + 800.0, steps=True)
    if sp.size != 1:
        raise ValueError(f"{cell.name}: the {pulse_nA} nA, {pulse_ms} ms pulse gave {sp.size} spikes, not one")
    dt = 0.025
    rest = v[int((onset - 1.0) / dt)]
    after = v[int(sp[0] / dt):]
    trough = int(np.argmin(after))
    back = np.flatnonzero(after[trough:] > after[trough] + recovery * (rest - after[trough]))
    if not back.size:
        raise ValueError(f"{cell.name}: the potential did not recover from the AHP within 800 ms")
    return float((trough + back[0]) * dt)


def fi_slope_Hz_per_nA(cell: Motoneuron, amps_nA: Sequence[float], duration_ms: float = 1000.0,
                       skip_ms: float = 500.0) -> tuple[float, np.ndarray]:
    """Steady discharge rate (Hz, spikes after skip_ms of each step) at each step current, and the slope (Hz/nA)
    of a straight line through them."""
    rates = []
    for a in amps_nA:
        sp = step_spikes(cell, a, duration_ms)
        rates.append(np.sum(sp >= 100.0 + skip_ms) / ((duration_ms - skip_ms) / 1000.0))
    r = np.asarray(rates, float)
    return float(np.polyfit(np.asarray(amps_nA, float), r, 1)[0]), r


@dataclass(frozen=True)
class Hysteresis:
    """Recruitment and derecruitment on a triangular current: currents (nA) at the first and the last spike."""

    on_nA: float
    off_nA: float
    n_spikes: int

    @property
    def delta_nA(self) -> float:
        """off - on (nA): negative when the cell keeps firing below its recruitment current (a PIC's signature)."""
        return self.off_nA - self.on_nA


def triangle_hysteresis(cell: Motoneuron, peak_nA: float, rise_ms: float = 2000.0) -> Hysteresis:
    """Fire the cell by a triangular current 0 -> peak_nA -> 0 (rise_ms up, rise_ms down) and report the currents
    at recruitment and derecruitment."""
    sp, _ = clamp_run(cell, [0.0, rise_ms, 2 * rise_ms], [0.0, peak_nA, 0.0], 2 * rise_ms, steps=False)
    if sp.size == 0:
        raise ValueError(f"{cell.name}: no spike on the {peak_nA} nA triangle")
    current: Any = lambda t: peak_nA * (t / rise_ms if t <= rise_ms else (2 * rise_ms - t) / rise_ms)
    return Hysteresis(current(sp[0]), current(sp[-1]), int(sp.size))
