"""A pool run's result: every unit's spikes and force, the pool force, the unit table; HDF5 and a summary figure.

HDF5 layout (schema ``neuromuscle.pool/1``)::

    /                 attrs: schema, pool (JSON definition summary), provenance (JSON), drive, ranks, wall_s
    /t_ms             float64 (n,)
    /pool_force_N     float64 (n,)
    /unit_force_N     float64 (units, n)
    /spikes/unit_<i>  float64 (spike times, ms)
    /units            compound-free table: columns index, size, P0_N, axon_delay_ms, twitch_speed; attr types
    /recordings/<var> float64 (recorded units, n) of each recorded variable (Pool.record), e.g. "mn.v";
                      attrs unit (of measure), units (JSON list of unit indices); absent when nothing was recorded
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import h5py
import numpy as np

from ..reports.outdir import atomic_path, refuse_existing_file
from ..sim.provenance import provenance
from ..sim.results import open_with_schema
from .recording import Recording

SCHEMA = "neuromuscle.pool/1"


@dataclass
class PoolResult:
    """Spikes (ms) and force (N) of every unit, sampled at ``t_ms``; ``units`` the unit table (one dict a unit);
    ``recordings`` the variables recorded by ``Pool.record`` (by name), sampled at ``t_ms``."""

    t_ms: np.ndarray
    unit_force_N: np.ndarray
    spikes_ms: list[np.ndarray]
    units: list[dict[str, Any]]
    drive: str
    ranks: int = 1
    wall_s: float = float("nan")
    provenance: dict[str, Any] = field(default_factory=dict)
    recordings: dict[str, Recording] = field(default_factory=dict)

    @property
    def pool_force_N(self) -> np.ndarray:
        """Sum of the unit forces (N)."""
        return self.unit_force_N.sum(axis=0)

    @property
    def n_units(self) -> int:
        """Number of units."""
        return len(self.units)

    def rates_hz(self, window_ms: float = 500.0) -> np.ndarray:
        """Each unit's discharge rate (Hz) in consecutive windows of window_ms (ms), shape (units, windows)."""
        edges = np.arange(0.0, self.t_ms[-1] + window_ms, window_ms)
        return np.array([np.histogram(s, edges)[0] for s in self.spikes_ms]) / (window_ms / 1000.0)

    @classmethod
    def from_gathered(cls, definition: Any, force: Mapping[int, np.ndarray], spikes: Mapping[int, np.ndarray],
                      record_dt_ms: float, duration_ms: float, sim: Any, *, drive: str, ranks: int,
                      wall_s: float, length: Any, recordings: Mapping[str, Recording] | None = None
                      ) -> PoolResult:
        """Assemble from the per-gid dicts gathered from every rank."""
        specs = definition.units()
        f = np.array([force[u.index] for u in specs])
        t = np.arange(f.shape[1]) * record_dt_ms
        prov = provenance(settings=sim.settings(), duration_ms=duration_ms, record_dt_ms=record_dt_ms,
                          drive=drive, ranks=ranks, pool=definition.name, n_units=definition.n_units,
                          muscle_set=definition.muscle.name, smallest_p0_N=definition.smallest_p0_N,
                          p0_range=definition.p0_range, type_fractions=list(definition.type_fractions),
                          twitch_speed=dict(definition.twitch_speed), muscle_model=definition.muscle_model,
                          muscle_substeps=int(definition.muscle_substeps),
                          motoneuron_channels=definition.motoneuron_channels,
                          pic_substeps=int(getattr(definition, "pic_substeps", 1)),
                          synaptic_noise_uS=float(getattr(definition, "synaptic_noise_uS", 0.0)),
                          synaptic_noise_tau_ms=float(getattr(definition, "synaptic_noise_tau_ms", 5.0)),
                          noise_seed=int(getattr(definition, "noise_seed", 0)),
                          length_mm=(length if isinstance(length, float) else getattr(length, "name", "trace")))
        return cls(t, f, [np.asarray(spikes[u.index], float) for u in specs], [u.row() for u in specs], drive,
                   ranks, wall_s, prov, dict(recordings or {}))

    def save(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write to HDF5 (schema above); refuses to replace an existing file unless overwrite."""
        path = refuse_existing_file(path, overwrite)
        with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
            f.attrs["schema"] = SCHEMA
            f.attrs["provenance"] = json.dumps(self.provenance, default=str)
            f.attrs["drive"] = self.drive
            f.attrs["ranks"] = self.ranks
            f.attrs["wall_s"] = self.wall_s
            f.create_dataset("t_ms", data=self.t_ms)
            f.create_dataset("pool_force_N", data=self.pool_force_N)
            f.create_dataset("unit_force_N", data=self.unit_force_N, compression="gzip")
            g = f.create_group("spikes")
            for i, s in enumerate(self.spikes_ms):
                g.create_dataset(f"unit_{i}", data=s)
            u = f.create_group("units")
            for col in ("index", "size", "P0_N", "axon_delay_ms", "twitch_speed"):
                u.create_dataset(col, data=np.array([r[col] for r in self.units], dtype=float))
            u.attrs["types"] = json.dumps([r["type"] for r in self.units])
            if self.recordings:
                g = f.create_group("recordings")
                for name, rec in self.recordings.items():
                    d = g.create_dataset(name, data=rec.values, compression="gzip")
                    d.attrs["unit"] = rec.unit
                    d.attrs["units"] = json.dumps(rec.units)
        return path

    def save_nwb(self, path: str | Path, overwrite: bool = False, **metadata: Any) -> Path:
        """Write as NWB (``neuromuscle.pool.nwb.write_pool_nwb``; ``metadata`` goes there); refuses to replace an
        existing file unless overwrite."""
        from .nwb import write_pool_nwb

        return write_pool_nwb(self, path, overwrite=overwrite, **metadata)

    def figure(self, path: str | Path, title: str = "") -> Path:
        """Summary figure: raster, discharge rates, unit forces and pool force (PNG)."""
        from ..reports.figures import label_axes, new_figure, save_figure, set_title

        fig, axes = new_figure(4, height_ratios=[2, 1.2, 1.2, 1.2])
        ax = axes[0]
        for i, s in enumerate(self.spikes_ms):
            ax.plot(s / 1000.0, np.full(s.size, i), "|", ms=2, color="k")
        label_axes(ax, x=None, y="unit (recruitment order)")
        set_title(ax, title or f"pool of {self.n_units} units, {self.drive} drive")
        rates = self.rates_hz(250.0)
        tr = (np.arange(rates.shape[1]) + 0.5) * 0.25
        active = rates.sum(axis=1) > 0
        axes[1].plot(tr, rates[active].T, lw=0.6)
        label_axes(axes[1], x=None, y="rate (Hz)")
        step = max(1, self.n_units // 20)
        axes[2].plot(self.t_ms / 1000.0, self.unit_force_N[::step].T, lw=0.6)
        label_axes(axes[2], x=None, y=f"unit force (N), every {step}")
        axes[3].plot(self.t_ms / 1000.0, self.pool_force_N, "k")
        label_axes(axes[3], x="time (s)", y="pool force (N)")
        save_figure(fig, path)
        return Path(path)


def load_pool_result(path: str | Path) -> PoolResult:
    """Read a file written by PoolResult.save."""
    with open_with_schema(Path(path), SCHEMA) as f:
        types = json.loads(f["units"].attrs["types"])
        cols = {c: f["units"][c][()] for c in f["units"]}
        units = [{"index": int(cols["index"][i]), "type": types[i],
                  **{c: float(cols[c][i]) for c in cols if c != "index"}} for i in range(len(types))]
        recordings = {name: Recording(name, str(d.attrs["unit"]), json.loads(d.attrs["units"]), d[()])
                      for name, d in f.get("recordings", {}).items()}
        return PoolResult(f["t_ms"][()], f["unit_force_N"][()],
                          [f["spikes"][f"unit_{i}"][()] for i in range(len(types))], units, str(f.attrs["drive"]),
                          int(f.attrs["ranks"]), float(f.attrs["wall_s"]), json.loads(f.attrs["provenance"]),
                          recordings)
