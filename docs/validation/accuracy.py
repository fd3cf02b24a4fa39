"""Recompute the accuracy table of docs/validation/accuracy.md: the NEURON mechanisms (fixed step and CVODE) against the
independent SciPy Radau integration of the same equations (neuromuscle/reference.py) and the spec's values.

Run from the repository root:  python docs/validation/accuracy.py [--quick]
Prints Markdown (about 40 s on 2 cores; --quick, one twitch, one train and two dt values, about 10 s).
The conditions and the spec's values are read from tests/sim/test_accuracy.py, so page and test share them.
Units: N and ms; train plateaus in P0 (mean over 1300-1500 ms of a 1 s train starting at 500 ms, at -8 mm).
"""

from __future__ import annotations

import argparse
import ast
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from neuromuscle import Simulator, load_parameters, mechanism_hash, simulate
from neuromuscle.analysis.metrics import Twitch, plateau, twitch_metrics
from neuromuscle.protocols import constant_rate
from neuromuscle.reference import reference_simulate
from neuromuscle.reports.markdown import table

ACCURACY_TEST = Path(__file__).resolve().parents[2] / "tests" / "sim" / "test_accuracy.py"
DT_MS = 0.025
METHODS = ("fixed", "cvode")
DT_SERIES_MS = (0.1, 0.05, 0.025, 0.0125)
TWITCH_MEASURES = ("peak", "time to peak", "half-relaxation")


def spec_values(path: Path = ACCURACY_TEST) -> tuple[dict, dict]:
    """TWITCH_REFERENCE {(set, length mm, stimulus ms): (peak N, ttp ms, half-relaxation ms)} and
    TRAIN_REFERENCE {rate Hz: plateau P0} as the accuracy test asserts them (read, not imported: no pytest)."""
    found = {}
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            if node.targets[0].id in ("TWITCH_REFERENCE", "TRAIN_REFERENCE"):
                found[node.targets[0].id] = ast.literal_eval(node.value)
    if len(found) != 2:
        raise SystemExit(f"{path} no longer defines TWITCH_REFERENCE and TRAIN_REFERENCE: update this script")
    return found["TWITCH_REFERENCE"], found["TRAIN_REFERENCE"]


@dataclass
class Row:
    """One condition: its label, what each value measures, SciPy's values, each method's and the spec's."""

    label: str
    measures: tuple[str, ...]
    scipy: tuple[float, ...]
    neuron: dict[str, tuple[float, ...]]
    spec: tuple[float, ...]

    @property
    def is_twitch(self) -> bool:
        return self.measures == TWITCH_MEASURES


def _twitch(m: Twitch) -> tuple[float, float, float]:
    return m.peak_N, m.time_to_peak_ms, m.half_relaxation_ms


def twitch_row(set_name: str, length_mm: float, stimulus_ms: float, spec: tuple[float, ...]) -> Row:
    """A twitch at length_mm (mm) elicited at stimulus_ms (ms), 280 ms recorded after it."""
    p = load_parameters(set_name)
    end = stimulus_ms + 280.0
    # the spec's twitch at t = 10 ms is the unsettled one: from the published initial state of Kim et al. 2015
    initial = "published" if stimulus_ms < 100.0 else "rest"
    ref = reference_simulate(p, np.array([stimulus_ms]), length_mm, end, initial_state=initial)
    scipy = _twitch(twitch_metrics(ref.t_ms, ref.force_N, stimulus_ms))
    neuron = {}
    for method in METHODS:
        sim = simulate(p, [stimulus_ms], length_mm, end, method=method, dt_ms=DT_MS, record_dt_ms=DT_MS,
                       initial_state=initial)
        neuron[method] = _twitch(twitch_metrics(sim.t_ms, sim.force_N, stimulus_ms))
    name = "" if set_name == "CT09" else f"{set_name} "
    when = "" if stimulus_ms == 500.0 else f", stimulus at t = {stimulus_ms:g} ms"
    return Row(f"{name}twitch {length_mm:g} mm{when}", TWITCH_MEASURES, scipy, neuron, tuple(spec))


def plateau_row(rates_hz: list[int], spec: dict) -> Row:
    """1 s CT09 trains at -8 mm from 500 ms: plateau mean over 1300-1500 ms (P0) for each rate (Hz)."""
    p = load_parameters("CT09")
    scipy, neuron = [], {m: [] for m in METHODS}
    for rate in rates_hz:
        spikes = constant_rate(rate, 1000.0, start_ms=500.0)
        ref = reference_simulate(p, spikes, -8.0, 1500.0, record_dt_ms=0.1)
        scipy.append(plateau(ref.t_ms, ref.force_N, 1300.0, 1500.0)[0] / p["P0"])
        for method in METHODS:
            sim = simulate(p, spikes, -8.0, 1500.0, method=method, dt_ms=DT_MS, record_dt_ms=0.1)
            neuron[method].append(plateau(sim.t_ms, sim.force_N, 1300.0, 1500.0)[0] / p["P0"])
    label = "/".join(str(r) for r in rates_hz) + " Hz plateau (P0)"
    return Row(label, tuple(f"{r} Hz plateau" for r in rates_hz), tuple(scipy),
               {m: tuple(v) for m, v in neuron.items()}, tuple(spec[r] for r in rates_hz))


def dt_convergence(dts_ms: tuple[float, ...]) -> list[tuple[float, float]]:
    """(dt ms, relative error of the fixed-step CT09 twitch peak at -8 mm against SciPy)."""
    p = load_parameters("CT09")
    ref = reference_simulate(p, np.array([500.0]), -8.0, 700.0)
    peak = twitch_metrics(ref.t_ms, ref.force_N, 500.0).peak_N
    out = []
    for dt in dts_ms:
        sim = simulate(p, [500.0], -8.0, 700.0, dt_ms=dt, record_dt_ms=dt)
        out.append((dt, abs(twitch_metrics(sim.t_ms, sim.force_N, 500.0).peak_N / peak - 1.0)))
    return out


def _cells(row: Row, values: tuple[float, ...], with_units: bool = False) -> str:
    if not row.is_twitch:
        return " / ".join(f"{v:.4f}" for v in values)
    peak, ttp, half = values
    return f"{peak:.4f} N / {ttp:.2f} / {half:.2f} ms" if with_units else f"{peak:.4f} / {ttp:.2f} / {half:.2f}"


def _spec_cells(row: Row) -> str:
    return " / ".join(f"{v:g}" for v in row.spec)


def largest_deviation(rows: list[Row], against: str) -> tuple[float, str]:
    """The largest relative deviation of any NEURON value from SciPy's ("scipy") or the spec's ("spec"), and
    where it is."""
    worst = (0.0, "")
    for row in rows:
        base = row.scipy if against == "scipy" else row.spec
        for method, values in row.neuron.items():
            for what, v, b in zip(row.measures, values, base):
                if abs(v / b - 1.0) > worst[0]:
                    how = "CVODE" if method == "cvode" else "fixed step"
                    where = f"{row.label}: {what}" if row.is_twitch else what
                    worst = (abs(v / b - 1.0), f"{where}, {how}")
    return worst


def report(quick: bool) -> str:
    """The Markdown block pasted into docs/validation/accuracy.md."""
    twitches, trains = spec_values()
    cases = list(twitches.items())[:1] if quick else list(twitches.items())
    rows = [twitch_row(name, x, st, spec) for (name, x, st), spec in cases]
    rows.append(plateau_row([20] if quick else sorted(trains), trains))
    body = [(r.label, _cells(r, r.scipy, with_units=r is rows[0]), *(_cells(r, r.neuron[m]) for m in METHODS),
             _spec_cells(r)) for r in rows]
    dev_scipy, where_scipy = largest_deviation(rows, "scipy")
    dev_spec, where_spec = largest_deviation(rows, "spec")
    dts = dt_convergence(DT_SERIES_MS[1:3] if quick else DT_SERIES_MS)
    lines = [f"Mechanism hash {mechanism_hash()[:16]}; fixed step dt = {DT_MS} ms; CVODE atol 1e-3 (in each "
             f"state's atolscale), rtol {Simulator.rtol:g}; twitch cells: peak / time to peak / half-relaxation after "
             "the peak.", ""]
    lines += table(["condition (CT09 unless named)", "SciPy Radau", "NEURON fixed", "NEURON CVODE", "spec"], body)
    lines += ["", f"Largest deviation from SciPy: {100 * dev_scipy:.3f} % ({where_scipy}); "
                  f"from the spec's rounded values: {100 * dev_spec:.3f} % ({where_spec}).", ""]
    lines += table(["dt (ms)", "twitch peak error vs SciPy (%)"], [(f"{dt:g}", f"{100 * e:.3f}") for dt, e in dts])
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one twitch, the 20 Hz train, dt 0.05 and 0.025 ms")
    print(report(parser.parse_args(argv).quick))


if __name__ == "__main__":
    main()
