"""Pool experiments shared by the example networks: force-frequency by unit type, recruitment thresholds.

    ff = force_frequency(definition, [5, 10, 20, 40])   # plateau force / P0 of one unit of each type, by rate
    ff.pool_force_N(definition)                          # every unit discharging at each rate (N)
    recruitment_drive(result, times_ms, drive)            # the ramp's drive (nA or uS) at each unit's first spike

A unit's force is P0 times its force per newton of P0 (Module 3 is homogeneous in P0: ``force_calibration``), and
the units of one type differ only in P0, so one unit a type and rate gives the whole pool's force-frequency curve
(units with their own extensions excepted).  Units: Hz, ms, N, nA.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..sim.unit import MuscleUnit
from ..protocols.trains import constant_rate
from ..sim import Simulator
from ..validate import positive_number
from .definition import PoolDefinition
from .result import PoolResult


@dataclass(frozen=True)
class ForceFrequency:
    """Plateau force per newton of P0 (``relative``, shape (types, rates)) of one unit of each type."""

    rates_hz: np.ndarray
    types: tuple[str, ...]
    relative: np.ndarray

    def pool_force_N(self, definition: PoolDefinition) -> np.ndarray:
        """The pool's plateau force (N) at each rate with every unit discharging at that rate."""
        rows = {t: self.relative[i] for i, t in enumerate(self.types)}
        return sum(u.muscle["P0"] * rows[u.unit_type] for u in definition.units())

    def save_into(self, path: str | Path, definition: PoolDefinition, group: str = "force_frequency",
                  **provenance_fields: Any) -> None:
        """Add a group (rates_hz, relative, pool_force_N, attrs types and provenance) to an HDF5 file."""
        import h5py

        from ..sim.provenance import provenance

        with h5py.File(path, "a") as f:
            g = f.create_group(group)
            g.attrs["types"] = json.dumps(list(self.types))
            g.attrs["provenance"] = json.dumps(provenance(**provenance_fields), default=str)
            g.create_dataset("rates_hz", data=self.rates_hz)
            g.create_dataset("relative", data=self.relative)
            g.create_dataset("pool_force_N", data=self.pool_force_N(definition))


def force_frequency(definition: PoolDefinition, rates_hz: Sequence[float], *, train_ms: float = 1000.0,
                    plateau_ms: float = 300.0, length_mm: float = -8.0, dt_ms: float = 0.05) -> ForceFrequency:
    """Mean force over the last ``plateau_ms`` (ms) of a ``train_ms`` (ms) train at each rate (Hz), divided by
    P0, for the first unit of each type in ``definition``, isometric at ``length_mm`` (mm); one NEURON run."""
    rates = np.array([positive_number(f"rate {i} (Hz)", r) for i, r in enumerate(rates_hz)])
    if rates.size == 0:
        raise InputError("force_frequency needs at least one rate")
    positive_number("train_ms", train_ms)
    if not 0 < positive_number("plateau_ms", plateau_ms) < train_ms:
        raise InputError(f"plateau_ms must be below train_ms ({train_ms:g} ms), got {plateau_ms:g}")
    first: dict[str, Any] = {}
    for u in definition.units():
        first.setdefault(u.unit_type, u)
    start, rec_dt = 100.0, 1.0
    units, vecs = [], []
    from neuron import h

    try:
        for t, u in first.items():
            for r in rates:
                mu = MuscleUnit(u.muscle, extensions=u.extensions or None, name=f"ff_{t}_{r:g}")
                mu.length.xm = length_mm
                mu.add_spike_times(constant_rate(float(r), train_ms, start_ms=start))
                vecs.append(h.Vector().record(mu[mu.output_slot].obj, mu.ref(mu.output), rec_dt))
                units.append(mu)
        Simulator(method="fixed", dt_ms=dt_ms).run(start + train_ms, units=units)
        lo = int((start + train_ms - plateau_ms) / rec_dt)
        hi = int((start + train_ms) / rec_dt)
        plateau = np.array([np.mean(np.array(v)[lo:hi]) - np.array(v)[0] for v in vecs])
    finally:
        for mu in units:
            mu.destroy()
    p0 = np.repeat([u.muscle["P0"] for u in first.values()], rates.size)
    return ForceFrequency(rates, tuple(first), (plateau / p0).reshape(len(first), rates.size))


def recruitment_drive(result: PoolResult, times_ms: Sequence[float], drive: Sequence[float]) -> np.ndarray:
    """The ramp's drive (its unit: nA for a current, uS for a synaptic conductance; linear between times_ms) at each
    unit's first spike; NaN for silent units."""
    return np.array([np.interp(s[0], times_ms, drive) if s.size else np.nan for s in result.spikes_ms])


def total_force_smallest_p0_N(n_units: int, total_p0_N: float, p0_range: float) -> float:
    """The smallest unit's P0 (N) that makes the exponential spread of ``p0_range`` over ``n_units`` sum to
    ``total_p0_N`` (N)."""
    from .units import p0_spread_N

    return positive_number("total P0 (N)", total_p0_N) / float(p0_spread_N(n_units, 1.0, p0_range).sum())


def summary_figure(path: str | Path, ramp: PoolResult, ramp_times_ms: Sequence[float], ramp_drive: Sequence[float],
                   ff: ForceFrequency, definition: PoolDefinition, title: str,
                   length_run: PoolResult | None = None, drive_label: str = "synaptic drive (uS)") -> Path:
    """Ramp (drive and pool force), recruitment drive by unit, force-frequency (per type, relative; pool, N), and
    the pool force under the length input (if given).  ``drive_label`` names the drive and its unit."""
    from ..reports.figures import label_axes, legend, new_figure, save_figure, set_title

    fig, axes = new_figure(4 if length_run is not None else 3)
    t = ramp.t_ms / 1000.0
    axes[0].plot(t, ramp.pool_force_N, "k", label="pool force (N)")
    ax2 = axes[0].twinx()
    ax2.plot(np.asarray(ramp_times_ms) / 1000.0, ramp_drive, color="C1", lw=0.8)
    ax2.set_ylabel(drive_label, color="C1", fontsize=8)
    label_axes(axes[0], x="time (s)", y="pool force (N)")
    set_title(axes[0], title)
    thr = recruitment_drive(ramp, ramp_times_ms, ramp_drive)
    for k, typ in enumerate(("S", "FR", "FF")):
        idx = [i for i, u in enumerate(ramp.units) if u["type"] == typ]
        axes[1].plot(idx, thr[idx], ".", ms=3, color=f"C{k}", label=typ)
    label_axes(axes[1], x=f"unit (recruitment order; {np.isfinite(thr).sum()} of {thr.size} recruited)",
               y=f"recruitment {drive_label}")
    legend(axes[1], small=True)
    for k, typ in enumerate(ff.types):
        axes[2].plot(ff.rates_hz, ff.relative[k], "o-", ms=3, label=f"{typ} unit (force / P0)")
    pool = ff.pool_force_N(definition)
    axes[2].plot(ff.rates_hz, pool / pool.max(), "k--", lw=1, label=f"pool / {pool.max():.3g} N")
    label_axes(axes[2], x="discharge rate (Hz)", y="plateau force (fraction)")
    legend(axes[2], small=True)
    if length_run is not None:
        axes[3].plot(length_run.t_ms / 1000.0, length_run.pool_force_N, "k")
        label_axes(axes[3], x="time (s)", y="pool force, random length (N)")
    save_figure(fig, path)
    return Path(path)
