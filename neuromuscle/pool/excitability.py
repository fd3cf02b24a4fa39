"""Current-clamp measurements of one motoneuron (any cell of the pool's interface, ``pool.cells``): rheobase, AHP
duration, f-I slope, hysteresis on a triangle, self-sustained firing, the rates under a common synaptic drive, the
lowest steady rate under a constant synaptic drive, and the recruitment hysteresis and paired-unit Delta F of
cells under one slow synaptic triangle.

Each builds its own IClamp at the soma, runs through the Simulator (fixed step, from ``v_init_mV``) and removes
the clamp.  ``python -m neuromuscle.pool.excitability`` prints the cells' figures (S to FF) as JSON;
``--synaptic-triangle NM [NM ...]`` the synaptic triangle's figures at those neuromodulations instead, and
``--minimum-rate NM [NM ...]`` the lowest steady rates (``--set NAME=VALUE``: a motoneuron parameter replaced in
every cell, e.g. ``--set cal_vhalf_mV=-50``).
Units: nA, ms, mV, Hz, uS.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..sim import Simulator
from ..validate import positive_number
from .cells import MotoneuronCell
from .discharge_stats import DeltaF, delta_f
from .motoneuron import Motoneuron, clear_synaptic_conductance, parse_settings

_THRESHOLD_MV = -10.0


def clamp_run(cell: MotoneuronCell, times_ms: Sequence[float], amps_nA: Sequence[float], duration_ms: float,
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
    Simulator(method="fixed", dt_ms=dt_ms, v_init_mV=cell.v_rest_mV).run(duration_ms)
    out = np.array(spikes), np.array(v)
    av.play_remove()
    del nc, ic
    return out


def steady_rate_hz(cell: MotoneuronCell, amp_nA: float, duration_ms: float = 1500.0, skip_ms: float = 1000.0) -> float:
    """Mean discharge rate (Hz) from skip_ms (ms) after the onset of a step of amp_nA to its end (the adapted,
    steady discharge Kernell 1965 measured); 0 when fewer than two spikes fall there."""
    sp = step_spikes(cell, amp_nA, duration_ms)
    late = sp[sp >= 100.0 + skip_ms]
    return float((late.size - 1) * 1000.0 / (late[-1] - late[0])) if late.size > 2 else 0.0


def input_resistance_step_MOhm(cell: MotoneuronCell, amp_nA: float = -0.5, duration_ms: float = 400.0) -> float:
    """Input resistance (MOhm) as a physiologist measures it: the steady change of the soma potential under a
    small hyperpolarising step (amp_nA, nA) divided by the current."""
    dt = 0.025
    _, v = clamp_run(cell, [0.0, 200.0, 200.0 + duration_ms], [0.0, amp_nA, 0.0], 200.0 + duration_ms,
                     steps=True, dt_ms=dt)
    return float((v[int((200.0 + duration_ms - 1.0) / dt)] - v[int(199.0 / dt)]) / amp_nA)


def step_spikes(cell: MotoneuronCell, amp_nA: float, duration_ms: float = 200.0, onset_ms: float = 100.0) -> np.ndarray:
    """Spike times (ms) during and just after a current step of amp_nA from onset_ms for duration_ms."""
    sp, _ = clamp_run(cell, [0.0, onset_ms, onset_ms + duration_ms], [0.0, amp_nA, 0.0],
                      onset_ms + duration_ms + 5.0, steps=True)
    return sp[sp >= onset_ms]


def rheobase_nA(cell: MotoneuronCell, upper_nA: float = 100.0, tolerance_nA: float = 0.05,
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


def ahp_duration_ms(cell: MotoneuronCell, pulse_nA: float = 150.0, pulse_ms: float = 0.5,
                    recovery: float = 0.9) -> float:
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


def fi_slope_Hz_per_nA(cell: MotoneuronCell, amps_nA: Sequence[float], duration_ms: float = 1000.0,
                       skip_ms: float = 500.0) -> tuple[float, np.ndarray]:
    """Steady discharge rate (Hz, ``steady_rate_hz`` after skip_ms of each step) at each step current, and the
    slope (Hz/nA) of a straight line through them."""
    r = np.array([steady_rate_hz(cell, a, duration_ms, skip_ms) for a in amps_nA])
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


def triangle_hysteresis(cell: MotoneuronCell, peak_nA: float, rise_ms: float = 2000.0) -> Hysteresis:
    """Fire the cell by a triangular current 0 -> peak_nA -> 0 (rise_ms up, rise_ms down) and report the currents
    at recruitment and derecruitment."""
    sp, _ = clamp_run(cell, [0.0, rise_ms, 2 * rise_ms], [0.0, peak_nA, 0.0], 2 * rise_ms, steps=False)
    if sp.size == 0:
        raise ValueError(f"{cell.name}: no spike on the {peak_nA} nA triangle")
    def current(t: float) -> float:
        return peak_nA * (t / rise_ms if t <= rise_ms else (2 * rise_ms - t) / rise_ms)

    return Hysteresis(current(sp[0]), current(sp[-1]), int(sp.size))


def self_sustained_ms(cell: MotoneuronCell, bias_nA: float, pulse_nA: float, pulse_ms: float = 500.0,
                      after_ms: float = 3000.0) -> float:
    """How long (ms) the cell keeps firing after a brief depolarising pulse (pulse_nA above bias_nA for pulse_ms)
    while the bias current holds on (Lee & Heckman 1998's test of bistability): the time from the pulse's end to
    the last spike, 0 when the firing stops with the pulse."""
    onset = 500.0
    end = onset + pulse_ms
    sp, _ = clamp_run(cell, [0.0, onset, end], [bias_nA, bias_nA + pulse_nA, bias_nA], end + after_ms, steps=True)
    after = sp[sp > end + 5.0]
    return float(after[-1] - end) if after.size else 0.0


def synaptic_rates_hz(cell: MotoneuronCell, conductances_uS: Sequence[float], duration_ms: float = 1500.0,
                      skip_ms: float = 1000.0) -> np.ndarray:
    """Steady rate (Hz, after skip_ms) under each constant common synaptic conductance (uS, the cell's total;
    the cell's ``play_synaptic_conductance``), one run each."""
    from neuron import h

    out = []
    for g in conductances_uS:
        tv = h.Vector([0.0])
        kept = cell.play_synaptic_conductance(tv, [float(g)])
        sp, _ = clamp_run(cell, [0.0, duration_ms], [0.0, 0.0], duration_ms, steps=True)
        for vec in kept:
            vec.play_remove()
        clear_synaptic_conductance(cell.sections)
        late = sp[sp >= skip_ms]
        out.append((late.size - 1) * 1000.0 / (late[-1] - late[0]) if late.size > 2 else 0.0)
    return np.array(out)


def minimum_synaptic_rate(cell: MotoneuronCell, upper_uS: float = 1.0, tolerance: float = 0.002,
                          duration_ms: float = 3000.0, skip_ms: float = 1500.0) -> tuple[float, float]:
    """The smallest constant common synaptic conductance (uS, within a relative ``tolerance``) under which the cell
    fires steadily (``synaptic_rates_hz`` after skip_ms > 0), found by bisection, and its steady rate (Hz) there:
    the lower limit of steady discharge that Kernell 1965 related to the AHP's duration."""
    positive_number("minimum_synaptic_rate: upper_uS", upper_uS)
    if not 0.0 < tolerance < 1.0:
        raise InputError(f"minimum_synaptic_rate: tolerance must lie in (0, 1), got {tolerance!r}")
    lo, hi = 0.0, upper_uS
    rate = float(synaptic_rates_hz(cell, [hi], duration_ms, skip_ms)[0])
    if rate <= 0:
        raise ValueError(f"{cell.name}: no steady discharge even at {upper_uS} uS")
    while hi - lo > tolerance * hi:
        mid = 0.5 * (lo + hi)
        r = float(synaptic_rates_hz(cell, [mid], duration_ms, skip_ms)[0])
        if r > 0:
            hi, rate = mid, r
        else:
            lo = mid
    return hi, rate


@dataclass(frozen=True)
class SynapticTriangle:
    """Cells under one common synaptic triangle 0 -> ``peak_uS`` -> 0 (``rise_ms`` each way): each cell's drive
    (uS) at its first and last spike (``on_uS``, ``off_uS``; NaN if it never fired) and the paired-unit Delta F
    of their discharges taken together, as a pool's units under one drive (``delta_f``)."""

    sizes: tuple[float, ...]
    neuromodulation: float
    on_uS: np.ndarray
    off_uS: np.ndarray
    delta_f: DeltaF

    def summary(self) -> dict[str, Any]:
        """JSON-ready figures."""
        return {"sizes": list(self.sizes), "neuromodulation": self.neuromodulation,
                "on_uS": [float(x) for x in self.on_uS], "off_uS": [float(x) for x in self.off_uS],
                "delta_f": self.delta_f.summary()}


def synaptic_triangle(sizes: Sequence[float], neuromodulation: float, *, peak_uS: float = 0.3,
                      rise_ms: float = 10000.0, step_ms: float = 10.0, dt_ms: float = 0.025,
                      **overrides: Any) -> SynapticTriangle:
    """Run each cell at size index ``sizes`` (0..1; ``overrides``: motoneuron parameters replaced in each) alone
    under the common synaptic conductance 0 -> ``peak_uS`` (uS, the cell's total) -> 0, ``rise_ms`` (ms) each
    way, set every ``step_ms`` (ms); report recruitment and derecruitment drives and the paired-unit Delta F.

    Unlike a current injected at the soma, the synaptic conductance also depolarises and shunts the dendrite
    that holds the PIC, as the drive of a voluntary contraction does."""
    from neuron import h

    from .motoneuron import motoneuron_parameters

    if "neuromodulation" in overrides:
        raise InputError("synaptic_triangle: give the neuromodulation as its argument, not among the overrides")
    times = np.arange(0.0, 2.0 * rise_ms + step_ms / 2, step_ms)
    drive = peak_uS * (1.0 - np.abs(times - rise_ms) / rise_ms)
    trains, on, off = [], [], []
    for x in sizes:
        with Motoneuron(motoneuron_parameters(float(x), neuromodulation=neuromodulation, **overrides)) as mn:
            tv = h.Vector(times)
            kept = mn.play_synaptic_conductance(tv, drive)
            sp, _ = clamp_run(mn, [0.0], [0.0], 2.0 * rise_ms, steps=True, dt_ms=dt_ms)
            for vec in kept:
                vec.play_remove()
        trains.append(sp)
        on.append(float(np.interp(sp[0], times, drive)) if sp.size else np.nan)
        off.append(float(np.interp(sp[-1], times, drive)) if sp.size else np.nan)
    return SynapticTriangle(tuple(float(x) for x in sizes), float(neuromodulation), np.array(on), np.array(off),
                            delta_f(trains))


def cell_facts(size: float, neuromodulation: float = 0.0) -> dict[str, float]:
    """The figures a physiologist measures on the cell at ``size`` (0..1) and ``neuromodulation``: input
    resistance (MOhm), rheobase (nA, 200-ms steps), AHP duration (ms), steady f-I slopes (Hz/nA) over 1.25-2 and
    3-5 rheobase (primary and secondary ranges)."""
    from .motoneuron import motoneuron_parameters

    with Motoneuron(motoneuron_parameters(size, neuromodulation=neuromodulation)) as mn:
        rb = rheobase_nA(mn, upper_nA=120.0, tolerance_nA=0.1)
        lo = [1.25 * rb, 1.5 * rb, 2.0 * rb]
        hi = [3.0 * rb, 4.0 * rb, 5.0 * rb]
        primary, _ = fi_slope_Hz_per_nA(mn, lo, 1500.0, 1000.0)
        secondary, _ = fi_slope_Hz_per_nA(mn, hi, 1500.0, 1000.0)
        return {"size": size, "neuromodulation": neuromodulation, "input_resistance_MOhm": mn.input_resistance_MOhm(),
                "rheobase_nA": rb, "ahp_ms": ahp_duration_ms(mn, pulse_nA=150.0, pulse_ms=0.5),
                "fi_primary_Hz_per_nA": primary, "fi_secondary_Hz_per_nA": secondary}


def minimum_rate_facts(size: float, neuromodulation: float, **overrides: Any) -> dict[str, Any]:
    """The cell at ``size`` (0..1), ``neuromodulation`` and ``overrides`` (motoneuron parameters): its lowest
    steady rate under a constant synaptic drive (Hz), the drive there (uS) and its AHP duration (ms)."""
    from .motoneuron import motoneuron_parameters

    with Motoneuron(motoneuron_parameters(size, neuromodulation=neuromodulation, **overrides)) as mn:
        drive, rate = minimum_synaptic_rate(mn, upper_uS=2.0)
        return {"size": size, "neuromodulation": neuromodulation, "overrides": overrides,
                "minimum_rate_hz": rate, "drive_uS": drive, "ahp_ms": ahp_duration_ms(mn)}


def main(argv: Sequence[str] | None = None) -> list[dict[str, Any]]:
    """Command line (module docstring); prints and returns the figures."""
    import argparse
    import json

    ap = argparse.ArgumentParser(description="The motoneurons' figures, S to FF, as JSON.")
    ap.add_argument("--synaptic-triangle", type=float, nargs="+", metavar="NM",
                    help="cells of sizes 0, 0.1, ..., 0.6 under a synaptic triangle, 10 s each way, at each NM")
    ap.add_argument("--minimum-rate", type=float, nargs="+", metavar="NM",
                    help="cells of sizes 0, 0.3, 0.6: the lowest steady rate under a constant synaptic drive, the "
                         "drive there and the AHP duration, at each NM")
    ap.add_argument("--peak-uS", type=float, default=0.3, help="the synaptic triangle's peak (uS)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a motoneuron parameter replaced in every cell (synaptic triangle and minimum rate)")
    a = ap.parse_args(argv)
    try:
        overrides = parse_settings(a.set)
    except InputError as e:
        ap.error(f"--set: {e}")
    if a.synaptic_triangle:
        sizes = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
        out = [{**synaptic_triangle(sizes, nm, peak_uS=a.peak_uS, **overrides).summary(), "overrides": overrides}
               for nm in a.synaptic_triangle]
    elif a.minimum_rate:
        out = [minimum_rate_facts(x, nm, **overrides) for nm in a.minimum_rate for x in (0.0, 0.3, 0.6)]
    else:
        out = [cell_facts(x) for x in (0.0, 0.25, 0.5, 0.75, 1.0)]
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
