"""Simulation results in HDF5, with provenance.

Layout (schema ``neuromuscle.simulation/1``)::

    /                 attrs: schema, parameter_set, provenance (JSON: versions, mechanism hash, settings,
                             spike times, seeds), parameters (JSON with units), warnings (JSON)
    /t_ms /force_N /A /atil /length_mm      float64 (n,)
    /ca/<state>_M                           float64 (n,)
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np

from .errors import InputError
from .parameters import parameters_from_json

SCHEMA = "neuromuscle.simulation/1"


def save_result(result: "SimulationResult", path: str | Path, overwrite: bool = False) -> Path:  # noqa: F821
    """Write a SimulationResult; refuses to replace an existing file unless overwrite."""
    path = Path(path)
    if path.exists() and not overwrite:
        raise InputError(f"{path}: exists; refusing to overwrite (pass overwrite=True)")
    tmp = path.with_name(path.name + ".part")
    with h5py.File(tmp, "w") as f:
        f.attrs["schema"] = SCHEMA
        f.attrs["parameter_set"] = result.params.name
        f.attrs["parameters"] = json.dumps(result.params.to_json())
        f.attrs["provenance"] = json.dumps(result.provenance, default=str)
        f.attrs["warnings"] = json.dumps(result.warnings)
        for name, arr in (("t_ms", result.t_ms), ("force_N", result.force_N), ("A", result.A),
                          ("atil", result.atil), ("length_mm", result.length_mm)):
            f.create_dataset(name, data=np.asarray(arr, dtype=float))
        g = f.create_group("ca")
        for k, v in result.ca_M.items():
            g.create_dataset(f"{k}_M", data=np.asarray(v, dtype=float))
    tmp.replace(path)
    return path


def load_result(path: str | Path) -> "SimulationResult":  # noqa: F821
    """Read a file written by save_result (read-only)."""
    from .unit import SimulationResult

    path = Path(path)
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"{path}: not a readable HDF5 file ({exc})") from None
    with f:
        if f.attrs.get("schema") != SCHEMA:
            raise InputError(f"{path}: schema is {f.attrs.get('schema')!r}, expected {SCHEMA!r}")
        params = parameters_from_json(json.loads(f.attrs["parameters"]), str(path))
        prov = json.loads(f.attrs["provenance"])
        return SimulationResult(
            t_ms=f["t_ms"][()], force_N=f["force_N"][()], A=f["A"][()], atil=f["atil"][()],
            ca_M={k[:-2]: f["ca"][k][()] for k in f["ca"]}, length_mm=f["length_mm"][()], params=params,
            settings=prov.get("settings", {}), warnings=json.loads(f.attrs["warnings"]), provenance=prov)
