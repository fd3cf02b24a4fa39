"""Recorded discharges and force from the files the ``openhdemg`` package opens (Valli et al. 2024, J Electromyogr
Kinesiol 74:102850): its own JSON (``.json``, gzip-compressed), OTBiolab+ exports (``otb``) and DEMUSE results
(``demuse``), read through openhdemg itself.

    rec = load_openhdemg("trial.json")                       # REF_SIGNAL taken as % MVC (openhdemg's convention)
    rec = load_openhdemg("trial.mat", kind="otb", level_percent_mvc=30.0)   # raw force: plateau set to 30 % MVC

Fields used (openhdemg's ``emgfile`` dict): ``MUPULSES`` (one array of discharge sample indices per unit, counted
from 0), ``FSAMP`` (Hz) and the first column of ``REF_SIGNAL`` (the force, one sample per EMG sample).  Without
``level_percent_mvc`` the force must already be in % MVC (openhdemg's convention after its MVC conversion); with it,
the force is normalised as for the Caillet files (baseline 0, plateau at the level).  openhdemg is an optional
dependency (``pip install 'neuromuscle[openhdemg]'``), imported only inside :func:`load_openhdemg`, by its
file-reading module ``openhdemg.library.openfiles``; that import loads the whole ``openhdemg.library`` (tkinter and
matplotlib among it) but opens no window and needs no display.  Times in ms.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..validate import positive_number
from .discharges import RecordedDischarges, normalise_force, numeric_field, pulse_trains

#: File kinds openhdemg opens, and the openhdemg function that reads each.
KINDS = {"json": "emg_from_json", "otb": "emg_from_otb", "demuse": "emg_from_demuse"}
#: Largest force (% MVC) accepted as already normalised when no level is given.
MAX_PERCENT_MVC = 150.0


def _open(path: Path, kind: str) -> dict[str, Any]:
    try:
        from openhdemg.library import openfiles
    except ImportError as exc:
        raise InputError(f"{path}: reading openhdemg files needs the openhdemg package (pip install "
                         f"'neuromuscle[openhdemg]'): {exc}") from None
    try:
        emgfile = getattr(openfiles, KINDS[kind])(str(path))
    except Exception as exc:  # openhdemg raises whatever its parsers raise (gzip, JSON, pandas, scipy, KeyError)
        raise InputError(f"{path}: not a readable openhdemg {kind} file ({type(exc).__name__}: {exc})") from None
    if not isinstance(emgfile, dict):
        raise InputError(f"{path}: openhdemg returned {type(emgfile).__name__}, not an emgfile dict")
    return emgfile


def _get(emgfile: dict[str, Any], path: Path, name: str) -> Any:
    if name not in emgfile or emgfile[name] is None:
        raise InputError(f"{path}: field {name!r} is missing (found {sorted(emgfile)})")
    return emgfile[name]


def _force(path: Path, ref: Any) -> np.ndarray:
    values = getattr(ref, "to_numpy", lambda: np.asarray(ref))()
    values = np.asarray(values)
    if values.ndim != 2 or values.shape[1] < 1 or values.shape[0] == 0:
        raise InputError(f"{path}: field 'REF_SIGNAL' must be a table with the force in its first column, got "
                         f"shape {values.shape}")
    return numeric_field(path, "REF_SIGNAL", values[:, 0])


def load_openhdemg(path: str | Path, kind: str | None = None, level_percent_mvc: float | None = None
                   ) -> RecordedDischarges:
    """Read one file openhdemg opens (``kind`` json, otb or demuse; by default json for ``.json``, else refused)
    as discharges (ms) and force (% MVC, module docstring); every problem raises InputError naming the file and
    the field (and the unit)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    kind = kind or ("json" if p.suffix.lower() == ".json" else None)
    if kind not in KINDS:
        raise InputError(f"{p}: openhdemg file kind must be one of {', '.join(KINDS)} (json is assumed only for "
                         f".json files), got {kind!r}")
    emgfile = _open(p, kind)
    fs = numeric_field(p, "FSAMP", np.asarray(_get(emgfile, p, "FSAMP")))
    if fs.size != 1 or fs[0] <= 0:
        raise InputError(f"{p}: field 'FSAMP' must be one positive rate (Hz), got {fs[:3]}")
    raw = _force(p, _get(emgfile, p, "REF_SIGNAL"))
    pulses = _get(emgfile, p, "MUPULSES")
    if not isinstance(pulses, (list, tuple)):
        raise InputError(f"{p}: field 'MUPULSES' must be a list of discharge arrays, got {type(pulses).__name__}")
    trains = pulse_trains(p, "MUPULSES", pulses, float(fs[0]), raw.size, 0)
    if level_percent_mvc is None:
        top = float(np.percentile(raw, 99.0))
        if not 0.0 < top <= MAX_PERCENT_MVC:
            raise InputError(f"{p}: field 'REF_SIGNAL' is not in % MVC (99th percentile {top:g}); give the "
                             "trial's level (% MVC) to normalise it")
        level, force = float(np.median(raw[raw >= 0.8 * top])), raw
    else:
        level = positive_number("level_percent_mvc", level_percent_mvc)
        first = int(round(min(d[0] for d in trains) * fs[0] / 1000.0))
        force = normalise_force(p, raw, first, level)
    return RecordedDischarges(p, float(fs[0]), level, trains, force)
