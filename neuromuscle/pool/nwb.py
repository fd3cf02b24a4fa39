"""A pool's result as NWB (Neurodata Without Borders, through pynwb), the format the field shares spikes and signals in.

Layout of the file (times in s, as NWB requires; forces in N)::

    units                      Units table, one row a motor unit in recruitment order: spike_times (s) and the
                               columns unit_index, unit_type (S, FR, FF), size, P0_N, axon_delay_ms, twitch_speed
    acquisition/pool_force     TimeSeries (samples,) N: the sum of the unit forces
    acquisition/unit_force     TimeSeries (samples, units) N: column k is row k of the Units table
    acquisition/<variable>     TimeSeries (samples, recorded units) of each variable recorded by Pool.record
                               ("mn.v", "act.A", ...); its description names the variable and the unit indices
    notes                      JSON: schema, drive, ranks, wall_s, record_dt_ms and the provenance (the pool
                               definition, parameters, seeds, versions, mechanism hash)

Every TimeSeries starts at 0 s at the rate 1000 / record_dt_ms Hz.  ``read_pool_nwb`` gives back the PoolResult.
"""

from __future__ import annotations

import datetime as _dt
import json
import uuid
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..reports.outdir import atomic_path, refuse_existing_file
from .recording import Recording
from .result import SCHEMA, PoolResult

#: The Units table's columns besides spike_times: (column, the unit row's key, description).
UNIT_COLUMNS = (("unit_index", "index", "the unit's index (gid) in recruitment order"),
                ("unit_type", "type", "motor-unit type: S (slow), FR (fast fatigue-resistant), FF (fast fatigable)"),
                ("size", "size", "the motoneuron's size index (0: smallest S cell, 1: largest FF cell)"),
                ("P0_N", "P0_N", "the muscle unit's maximal isometric force P0 (N)"),
                ("axon_delay_ms", "axon_delay_ms", "axon conduction delay from the soma to the muscle (ms)"),
                ("twitch_speed", "twitch_speed", "twitch time scaling of the muscle unit (1: the base set's)"))
FORCE_SERIES = ("pool_force", "unit_force")
#: The species whose muscle a built-in parameter set describes (the NWB subject's species).
SPECIES_OF_SETS = {"CT09": "Felis catus", "CT95": "Felis catus"}


def _start_time(result: PoolResult) -> _dt.datetime:
    """The run's creation time (provenance created_utc), timezone-aware; now if absent."""
    text = result.provenance.get("created_utc")
    try:
        when = _dt.datetime.fromisoformat(str(text))
    except ValueError:
        return _dt.datetime.now(_dt.timezone.utc)
    return when if when.tzinfo is not None else when.replace(tzinfo=_dt.timezone.utc)


def write_pool_nwb(result: PoolResult, path: str | Path, overwrite: bool = False, *,
                   session_description: str | None = None, institution: str | None = None,
                   experimenter: str | None = None, species: str | None = None) -> Path:
    """Write ``result`` to ``path`` as NWB (module docstring); refuses to replace an existing file unless
    overwrite.  ``session_description``: default a sentence naming the pool, its units and drive.  The NWB
    subject is the simulated pool: no animal, sex "U", age "P0D/" (unspecified), ``species`` the one whose muscle
    the parameter set describes (default: SPECIES_OF_SETS of the result's muscle set, else none).  Spike-time
    resolution: the fixed step; under CVODE, which interpolates the threshold crossing, the spacing of doubles (s)
    at the run's end."""
    from hdmf.backends.hdf5 import H5DataIO
    from pynwb import NWBHDF5IO, NWBFile, TimeSeries
    from pynwb.file import Subject
    from pynwb.misc import Units

    path = refuse_existing_file(path, overwrite)
    dt_ms = float(result.t_ms[1] - result.t_ms[0]) if result.t_ms.size > 1 else \
        float(result.provenance.get("record_dt_ms", 1.0))
    rate = 1000.0 / dt_ms
    name = result.provenance.get("pool", "pool")
    meta = {"schema": SCHEMA, "drive": result.drive, "ranks": result.ranks, "wall_s": result.wall_s,
            "record_dt_ms": dt_ms, "provenance": result.provenance}
    nwb = NWBFile(session_description=session_description or
                  f"simulated motor-unit pool {name!r}: {result.n_units} units, {result.drive} drive",
                  identifier=str(uuid.uuid4()), session_start_time=_start_time(result),
                  experiment_description="motoneurons driving Kim-Sandercock-Heckman muscle units in NEURON "
                                         "(neuromuscle)",
                  notes=json.dumps(meta, default=str), institution=institution,
                  experimenter=[experimenter] if experimenter else None, keywords=["motor unit", "motoneuron",
                                                                                   "muscle force", "simulation"])
    muscle_set = str(result.provenance.get("muscle_set", ""))
    nwb.subject = Subject(subject_id=str(name).replace("/", "_"), sex="U", age="P0D/",
                          species=species or SPECIES_OF_SETS.get(muscle_set),
                          description=f"a simulated motor-unit pool (no animal); muscle parameter set "
                                      f"{muscle_set or 'unknown'}")
    settings = result.provenance.get("settings", {})
    if settings.get("method") == "fixed" and settings.get("dt_ms"):
        resolution = float(settings["dt_ms"]) / 1000.0
    else:  # CVODE interpolates the threshold crossing: spike times are any double
        resolution = float(np.spacing(max(float(result.t_ms[-1]) / 1000.0, 1.0)))
    nwb.units = Units(name="units", description="motor units in recruitment order: their motoneurons' spikes",
                      resolution=resolution)
    for column, _, description in UNIT_COLUMNS:
        nwb.add_unit_column(name=column, description=description)
    for row, spikes in zip(result.units, result.spikes_ms):
        nwb.add_unit(spike_times=np.asarray(spikes, float) / 1000.0,
                     **{column: row[key] for column, key, _ in UNIT_COLUMNS})
    nwb.add_acquisition(TimeSeries(name="pool_force", data=result.pool_force_N, unit="N", rate=rate,
                                   starting_time=0.0, description="pool force: the sum of the unit forces"))
    nwb.add_acquisition(TimeSeries(name="unit_force", data=H5DataIO(result.unit_force_N.T, compression="gzip"),
                                   unit="N", rate=rate, starting_time=0.0,
                                   description="force of each muscle unit; column k is row k of the Units table"))
    for variable, rec in result.recordings.items():
        if variable in FORCE_SERIES:
            raise InputError(f"recorded variable {variable!r} clashes with the force series of the NWB file")
        nwb.add_acquisition(TimeSeries(name=variable, data=H5DataIO(rec.values.T, compression="gzip"),
                                       unit=rec.unit, rate=rate, starting_time=0.0,
                                       description=json.dumps({"variable": variable, "units": rec.units}),
                                       comments=f"{variable} of units {rec.units} (column k: unit units[k])"))
    with atomic_path(path) as tmp, warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*does not end in '.nwb'")  # the temporary name
        with NWBHDF5IO(str(tmp), "w") as io:
            io.write(nwb)
    return path


def read_pool_nwb(path: str | Path) -> PoolResult:
    """The PoolResult in a file written by ``write_pool_nwb`` (spike times back in ms); InputError if it is
    not one."""
    from pynwb import NWBHDF5IO

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    with NWBHDF5IO(str(p), "r") as io:
        nwb = io.read()
        try:
            meta = json.loads(nwb.notes or "")
        except json.JSONDecodeError:
            meta = {}
        if meta.get("schema") != SCHEMA:
            raise InputError(f"{p}: not a pool written by neuromuscle (notes lack schema {SCHEMA!r})")
        table = nwb.units
        units: list[dict[str, Any]] = []
        spikes = []
        for i in range(len(table)):
            row = {key: table[column][i] for column, key, _ in UNIT_COLUMNS}
            row["index"], row["type"] = int(row["index"]), str(row["type"])
            units.append({k: (v if k in ("index", "type") else float(v)) for k, v in row.items()})
            spikes.append(np.asarray(table["spike_times"][i], float) * 1000.0)
        acq = nwb.acquisition
        force = np.asarray(acq["unit_force"].data[()], float).T
        recordings = {}
        for name, series in acq.items():
            if name in FORCE_SERIES:
                continue
            about = json.loads(series.description)
            recordings[name] = Recording(about["variable"], series.unit, [int(u) for u in about["units"]],
                                         np.asarray(series.data[()], float).T)
    t = np.arange(force.shape[1]) * float(meta["record_dt_ms"])
    return PoolResult(t, force, spikes, units, meta["drive"], int(meta["ranks"]), float(meta["wall_s"]),
                      meta["provenance"], recordings)
