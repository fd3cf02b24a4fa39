"""Which of a pool's units a decomposition of surface EMG would identify.

    ident = identify(p0_N, active, count=84, motor_units=400)       # the muscle units a grid's decomposition finds
    ident.units, ident.weights                                      # model units identified, and how many copies

A decomposition of high-density surface EMG (blind source separation: Holobar & Zazula 2007; Negro et al. 2016)
identifies a sample of the active units, biased towards those whose action potentials carry the most energy at
the skin (Farina et al. 2008; Del Vecchio et al. 2020); larger and denser grids identify more units and more of the
early-recruited, smaller ones (Caillet et al. 2023).  The model:

- **size**: each unit's surface action potential grows with its number of fibres, which sets its force (the range
  of unit forces is mostly one of innervation numbers: Enoka & Fuglevand 2001), so its amplitude is taken
  proportional to its P0 (the assumption of the pool EMG models of Fuglevand, Winter & Patla 1993 and Keenan et
  al. 2005) and its energy to P0 ** ``size_exponent`` (2: energy goes as amplitude squared; only
  ``depth_attenuation / size_exponent`` matters to which units are chosen);
- **depth**: the units' territories are scattered through the muscle's thickness (Buchthal, Guld & Rosenfalck
  1957), each one's depth uniform between the muscle's surface (0) and its deep face (1), and the surface potential
  falls steeply with depth (Fuglevand, Winter, Patla & Stashuk 1992; Roeleveld et al. 1997; Farina & Merletti
  2001): the energy is
  multiplied by exp(-``depth_attenuation`` depth);
- **activity** (off by default): a source separation estimates each unit's separation filter from its discharges
  over the whole recording (Holobar & Zazula 2007; Negro et al. 2016), so a unit that discharges for longer may
  weigh more in the recording's statistics and be found more reliably.  With ``activity_exponent`` E > 0 a unit's
  weight is its action potential's energy times its time discharging in the trial (s) ** E (1: the energy of all
  its action potentials).  Units recruited near a plateau's top, which discharge on the plateau alone, are then
  found less often than their size says.  On five of the eight recordings of ``networks/pool_vs_recorded.py``
  E = 1 moved the failures rather than removing them (docs/validation/pools_vs_recorded.md), so the default is 0;
- **count**: the decomposition identifies the ``count`` active units of highest weight, ``count`` being the number
  of units the recording itself identified (a count, not which units nor their thresholds);
- **selection** (``selection``): ``"ranked"`` (default) takes those of highest weight; ``"sampled"`` draws them one
  after another without replacement, each with probability proportional to its weight (a decomposition whose
  random initialisations converge to a unit as often as its share of the signal's energy).  On the eight recordings
  of ``networks/pool_vs_recorded.py`` it fits no better than ranking (docs/validation/pools_vs_recorded.md).

A model pool has fewer units than the muscle: each model unit stands for ``motor_units / n`` units of the muscle
(``copies_per_unit``), each copy with its own depth, drawn from ``seed``; the identified sample is ``count`` copies,
and a model unit is identified when one or more of its copies is (``Identification.weights``: how many).  Only
units active in the trial (firing often enough to be found) are candidates.  Deterministic given the random seed.

``depth_attenuation`` (the natural log of the energy ratio of a unit at the muscle's surface to the same unit at its
deep face) is the one parameter not taken from the literature: ``DEPTH_ATTENUATION`` was estimated on one recording,
with ``activity_exponent`` 0 (``estimate_depth_attenuation``; ``python -m neuromuscle.pool.identification
DIR/S1_30_256.json`` on a run of ``networks/pool_vs_recorded.py``); the other recordings are held out.  Units: N
(P0), depth as a fraction of the muscle's thickness (1), times discharging s, energies relative (1).
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..errors import InputError
from ..validate import nonnegative_number, seed_value
from . import discharge_stats as ds

#: Energy of a unit's surface action potential against its P0: amplitude proportional to P0 (innervation number),
#: energy to its square.
SIZE_EXPONENT = 2.0
#: ln(energy at the muscle's surface / energy at its deep face) of one unit (1): a unit at the deep face keeps
#: e^-1.75 = 17 % of the energy (42 % of the amplitude) it would have at the surface.  Estimated on S1_30_256 (the
#: 256-electrode grid, 84 units) with the 40-unit TA pool: the smallest mean KS distance of the thresholds over
#: 20 seeds (0.124; 0.13-0.16 from 1.5 to 4, 0.60 at 0: the estimate is loosely determined above 1.5).
DEPTH_ATTENUATION = 1.75
#: Exponent of a unit's time discharging in the trial in its weight in the recording (1, module docstring; 0: the
#: time plays no part).
ACTIVITY_EXPONENT = 0.0
#: Seed of the units' depths.
DEFAULT_SEED = 0
#: The depth attenuations ``estimate_depth_attenuation`` tries by default (1).
DEPTH_GRID = np.arange(0.0, 12.001, 0.25)
#: How the identified units are chosen among the active ones (module docstring).
SELECTIONS = ("ranked", "sampled")


@dataclass(frozen=True)
class IdentificationModel:
    """The identification model's parameters (module docstring): ``depth_attenuation`` (1, >= 0),
    ``size_exponent`` (1, >= 0), ``activity_exponent`` (1, >= 0; 0: the time discharging plays no part), the
    ``seed`` of the depths (and of the draws) and the ``selection`` (one of ``SELECTIONS``)."""

    depth_attenuation: float = DEPTH_ATTENUATION
    size_exponent: float = SIZE_EXPONENT
    seed: int = DEFAULT_SEED
    activity_exponent: float = ACTIVITY_EXPONENT
    selection: str = "ranked"
    source: str = field(default="weight ~ P0 ** size_exponent * exp(-depth_attenuation * depth) * "
                                "(time discharging) ** activity_exponent; depth_attenuation estimated on S1_30_256 "
                                "with activity_exponent 0", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "depth_attenuation", nonnegative_number("depth_attenuation",
                                                                         self.depth_attenuation))
        object.__setattr__(self, "size_exponent", nonnegative_number("size_exponent", self.size_exponent))
        object.__setattr__(self, "seed", seed_value(self.seed))
        object.__setattr__(self, "activity_exponent", nonnegative_number("activity_exponent",
                                                                         self.activity_exponent))
        if self.selection not in SELECTIONS:
            raise InputError(f"selection must be one of {', '.join(SELECTIONS)}, got {self.selection!r}")

    def provenance(self) -> dict[str, Any]:
        """JSON-ready parameters and seed."""
        return asdict(self)


def copies_per_unit(n_units: int, motor_units: int) -> np.ndarray:
    """How many of the muscle's ``motor_units`` each of ``n_units`` model units stands for (as even as possible,
    summing to ``motor_units``)."""
    if isinstance(n_units, bool) or not isinstance(n_units, (int, np.integer)) or n_units < 1:
        raise InputError(f"n_units must be a positive integer, got {n_units!r}")
    if isinstance(motor_units, bool) or not isinstance(motor_units, (int, np.integer)) or motor_units < n_units:
        raise InputError(f"motor_units must be an integer >= the pool's {n_units} units, got {motor_units!r}")
    edges = np.round(np.linspace(0.0, float(motor_units), int(n_units) + 1)).astype(int)
    return np.diff(edges)


def muap_energy(p0_N: np.ndarray, depth: np.ndarray, *, size_exponent: float = SIZE_EXPONENT,
                depth_attenuation: float = DEPTH_ATTENUATION) -> np.ndarray:
    """Relative energy (1) of surface action potentials of units of P0 ``p0_N`` (N) at ``depth`` (fraction of
    the muscle's thickness, 0 at its surface): P0 ** size_exponent * exp(-depth_attenuation * depth)."""
    p0 = np.asarray(p0_N, float)
    z = np.asarray(depth, float)
    return p0 ** size_exponent * np.exp(-depth_attenuation * z)


@dataclass(frozen=True)
class Identification:
    """Which model units a decomposition identifies: ``copies`` (muscle units each model unit stands for),
    ``identified_copies`` (how many of them are identified), ``count`` (their total, the recording's number of
    units), ``model`` (parameters and seed)."""

    model: IdentificationModel
    count: int
    motor_units: int
    copies: np.ndarray
    identified_copies: np.ndarray

    @property
    def units(self) -> np.ndarray:
        """Indices of the model units with at least one identified copy (ascending)."""
        return np.flatnonzero(self.identified_copies > 0)

    @property
    def weights(self) -> np.ndarray:
        """Identified copies of each of ``units`` (sums to ``count``)."""
        return self.identified_copies[self.units]

    def summary(self) -> dict[str, Any]:
        """JSON-ready: parameters, seed, the count, the identified model units and their weights."""
        return {"model": self.model.provenance(), "count": self.count, "motor_units": self.motor_units,
                "units": [int(u) for u in self.units], "weights": [int(w) for w in self.weights]}


def _discharging(active_s: Sequence[float] | np.ndarray | None, n: int) -> np.ndarray:
    """Each unit's time discharging (s, finite, >= 0; ones when None, every unit alike)."""
    if active_s is None:
        return np.ones(n)
    try:
        a = np.asarray(active_s, dtype=float)
    except (TypeError, ValueError):
        raise InputError("active_s must be a 1-D array of times discharging (s)") from None
    if a.shape != (n,) or not np.all(np.isfinite(a)) or np.any(a < 0.0):
        raise InputError(f"active_s must hold one finite time discharging >= 0 (s) for each of the {n} units, "
                         f"got shape {a.shape}")
    return a


def identify(p0_N: Sequence[float] | np.ndarray, active: Sequence[bool] | np.ndarray, count: int, *,
             motor_units: int, model: IdentificationModel | None = None,
             active_s: Sequence[float] | np.ndarray | None = None) -> Identification:
    """The ``count`` muscle units of highest weight in the recording among the copies of the ``active`` model
    units, or ``count`` drawn in proportion to their weights (``model.selection``; module docstring).
    ``p0_N``: every model unit's P0 (N, > 0); ``active``: which of them fire enough to be found; ``active_s``:
    each unit's time discharging in the trial (s; None: every active unit alike); ``motor_units``: the muscle's
    number of motor units.  InputError when the active units stand for fewer than ``count`` muscle units."""
    m = model or IdentificationModel()
    try:
        p0 = np.asarray(p0_N, dtype=float)
    except (TypeError, ValueError):
        raise InputError("p0_N must be a 1-D array of numbers (N)") from None
    if p0.ndim != 1 or not p0.size or not np.all(np.isfinite(p0)) or np.any(p0 <= 0.0):
        raise InputError(f"p0_N must be a non-empty 1-D array of finite P0 > 0 (N), got {p0_N!r}")
    act = np.asarray(active)
    if act.shape != p0.shape or act.dtype != bool:
        raise InputError(f"active must be a boolean array of the {p0.size} units' shape, got {act.dtype} "
                         f"{act.shape}")
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise InputError(f"count (units the recording identified) must be a positive integer, got {count!r}")
    time_s = _discharging(active_s, p0.size)
    copies = copies_per_unit(p0.size, motor_units)
    owner = np.repeat(np.arange(p0.size), copies)
    rng = np.random.default_rng(m.seed)
    depth = rng.random(owner.size)                                    # every copy's depth, active or not
    candidates = np.flatnonzero(act[owner])
    if count > candidates.size:
        raise InputError(f"the recording identified {count} units but the pool's {int(act.sum())} active units "
                         f"stand for only {candidates.size} of the muscle's {motor_units}")
    energy = muap_energy(p0[owner[candidates]], depth[candidates], size_exponent=m.size_exponent,
                         depth_attenuation=m.depth_attenuation)
    if m.activity_exponent:
        energy = energy * time_s[owner[candidates]] ** m.activity_exponent
    if m.selection == "sampled":
        # drawn without replacement in proportion to the weights: the highest of log(weight) + a Gumbel variable
        with np.errstate(divide="ignore"):
            key = np.log(energy) + rng.gumbel(size=energy.size)
    else:
        key = energy
    chosen = candidates[np.argsort(-key, kind="stable")[:count]]
    identified = np.bincount(owner[chosen], minlength=p0.size)
    return Identification(m, int(count), int(motor_units), copies, identified)


def identified_ks(p0_N: np.ndarray, active: np.ndarray, thresholds_percent: np.ndarray,
                  recorded_thresholds_percent: np.ndarray, *, motor_units: int, model: IdentificationModel,
                  seeds: Sequence[int] = range(20), active_s: np.ndarray | None = None) -> float:
    """Mean over ``seeds`` (of the units' depths) of the Kolmogorov-Smirnov distance between the recruitment
    thresholds of the units a decomposition would identify (``thresholds_percent``, % MVC, one per model unit, NaN
    when inactive; each identified unit weighted by its copies) and the recorded ones, as many units identified as
    were recorded; ``model`` gives every parameter but the random seed, ``active_s`` each unit's time discharging
    (s, ``identify``)."""
    rec = np.asarray(recorded_thresholds_percent, float)
    rec = rec[np.isfinite(rec)]
    thr = np.asarray(thresholds_percent, float)
    if not rec.size or thr.shape != np.shape(p0_N):
        raise InputError("identified_ks needs recorded thresholds and one model threshold per unit")
    d = []
    for s in seeds:
        ident = identify(p0_N, active, rec.size, motor_units=motor_units, model=replace(model, seed=int(s)),
                         active_s=active_s)
        d.append(ds.ks_distance(thr[ident.units], rec, ident.weights))
    return float(np.mean(d))


def estimate_depth_attenuation(p0_N: np.ndarray, active: np.ndarray, thresholds_percent: np.ndarray,
                               recorded_thresholds_percent: np.ndarray, *, motor_units: int,
                               grid: Sequence[float] | None = None, seeds: Sequence[int] = range(20),
                               size_exponent: float = SIZE_EXPONENT, activity_exponent: float = ACTIVITY_EXPONENT,
                               active_s: np.ndarray | None = None) -> tuple[float, np.ndarray]:
    """The ``depth_attenuation`` of ``grid`` (default 0-12 by 0.25) whose identified units' recruitment
    thresholds come closest to the recorded ones (``identified_ks`` over ``seeds``; ``active_s``: each unit's time
    discharging, s).  Returns (the value, the mean distance at every grid value)."""
    values = DEPTH_GRID if grid is None else np.asarray(grid, float)
    cost = np.array([identified_ks(p0_N, active, thresholds_percent, recorded_thresholds_percent,
                                   motor_units=motor_units,
                                   model=IdentificationModel(float(a), size_exponent,
                                                             activity_exponent=activity_exponent),
                                   seeds=seeds, active_s=active_s) for a in values])
    return float(values[int(np.argmin(cost))]), cost


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """``python -m neuromuscle.pool.identification FILE.json``: estimate ``depth_attenuation`` on one file's
    output of ``networks/pool_vs_recorded.py`` (its per-unit table); prints and returns the estimate as JSON."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        raise SystemExit("usage: python -m neuromuscle.pool.identification DIR/<file>.json")
    path = Path(args[0])
    try:
        row = json.loads(path.read_text())
        u = row["units"]
        p0 = np.asarray(u["p0_N"], float)
        thr = np.asarray([np.nan if x is None else x for x in u["threshold_percent_mvc"]], float)
        active = np.asarray(u["active"], bool)
        times = u.get("discharging_s")              # absent from runs written before it was recorded
        active_s = None if times is None else np.asarray([0.0 if x is None else x for x in times], float)
        recorded = np.asarray(row["recorded_thresholds_percent_mvc"], float)
        motor_units = int(row["identification"]["motor_units"])
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a readable JSON file of networks/pool_vs_recorded.py ({exc})") from None
    except (KeyError, TypeError) as exc:
        raise InputError(f"{path}: field {exc} missing or malformed: give a per-file JSON written by "
                         "networks/pool_vs_recorded.py") from None
    best, cost = estimate_depth_attenuation(p0, active, thr, recorded, motor_units=motor_units, active_s=active_s)
    out = {"file": row.get("file", str(path)), "depth_attenuation": best, "mean_ks": float(cost.min()),
           "mean_ks_by_value": {f"{a:g}": round(float(c), 4) for a, c in zip(DEPTH_GRID, cost)}}
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
