"""The unit-force basis of recorded discharges: each unit's force per newton of P0 under its own discharge times.

Module 3 is homogeneous in P0 (KSE is normalised by P0; a0, c0 scale with it: ``pool/units.py``), so a unit's
force is exactly P0_i * g_i(t), g_i being its force per newton of P0 under its recorded discharges; one pool run with
every P0 = 1 N gives every g_i (:func:`unit_force_basis`), and any choice of unit forces is then a weighted sum of the
basis, with no further simulation.  :mod:`.human_units` fits those weights (and the twitch speed) to a recorded
force; :mod:`.follow_force` uses the same property for pools driven by motoneurons.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..parameters import ParameterSet
from ..sim import Simulator
from ..validate import positive_number
from .definition import PoolDefinition
from .motoneuron import TYPES
from .pool import Pool


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
