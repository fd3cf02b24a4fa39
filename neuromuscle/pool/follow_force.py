"""A motoneuron pool whose force follows a recorded force: the muscle's pool, its P0 spread and maximal drive from
one slow calibration ramp, and the common synaptic drive that gives the recorded force (in % MVC).

    muscle = HUMAN_MUSCLES["TA"]                        # composition, published recruitment thresholds
    cal = calibrate(muscle.definition(100))             # one slow ramp of the common drive, up and down
    spread = cal.fit_p0_spread(muscle)                  # P0 range and MVC: thresholds as published for the muscle
    times, drive = cal.drive_for(spread, t_ms, force_percent_mvc, descent_ms=...)   # force -> drive (inverted)
    result = run_drive(spread.definition(cal), times, drive, duration_ms)
    times, drive = cal.correct_drive(spread, times, drive, result, t_ms, force_percent_mvc)   # one more pass
    best = follow(cal, spread, t_ms, force_percent_mvc, run, corrections=3, descent_ms=...)    # all of it

Calibration: the pool with every unit's P0 = 1 N runs one slow triangle of the common synaptic drive (0 ->
``top_uS`` -> 0); Module 3 is homogeneous in P0 (``force_calibration``), so each unit's force per newton along the
ramp gives the pool force for any P0 spread.  P0 spread: P0_i = 1 + (range_ratio - 1) rank_i ** exponent (N; rank
0..1): most units alike and the last ones much larger, as in the P0 distributions of human TA and GM (Caillet et
al. 2022); exponent 1 is a linear spread.  MVC: the pool force at the drive that makes the last unit's recruitment
fall at the muscle's upper limit of recruitment (``HumanMuscle.recruitment_limit_percent``, % MVC).  Range ratio
and exponent are those whose recruitment thresholds (force at each unit's recruitment on the ramp, % MVC) come
closest (least squares) to the muscle's published distribution: fitted to the literature, not to the recording
they are compared with.
Drive for a force: the ramp's force against drive, rising branch up to ``descent_ms`` and falling branch after
it (the PIC's hysteresis), inverted; ``correct_drive`` adds the remaining force error divided by the local slope
(one step of iterative learning control); ``follow`` runs the inverted drive and its corrections, each from the
best drive so far, halving the step after one that did not bring the force closer (a pool whose units adapt or
keep firing in their hysteresis band is not the calibration's static map, and a full step can overshoot).
Units: ms, uS (the drive: each motoneuron's total synaptic conductance), N (forces per newton of P0), % MVC.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Sequence

import numpy as np
from scipy.ndimage import uniform_filter

from ..analysis.metrics import nrmse_percent
from ..errors import InputError
from ..parameters import load_parameters
from ..sim import Simulator
from ..validate import finite_number, positive_number
from .definition import PoolDefinition
from .identification import IdentificationModel, copies_per_unit, identified_ks
from .motoneuron import HUMAN_NEUROMODULATION
from .pool import Pool
from .result import PoolResult


#: Half the drive interval (fraction of the MVC drive) over which ``correct_drive`` measures a branch's slope.
SLOPE_HALF_WIDTH = 0.025


def _ta_thresholds(rank: np.ndarray) -> np.ndarray:
    return 0.5052 * (58.1 * rank + 120.0 ** (rank ** 1.83))


def _gm_thresholds(rank: np.ndarray) -> np.ndarray:
    return 0.6562 * (46.7 * rank + 90.0 ** (rank ** 1.79))


@dataclass(frozen=True)
class HumanMuscle:
    """A human muscle's motor-unit pool: unit types, published recruitment thresholds (% MVC against the rank in
    the pool, 0..1), upper limit of recruitment (% MVC), number of motor units, motor axon length (mm), and how the
    motoneuron sizes spread over the ranks (``PoolDefinition.size_spacing``)."""

    name: str
    type_fractions: tuple[float, float, float]
    thresholds: Callable[[np.ndarray], np.ndarray]
    recruitment_limit_percent: float
    motor_units: int
    axon_length_mm: float
    source: str
    size_spacing: float = 20.0
    motoneuron_scales: tuple[tuple[str, float], ...] = ()

    def definition(self, n_units: int, *, neuromodulation: float = HUMAN_NEUROMODULATION,
                   muscle_set: str = "CT09", **kwargs: object) -> PoolDefinition:
        """The pool of ``n_units`` model units (each P0 = 1 N until a spread is fitted), fused muscle every 8
        membrane steps (the fast path)."""
        opts: dict = dict(type_fractions=self.type_fractions, axon_length_mm=self.axon_length_mm,
                          neuromodulation=neuromodulation, muscle_model="fused", muscle_substeps=8,
                          smallest_p0_N=1.0, p0_range=1.0, size_spacing=self.size_spacing,
                          motoneuron_scales=dict(self.motoneuron_scales), name=self.name)
        opts.update(kwargs)
        return PoolDefinition(n_units, load_parameters(muscle_set), **opts)


#: Human muscles of the recorded discharges.  Thresholds: the distributions Caillet, Phillips, Farina & Modenese
#: 2022 (PLoS Comput Biol 18:e1010556) fitted to published recruitment thresholds of human tibialis anterior and
#: gastrocnemius medialis units (both reach 90 % MVC, the upper limit of recruitment of these muscles); their pool
#: of 400 units.  Fibre types: 73 % type I in
#: TA, about 50 % in GM (Johnson, Polgar, Weightman & Appleton 1973), the fast ones split evenly between FR and
#: FF.  Motor axons of the leg about 0.9 m.  Sizes spread so that the recruitment drive grows about linearly
#: with rank (``size_spacing`` 20, the ratio of the last to the first unit's recruitment drive): with the fitted
#: P0 spread the pool's thresholds then follow the published ones within 2 % MVC rms (with sizes uniform in rank
#: the first third of the units would all be recruited below 1 % MVC).  GM motoneurons: AHP calcium decaying half
#: as fast (AHP 1.6-1.9 times as long: 300 ms S, 90 ms FF), which brings the GM pool's rates to the 7-12 Hz of the
#: recorded GM units at 30 % MVC (TA units fire at 11-21 Hz there); set on the one GM recording compared, so the
#: GM rates are a fit, not a test.
HUMAN_MUSCLES: dict[str, HumanMuscle] = {
    "TA": HumanMuscle("TA", (0.73, 0.135, 0.135), _ta_thresholds, 90.0, 400, 900.0,
                      "Caillet et al. 2022 (thresholds); Johnson et al. 1973 (types)"),
    "GM": HumanMuscle("GM", (0.5, 0.25, 0.25), _gm_thresholds, 90.0, 400, 950.0,
                      "Caillet et al. 2022 (thresholds); Johnson et al. 1973 (types)",
                      motoneuron_scales=(("ca_decay_ms", 2.0),)),
}


def p0_spread(rank: np.ndarray, range_ratio: float, exponent: float) -> np.ndarray:
    """P0 (N) at each rank (0..1): 1 + (range_ratio - 1) rank ** exponent."""
    return 1.0 + (range_ratio - 1.0) * np.asarray(rank, float) ** exponent


@dataclass(frozen=True)
class P0Spread:
    """A fitted P0 spread (``p0_spread``: ``range_ratio`` largest / smallest, ``exponent``), the maximal drive
    ``mvc_drive_uS`` and the pool force there ``mvc_force`` (N, smallest P0 1 N), the units' thresholds (% MVC)
    on the calibration ramp and the rms distance (% MVC) to the published ones."""

    range_ratio: float
    exponent: float
    mvc_drive_uS: float
    mvc_force: float
    thresholds_percent: np.ndarray
    rms_error_percent: float

    def definition(self, cal: Calibration) -> PoolDefinition:
        """The calibrated pool with this spread of P0 (N)."""
        return replace(cal.definition, p0_N=tuple(float(x) for x in self.p0_N(cal.rank)))

    def p0_N(self, rank: np.ndarray) -> np.ndarray:
        """P0 (N) of the units at ``rank``."""
        return p0_spread(rank, self.range_ratio, self.exponent)

    def percent_mvc(self, force: np.ndarray) -> np.ndarray:
        """A force of the pool with this spread (N above rest) in % MVC."""
        return 100.0 * np.asarray(force, float) / self.mvc_force


@dataclass(frozen=True)
class Calibration:
    """One slow ramp of the common drive: ``drive_uS`` at ``t_ms``, each unit's force per newton above rest
    (``basis``, units x samples), its recruitment drive (``onset_uS``, NaN if never recruited), the ramp's top
    time ``top_ms``."""

    definition: PoolDefinition
    t_ms: np.ndarray
    drive_uS: np.ndarray
    basis: np.ndarray
    onset_uS: np.ndarray
    top_ms: float

    @property
    def rank(self) -> np.ndarray:
        """Each model unit's rank in the pool, 0 (first recruited) to 1."""
        n = self.basis.shape[0]
        return np.arange(n) / max(n - 1, 1)

    def pool_force(self, p0_N: np.ndarray) -> np.ndarray:
        """The ramp's pool force (N above rest) with the units' P0 ``p0_N`` (N)."""
        return np.asarray(p0_N, float) @ self.basis

    def branches(self, p0_N: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """((drive, force) rising, (drive, force) falling): the force made monotone in the drive on each branch
        (running maximum), for inversion."""
        f = self.pool_force(p0_N)
        up = self.t_ms <= self.top_ms
        gu, fu = self.drive_uS[up], np.maximum.accumulate(f[up])
        gd, fd = self.drive_uS[~up][::-1], np.maximum.accumulate(f[~up][::-1])
        return (gu, fu), (gd, fd)

    def spread_for(self, range_ratio: float, exponent: float, muscle: HumanMuscle) -> P0Spread | None:
        """The spread of ``range_ratio`` and ``exponent`` (None when the ramp never reaches its MVC)."""
        (gu, fu), _ = self.branches(p0_spread(self.rank, range_ratio, exponent))
        on = self.onset_uS
        if not np.all(np.isfinite(on)):
            return None
        f_on = np.interp(on, gu, fu)
        mvc = f_on[-1] / (muscle.recruitment_limit_percent / 100.0)
        if mvc > fu[-1]:
            return None
        g_max = float(np.interp(mvc, fu, gu))
        thr = 100.0 * f_on / mvc
        err = float(np.sqrt(np.mean((thr - muscle.thresholds(self.rank)) ** 2)))
        return P0Spread(float(range_ratio), float(exponent), g_max, float(mvc), thr, err)

    def fit_p0_spread(self, muscle: HumanMuscle, ratios: np.ndarray | None = None,
                      exponents: np.ndarray | None = None,
                      distance: Callable[[P0Spread], float] | None = None) -> P0Spread:
        """The range ratio (of ``ratios``, default 2..1000 log-spaced) and exponent (of ``exponents``, default
        0.5..30) whose thresholds come closest to the muscle's published ones, or, given ``distance``, the
        spread of smallest ``distance(spread)`` (``fit_p0_spread_to_recording``: to one recording)."""
        grid = np.geomspace(2.0, 1000.0, 37) if ratios is None else np.asarray(ratios, float)
        powers = np.geomspace(0.5, 30.0, 19) if exponents is None else np.asarray(exponents, float)
        fits = [s for s in (self.spread_for(float(r), float(q), muscle) for r in grid for q in powers)
                if s is not None]
        if not fits:
            raise InputError(f"pool {self.definition.name!r}: the calibration ramp recruits "
                             f"{int(np.isfinite(self.onset_uS).sum())} of {self.onset_uS.size} units and never "
                             "reaches the MVC of any P0 spread: raise top_uS")
        return min(fits, key=distance or (lambda s: s.rms_error_percent))

    def drive_for(self, spread: P0Spread, t_ms: np.ndarray, force_percent: np.ndarray, *, descent_ms: float,
                  step_ms: float = 20.0) -> tuple[np.ndarray, np.ndarray]:
        """The drive (uS) every ``step_ms`` (ms) that gives ``force_percent`` (% MVC at ``t_ms``, ms): the rising
        branch inverted until ``descent_ms`` (ms), the falling branch after it."""
        (gu, fu), (gd, fd) = self.branches(spread.p0_N(self.rank))
        times = np.arange(float(t_ms[0]), float(t_ms[-1]) + step_ms / 2, step_ms)
        target = np.clip(np.interp(times, t_ms, force_percent), 0.0, 100.0) * spread.mvc_force / 100.0
        drive = np.where(times < descent_ms, np.interp(target, fu, gu), np.interp(target, fd, gd))
        return times, drive

    def correct_drive(self, spread: P0Spread, times: np.ndarray, drive: np.ndarray, result: PoolResult,
                      t_ms: np.ndarray, force_percent: np.ndarray, *, descent_ms: float = np.inf,
                      lag_ms: float = 100.0, smooth_ms: float = 200.0, max_step: float = 0.1, gain: float = 1.0
                      ) -> tuple[np.ndarray, np.ndarray]:
        """One step of iterative learning control: the drive plus ``gain`` times the force error ``lag_ms`` later (the
        muscle's delay) divided by the slope of the branch in use (rising before ``descent_ms``, falling after; the
        secant over +- ``SLOPE_HALF_WIDTH`` of the MVC drive),
        smoothed over ``smooth_ms`` (over the whole trial when it is shorter), each change at most ``max_step`` of the
        MVC drive, and the drive kept within the physiological range (0 to the MVC drive)."""
        (gu, fu), (gd, fd) = self.branches(spread.p0_N(self.rank))
        model = spread.percent_mvc(result.pool_force_N - result.pool_force_N[0])
        err = np.interp(times + lag_ms, t_ms, force_percent) - np.interp(times + lag_ms, result.t_ms, model)
        floor = 0.05 * spread.mvc_force / max(spread.mvc_drive_uS, 1e-12)
        h = SLOPE_HALF_WIDTH * spread.mvc_drive_uS
        slope = np.where(times < descent_ms, _slope(gu, fu, drive, h), _slope(gd, fd, drive, h))
        step = positive_number("gain", gain) * err * spread.mvc_force / 100.0 / np.maximum(slope, floor)
        k = min(max(int(round(smooth_ms / (times[1] - times[0]))), 1), step.size)   # a trial shorter than the window
        step = np.convolve(step, np.ones(k) / k, mode="same")
        limit = max_step * spread.mvc_drive_uS
        return times, np.clip(drive + np.clip(step, -limit, limit), 0.0, spread.mvc_drive_uS)


#: Seeds of the unit depths over which ``fit_p0_spread_to_recording`` averages (apart from the seeds 0-19 that
#: ``recorded_comparison`` reports, so that the reported identification is not the one fitted).
FIT_SEEDS = range(100, 110)


def time_above_s(force_percent: np.ndarray, sample_s: float, levels_percent: np.ndarray) -> np.ndarray:
    """How long (s) a force sampled every ``sample_s`` (s) is at or above each of ``levels_percent`` (same unit
    as the force; 0 for a NaN level)."""
    positive_number("sample_s", sample_s)
    f = np.sort(np.asarray(force_percent, float).ravel())
    lv = np.asarray(levels_percent, float)
    above = f.size - np.searchsorted(f, np.where(np.isfinite(lv), lv, np.inf), side="left")
    return above * float(sample_s)


def fit_p0_spread_to_recording(cal: Calibration, muscle: HumanMuscle, recorded_thresholds_percent: np.ndarray,
                               peak_percent: float, *, model: IdentificationModel | None = None,
                               seeds: Sequence[int] = FIT_SEEDS, recorded_force_percent: np.ndarray | None = None,
                               force_sample_s: float | None = None) -> tuple[P0Spread, float]:
    """The P0 spread fitted to one recording: the one whose units a decomposition would identify
    (``identification.identified_ks``: the recording's count of the active units of highest weight in it, depths
    from ``seeds``, ``model``'s parameters) have the recruitment thresholds (% MVC, on the calibration ramp)
    closest to the recorded ones (``spread_distances``, whose arguments these are), chosen by ``best_spread``.
    Returns (the spread, its own mean KS distance)."""
    grid, d = spread_distances(cal, muscle, recorded_thresholds_percent, peak_percent, model=model, seeds=seeds,
                               recorded_force_percent=recorded_force_percent, force_sample_s=force_sample_s)
    return best_spread(grid, d)


def spread_distances(cal: Calibration, muscle: HumanMuscle, recorded_thresholds_percent: np.ndarray,
                     peak_percent: float, *, model: IdentificationModel | None = None,
                     seeds: Sequence[int] = FIT_SEEDS, recorded_force_percent: np.ndarray | None = None,
                     force_sample_s: float | None = None) -> tuple[list[list[P0Spread | None]], np.ndarray]:
    """Every spread of the fit's grid (range ratios x exponents; None where the ramp never reaches its MVC) and the
    mean KS distance (``identification.identified_ks`` over ``seeds``) between the recruitment thresholds of the
    units a decomposition would identify with it and the recorded ones (inf where too few units are active).
    Active: the units recruited at or below ``peak_percent`` (% MVC, the largest force the recording reaches): a
    pool that follows the force recruits every unit whose threshold a fluctuation of the plateau reaches, and with
    the PIC's hysteresis those units go on firing on the plateau.  Given the recorded force
    (``recorded_force_percent``, % MVC, sampled every ``force_sample_s`` s), each unit's time discharging in the
    identification (``identify``'s ``active_s``, which counts when ``model.activity_exponent`` is above 0) is the
    time that force stays at or above the unit's threshold; without it every active unit counts alike.  Range
    ratios 1.5-100 (unit forces span about 100-fold in human muscles: Enoka & Fuglevand 2001) and exponents
    0.25-30, log-spaced.  InputError when no spread's active units stand for as many muscle units as were
    recorded."""
    rec = np.asarray(recorded_thresholds_percent, float).ravel()
    rec = rec[np.isfinite(rec)]
    if not rec.size:
        raise InputError("fit_p0_spread_to_recording: the recording has no finite recruitment threshold")
    finite_number("peak_percent", peak_percent)
    m = model or IdentificationModel()
    copies = copies_per_unit(cal.rank.size, muscle.motor_units)
    force = None
    if recorded_force_percent is not None:
        force = np.asarray(recorded_force_percent, float).ravel()
        if not force.size or not np.all(np.isfinite(force)):
            raise InputError("fit_p0_spread_to_recording: recorded_force_percent must be finite numbers (% MVC)")
        positive_number("force_sample_s", force_sample_s)

    def distance(spread: P0Spread) -> float:
        thr = spread.thresholds_percent
        active = thr <= peak_percent
        if copies[active].sum() < rec.size:       # too few active units for the recording's count
            return np.inf
        active_s = None if force is None else time_above_s(force, float(force_sample_s), thr)
        return identified_ks(spread.p0_N(cal.rank), active, thr, rec, motor_units=muscle.motor_units, model=m,
                             seeds=seeds, active_s=active_s)

    ratios, powers = np.geomspace(1.5, 100.0, 37), np.geomspace(0.25, 30.0, 23)
    grid = [[cal.spread_for(float(r), float(q), muscle) for q in powers] for r in ratios]
    if all(sp is None for row in grid for sp in row):
        cal.fit_p0_spread(muscle, ratios, powers)                 # raises: the ramp never reaches an MVC
    d = np.array([[np.inf if sp is None else distance(sp) for sp in row] for row in grid])
    if not np.isfinite(d).any():
        raise InputError(f"pool {cal.definition.name!r}: no P0 spread recruits enough units below "
                         f"{peak_percent:g} % MVC for the recording's {rec.size} units")
    return grid, d


def best_spread(grid: list[list[P0Spread | None]], distances: np.ndarray) -> tuple[P0Spread, float]:
    """The spread of ``grid`` (``spread_distances``) whose distance averaged with its grid neighbours (one step of
    range and of exponent either way) is smallest, and its own distance.  The distance is a KS distance of a few
    tens of units, noisy from one spread to the next, so the choice is a fit that holds when the spread changes a
    little, not a lone grid point where the sampled identification happens to line up.  ``distances`` may be a sum
    over several recordings of one muscle (one spread for all of them)."""
    d = np.asarray(distances, float)
    if d.shape != (len(grid), len(grid[0]) if grid else 0) or not np.isfinite(d).any():
        raise InputError(f"best_spread needs a finite distance for some spread of the {len(grid)}-row grid")
    i, j = np.unravel_index(np.argmin(_neighbourhood_mean(d)), d.shape)
    best = grid[i][j]
    assert best is not None
    return best, float(d[i, j])


def _neighbourhood_mean(d: np.ndarray) -> np.ndarray:
    """The mean of the finite values of each cell's 3 x 3 block of ``d`` (inf where the cell itself is not
    finite)."""
    finite = np.isfinite(d)
    total = uniform_filter(np.where(finite, d, 0.0), size=3, mode="constant")   # block means with zeros outside:
    count = uniform_filter(finite.astype(float), size=3, mode="constant")       # their ratio is the finite mean
    return np.where(finite, total / np.maximum(count, 1e-12), np.inf)


@dataclass(frozen=True)
class FollowedForce:
    """The pass of ``follow`` whose force came closest to the target: the drive (uS at ``times_ms``), the run,
    its force (% MVC at ``result.t_ms``), and every pass's force NRMSE (% of the target's range) in order."""

    times_ms: np.ndarray
    drive_uS: np.ndarray
    result: PoolResult
    force_percent: np.ndarray
    nrmse_passes: tuple[float, ...]

    @property
    def nrmse_percent(self) -> float:
        """The chosen pass's force NRMSE (% of the target's range): the smallest of the passes."""
        return min(self.nrmse_passes)


def follow(cal: Calibration, spread: P0Spread, t_ms: np.ndarray, force_percent: np.ndarray,
           run: Callable[[np.ndarray, np.ndarray], PoolResult], *, corrections: int, descent_ms: float,
           report: Callable[[int, float], None] | None = None) -> FollowedForce:
    """Find the drive whose pool force follows ``force_percent`` (% MVC at ``t_ms``, ms): the calibration inverted
    (``drive_for``), then ``corrections`` steps of ``correct_drive``, each from the best pass so far; a step that
    does not lower the NRMSE halves the next one's gain.  ``run(times_ms, drive_uS)`` runs the pool (e.g.
    ``run_drive`` with its definition and duration); ``report(pass, nrmse)`` is told each pass's NRMSE.  A pass
    whose force is not finite stops the search with an InputError (``nrmse_percent``)."""
    if not isinstance(corrections, int) or isinstance(corrections, bool) or corrections < 0:
        raise InputError(f"corrections must be an integer >= 0, got {corrections!r}")
    times, drive = cal.drive_for(spread, t_ms, force_percent, descent_ms=descent_ms)
    best: tuple[np.ndarray, np.ndarray, PoolResult, np.ndarray, float] | None = None
    errors: list[float] = []
    gain = 1.0
    for k in range(corrections + 1):
        result = run(times, drive)
        model = spread.percent_mvc(result.pool_force_N - result.pool_force_N[0])
        errors.append(nrmse_percent(np.interp(result.t_ms, t_ms, force_percent), model))
        if report is not None:
            report(k, errors[-1])
        if best is None or errors[-1] < best[-1]:
            best = (times, drive, result, model, errors[-1])
        else:
            gain *= 0.5
        if k < corrections:
            times, drive = cal.correct_drive(spread, best[0], best[1], best[2], t_ms, force_percent,
                                             descent_ms=descent_ms, gain=gain)
    assert best is not None
    return FollowedForce(best[0], best[1], best[2], best[3], tuple(errors))


def _slope(g: np.ndarray, f: np.ndarray, at: np.ndarray, half_width_uS: float) -> np.ndarray:
    """d f / d g of a branch (N per uS) at the drives ``at``: the secant over ``at`` +- ``half_width_uS``.  A
    branch sampled every millisecond is a staircase of single twitches and recruitments (flat, then a jump), so
    its point-by-point gradient is zero at some drives and many times the mean slope at others."""
    return (np.interp(at + half_width_uS, g, f) - np.interp(at - half_width_uS, g, f)) / (2.0 * half_width_uS)


def run_drive(definition: PoolDefinition, times_ms: np.ndarray, drive_uS: np.ndarray, duration_ms: float, *,
              dt_ms: float = 0.025, length_mm: float = -8.0) -> PoolResult:
    """Run the pool under the common synaptic drive (uS, linear between times_ms) for duration_ms (ms)."""
    positive_number("duration_ms", duration_ms)
    with Pool(definition, length=length_mm) as pool:
        pool.drive_synaptic(times_ms, drive_uS)
        return pool.run(duration_ms, Simulator(method="fixed", dt_ms=dt_ms))


def calibrate(definition: PoolDefinition, *, top_uS: float = 1.2, ramp_ms: float = 10000.0,
              dt_ms: float = 0.025, length_mm: float = -8.0) -> Calibration:
    """Run the slow triangle 0 -> top_uS (uS) -> 0 (ramp_ms each way, ms) with every P0 = 1 N; see the module
    docstring."""
    positive_number("top_uS", top_uS)
    positive_number("ramp_ms", ramp_ms)
    d = replace(definition, smallest_p0_N=1.0, p0_range=1.0, p0_N=None)
    times, drive = np.array([0.0, ramp_ms, 2.0 * ramp_ms]), np.array([0.0, top_uS, 0.0])
    r = run_drive(d, times, drive, 2.0 * ramp_ms, dt_ms=dt_ms, length_mm=length_mm)
    basis = r.unit_force_N - r.unit_force_N[:, :1]
    onset = np.array([np.interp(s[0], times, drive) if s.size and s[0] <= ramp_ms else np.nan
                      for s in r.spikes_ms])
    return Calibration(d, r.t_ms, np.interp(r.t_ms, times, drive), basis, onset, ramp_ms)
