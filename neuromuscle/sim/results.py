"""Simulation results: named traces with units and provenance, in memory and in HDF5.

HDF5 layout (schema ``neuromuscle.simulation/2``)::

    /                 attrs: schema, parameter_set, provenance (JSON: versions, mechanism hash, settings,
                             spike times, seeds), parameters (JSON with units), warnings (JSON), output
    /t_ms                                   float64 (n,)
    /traces/<slot.variable>                 float64 (n,), attr unit
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

import h5py
import numpy as np

from ..errors import InputError
from ..parameters import ParameterSet, parameters_from_json
from ..reports.outdir import atomic_path, refuse_existing_file

SCHEMA = "neuromuscle.simulation/2"
#: Module 1's calcium states (M).
CA_STATES = ("CaSR", "CaSRCS", "CaSP", "CaSPB", "CaSPT")


def find_variable(names: Iterable[str], slot: str, var: str) -> str | None:
    """Of the recordable or recorded ``names`` ("slot.variable"), ``slot.var`` if present, else the first other
    slot's ``var`` outside the length input (a fused unit keeps Modules 1-3 in one slot), else None."""
    names = list(names)
    if f"{slot}.{var}" in names:
        return f"{slot}.{var}"
    return next((n for n in names if n.split(".", 1)[-1] == var and not n.startswith("length.")), None)


@dataclass
class SimulationResult:
    """Time course of one simulated unit.  ``traces`` maps ``"slot.variable"`` to samples at ``t_ms`` (ms),
    ``units`` their units; ``output`` names the contraction output ("force.F" in N, or "force.M" in N m)."""

    t_ms: np.ndarray
    traces: Mapping[str, np.ndarray]
    units: Mapping[str, str]
    output: str
    params: ParameterSet
    settings: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    provenance: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.traces[name]
        except KeyError:
            raise InputError(f"no trace {name!r}; recorded: {', '.join(self.traces)}") from None

    @property
    def force_N(self) -> np.ndarray:
        """The contraction output (N for Module 3; N m for Hatze's MTC, see ``output``)."""
        return self[self.output]

    def variable(self, name: str, slot: str = "act") -> np.ndarray:
        """The trace of variable ``name`` in ``slot``, else in whichever slot records it (the fused KimUnit keeps
        Modules 1-3 in one slot, "muscle")."""
        return self[find_variable(self.traces, slot, name) or f"{slot}.{name}"]

    @property
    def A(self) -> np.ndarray:
        """Activation A (1) of the excitation model."""
        return self.variable("A")

    @property
    def atil(self) -> np.ndarray:
        """Module 2's Atil (1); only Kim's excitation has it."""
        return self.variable("atil")

    @property
    def length_mm(self) -> np.ndarray:
        """Muscle length Xm (mm)."""
        return self["length.xm"]

    @property
    def ca_M(self) -> dict[str, np.ndarray]:
        """Module 1's recorded calcium states (M) by state name."""
        ca = {k[3:]: v for k, v in self.traces.items() if k.startswith("ca.")}
        if not ca:  # the fused KimUnit: Module 1's states in its own slot
            ca = {k.split(".", 1)[1]: v for k, v in self.traces.items() if k.split(".", 1)[-1] in CA_STATES}
        return ca

    def save(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write to HDF5 with provenance; refuses to replace an existing file unless overwrite."""
        return save_result(self, path, overwrite=overwrite)


def save_result(result: SimulationResult, path: str | Path, overwrite: bool = False) -> Path:
    """Write a SimulationResult (schema above); refuses to replace an existing file unless overwrite."""
    path = refuse_existing_file(path, overwrite)
    with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["schema"] = SCHEMA
        f.attrs["parameter_set"] = result.params.name
        f.attrs["parameters"] = json.dumps(result.params.to_json())
        f.attrs["provenance"] = json.dumps(result.provenance, default=str)
        f.attrs["warnings"] = json.dumps(result.warnings)
        f.attrs["output"] = result.output
        f.create_dataset("t_ms", data=np.asarray(result.t_ms, dtype=float))
        g = f.create_group("traces")
        for k, v in result.traces.items():
            d = g.create_dataset(k, data=np.asarray(v, dtype=float))
            d.attrs["unit"] = result.units.get(k, "")
    return path


def open_with_schema(path: Path, schema: str) -> h5py.File:
    """``path`` opened read-only; InputError unless it is an HDF5 file whose ``schema`` attribute is ``schema``."""
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"{path}: not a readable HDF5 file ({exc})") from None
    if f.attrs.get("schema") != schema:
        found = f.attrs.get("schema")
        f.close()
        raise InputError(f"{path}: schema is {found!r}, expected {schema!r}")
    return f


def load_result(path: str | Path) -> SimulationResult:
    """Read a file written by save_result (read-only)."""
    path = Path(path)
    with open_with_schema(path, SCHEMA) as f:
        params = parameters_from_json(json.loads(f.attrs["parameters"]), str(path))
        prov = json.loads(f.attrs["provenance"])
        traces = {k: f["traces"][k][()] for k in f["traces"]}
        units = {k: str(f["traces"][k].attrs.get("unit", "")) for k in f["traces"]}
        return SimulationResult(t_ms=f["t_ms"][()], traces=traces, units=units, output=str(f.attrs["output"]),
                                params=params, settings=prov.get("settings", {}),
                                warnings=json.loads(f.attrs["warnings"]), provenance=prov)
