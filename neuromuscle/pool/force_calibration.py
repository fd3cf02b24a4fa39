"""Calibrating unit forces from recorded discharges and force: P0 by recruitment order, fitted by least squares.

Model: unit i (recruitment rank r_i in [0, 1], lowest threshold 0) has P0_i = scale * range_ratio ** r_i (the
exponential spread of Fuglevand et al. 1993 over the recorded units).  Module 3 is homogeneous in P0 (KSE is
normalised by P0; a0, c0 scale with it: ``pool/units.py``), so a unit's force is exactly P0_i * g_i(t), g_i being
its force per newton of P0 under its recorded discharges; one pool run with every P0 = 1 N gives every g_i
(:func:`unit_force_basis`).  The predicted force is then sum_i P0_i g_i(t - delay).

Fitted (:func:`fit_unit_forces`), on the calibration window only: ``scale`` (force unit of the target per N, in
closed form for a given range and delay), ``range_ratio`` (bounded scalar search on log range in [0, log
max_range]) and a constant ``delay_ms`` (grid search; the delay between the decomposed discharges and the
transducer force beyond what Modules 1-3 produce).  Fixed (chosen by the caller): the muscle parameter set, the
twitch speed (a time scaling of Modules 1-2) and the length.  The NRMSE (eq 17, % of the window's measured
range) is reported on the calibration window and on a held-out window not used by the fit.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from scipy.optimize import minimize_scalar

from ..analysis.metrics import nrmse_percent
from ..errors import InputError
from ..parameters import ParameterSet
from ..sim import Simulator
from ..validate import finite_series, positive_number
from .definition import PoolDefinition
from .motoneuron import TYPES
from .pool import Pool
from .window_fit import window_mask


@dataclass(frozen=True)
class UnitForceFit:
    """Fitted unit forces (recruitment order) and the fit's windows (ms) and errors (NRMSE, %)."""

    scale: float
    range_ratio: float
    delay_ms: float
    p0: np.ndarray
    calibration_ms: tuple[float, float]
    heldout_ms: tuple[float, float]
    nrmse_calibration_percent: float
    nrmse_heldout_percent: float
    predicted: np.ndarray

    def summary(self) -> dict[str, float | list[float]]:
        """The fit as a JSON-ready dict."""
        return {"scale": self.scale, "range_ratio": self.range_ratio, "delay_ms": self.delay_ms,
                "calibration_ms": list(self.calibration_ms), "heldout_ms": list(self.heldout_ms),
                "nrmse_calibration_percent": self.nrmse_calibration_percent,
                "nrmse_heldout_percent": self.nrmse_heldout_percent, "p0": [float(x) for x in self.p0]}


def unit_force_basis(discharges_ms: Sequence[Sequence[float]], duration_ms: float, muscle: ParameterSet, *,
                     speed: float = 1.0, length_mm: float = -8.0, dt_ms: float = 0.025,
                     record_dt_ms: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Each unit's force per newton of P0 above its resting force (1/1, shape (units, samples)) under its
    discharges (ms), with every unit's Modules 1-2 ``speed`` times faster, at ``length_mm`` (mm); returns
    (t_ms, basis)."""
    positive_number("twitch speed", speed)
    d = PoolDefinition(len(discharges_ms), muscle, smallest_p0_N=1.0, p0_range=1.0, type_fractions=(1.0, 0.0, 0.0),
                       twitch_speed={t: speed for t in TYPES}, name="basis")
    with Pool(d, length=length_mm, motoneurons=False) as pool:
        pool.drive_discharges(discharges_ms, duration_ms)
        r = pool.run(duration_ms, Simulator(method="fixed", dt_ms=dt_ms), record_dt_ms=record_dt_ms)
    g = r.unit_force_N
    return r.t_ms, g - g[:, :1]


def exponential_p0(rank: np.ndarray, scale: float, range_ratio: float) -> np.ndarray:
    """P0_i = scale * range_ratio ** rank_i (rank in [0, 1])."""
    return scale * range_ratio ** np.asarray(rank, float)


def _shift(basis: np.ndarray, samples: int) -> np.ndarray:
    """basis delayed by ``samples`` (holding its first value before)."""
    if samples == 0:
        return basis
    return np.concatenate([np.repeat(basis[:, :1], samples, axis=1), basis[:, :-samples]], axis=1)


def fit_unit_forces(t_ms: np.ndarray, basis: np.ndarray, rank: Sequence[float], target: Sequence[float], *,
                    calibration_ms: tuple[float, float], heldout_ms: tuple[float, float],
                    delays_ms: Sequence[float] = (0.0,), max_range: float = 1000.0) -> UnitForceFit:
    """Fit scale, range_ratio and delay (module docstring) to ``target`` (any force unit, sampled at ``t_ms``,
    ms) on ``calibration_ms``; report NRMSE there and on ``heldout_ms`` (ms windows, [start, end))."""
    t = finite_series("t_ms", t_ms)
    y = finite_series("target force", target)
    r = finite_series("recruitment rank", rank)
    g = np.asarray(basis, float)
    if g.shape != (r.size, t.size) or y.size != t.size:
        raise InputError(f"basis {g.shape}, rank {r.size}, target {y.size} and t {t.size} do not match")
    if np.any((r < 0) | (r > 1)):
        raise InputError("recruitment ranks must lie in [0, 1]")
    positive_number("max_range", max_range)
    delays = [float(d) for d in delays_ms]
    if not delays or min(delays) < 0:
        raise InputError(f"delays_ms must be a non-empty list of delays >= 0 ms, got {list(delays_ms)}")
    cal, held = window_mask(t, calibration_ms, "calibration"), window_mask(t, heldout_ms, "held-out")
    step = float(t[1] - t[0])
    best = (np.inf, 0.0, 1.0, 0.0)
    for delay in delays:
        gs = _shift(g, int(round(float(delay) / step)))[:, cal]

        def loss(log_range: float, gs: np.ndarray = gs) -> tuple[float, float]:
            h = (np.exp(log_range) ** r) @ gs
            scale = float(h @ y[cal]) / max(float(h @ h), 1e-300)
            return float(np.sum((scale * h - y[cal]) ** 2)), scale

        res = minimize_scalar(lambda x: loss(x)[0], bounds=(0.0, np.log(max_range)), method="bounded",
                              options={"xatol": 1e-6})
        cost, scale = loss(float(res.x))
        if cost < best[0]:
            best = (cost, scale, float(np.exp(res.x)), float(delay))
    _, scale, ratio, delay = best
    if scale <= 0:
        raise InputError("the calibration found no positive unit force: the target does not follow the discharges")
    p0 = exponential_p0(r, scale, ratio)
    pred = p0 @ _shift(g, int(round(delay / step)))
    return UnitForceFit(scale, ratio, delay, p0, tuple(calibration_ms), tuple(heldout_ms),
                        nrmse_percent(y[cal], pred[cal]), nrmse_percent(y[held], pred[held]), pred)


#: HDF5 schema of a saved calibration (:func:`save_fit`).
FIT_SCHEMA = "neuromuscle.pool_force_fit/1"


def save_fit(path: str | Path, t_ms: np.ndarray, recorded: np.ndarray, fit: UnitForceFit,
             discharges_ms: Sequence[np.ndarray], *, force_unit: str, overwrite: bool = False,
             **provenance_fields: Any) -> Path:
    """Write the recorded and predicted force (``force_unit``) at ``t_ms`` (ms), the discharges (ms, recruitment
    order), the fit (attrs and /p0) and provenance (versions, mechanism hash, ``provenance_fields``) to HDF5;
    refuses to replace an existing file unless overwrite."""
    import h5py

    from ..reports.outdir import atomic_path, refuse_existing_file
    from ..sim.provenance import provenance

    path = refuse_existing_file(path, overwrite)
    with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["schema"] = FIT_SCHEMA
        f.attrs["provenance"] = json.dumps(provenance(**provenance_fields), default=str)
        f.attrs["fit"] = json.dumps({k: v for k, v in fit.summary().items() if k != "p0"})
        f.attrs["force_unit"] = force_unit
        f.create_dataset("t_ms", data=t_ms)
        f.create_dataset("recorded_force", data=recorded)
        f.create_dataset("predicted_force", data=fit.predicted)
        f.create_dataset("p0", data=fit.p0)
        g = f.create_group("discharges_ms")
        for i, d in enumerate(discharges_ms):
            g.create_dataset(f"unit_{i}", data=np.asarray(d, float))
    return path
