"""What to fit: measured trials, a base parameter set, the free parameters with bounds, the objective.

    problem = FitProblem(list(data.trials.values()), base=load_parameters("CT09"), free=["C1", "C3"])

A :class:`FitProblem` maps a search vector z (see :mod:`.transforms`) to a ParameterSet and to the residual
vector of its objective (:mod:`.objectives`); the simulation of each trial is :func:`.evaluate.trial_simulation`.

Eq 11 needs the lengthening coefficient c0 above -P0 (its asymptote above the isometric force).  When both are
free, c0 is searched as the fraction c0/P0 in (-1, 0], so no point of the search crosses the asymptote whatever
P0 does; when only one is free, its bounds are narrowed to keep c0/P0 >= -``C0_OVER_P0_MIN``.
"""

from __future__ import annotations

import copy
from dataclasses import asdict
from typing import Any, Mapping, Sequence

import numpy as np

from ..analysis.module3 import C0_OVER_P0_MIN
from ..errors import InputError
from ..measured import Trial
from ..measured.simulation import check_trial_units, trial_simulation
from ..parameters import SPECS, ParameterSet
from .evaluate import SimulationOptions
from .objectives import OBJECTIVES, residual_scales, weighted_residuals
from .transforms import Transform, default_bounds


class FitProblem:
    """What to fit: trials (list of measured ``Trial``) with weights, a base ParameterSet, the free parameters
    with bounds (parameter units), frozen values, the objective ("sse" or "nrmse") and simulation options.

    free: names, or a mapping name -> (lower, upper) or None (default bounds, see :mod:`.transforms`).
    start: optional start values of free parameters (default: the base set after ``frozen``).
    sample_weights: optional per-trial arrays of per-sample weights in [0, 1] (None for a trial counts every
    sample fully): a sample of weight 0 leaves the objective, e.g. a phase whose physics the model lacks.
    """

    def __init__(self, trials: Sequence[Trial], base: ParameterSet,
                 free: Sequence[str] | Mapping[str, tuple[float, float] | None], *,
                 weights: Sequence[float] | None = None, frozen: Mapping[str, float] | None = None,
                 start: Mapping[str, float] | None = None, objective: str = "sse",
                 options: SimulationOptions = SimulationOptions(),
                 sample_weights: Sequence[np.ndarray | None] | None = None) -> None:
        if not isinstance(base, ParameterSet):
            raise InputError(f"base must be a ParameterSet (see load_parameters), got {type(base).__name__}")
        self.trials = list(trials)
        if not self.trials:
            raise InputError("FitProblem needs at least one trial")
        for t in self.trials:
            if not isinstance(t, Trial):
                raise InputError(f"trials must be measured Trial objects, got {type(t).__name__}")
            check_trial_units(t)
        self.weights = np.ones(len(self.trials)) if weights is None else np.asarray(weights, dtype=float)
        if self.weights.shape != (len(self.trials),) or not np.all(np.isfinite(self.weights)) \
                or np.any(self.weights < 0):
            raise InputError(f"weights must be {len(self.trials)} finite values >= 0, got {weights!r}")
        if objective not in OBJECTIVES:
            raise InputError(f"objective must be one of {OBJECTIVES}, got {objective!r}")
        self.objective = objective
        self.options = options
        bounds_in = dict(free) if isinstance(free, Mapping) else {n: None for n in free}
        if not bounds_in:
            raise InputError("no free parameters: give at least one name to fit")
        unknown = [n for n in bounds_in if n not in SPECS]
        if unknown:
            raise InputError(f"unknown free parameter(s) {unknown}; known: {', '.join(SPECS)}")
        frozen = dict(frozen or {})
        both = sorted(set(frozen) & set(bounds_in))
        if both:
            raise InputError(f"parameter(s) {both} are both free and frozen")
        self.frozen = frozen
        self.base = base.with_values(**frozen) if frozen else base
        start = dict(start or {})
        extra = sorted(set(start) - set(bounds_in))
        if extra:
            raise InputError(f"start values given for parameter(s) {extra} that are not free")
        self.free = list(bounds_in)
        self.start = {n: float(start.get(n, self.base[n])) for n in self.free}
        self.base.with_values(**self.start)  # admissible?
        self.bounds: dict[str, tuple[float, float]] = {}
        self._tf: list[Transform] = []
        for n in self.free:
            lo, hi = bounds_in[n] if bounds_in[n] is not None else default_bounds(n, self.start[n])
            lo, hi = float(lo), float(hi)
            spec = SPECS[n]
            if not (lo < hi) or not (np.isfinite(lo) and np.isfinite(hi)):
                raise InputError(f"free parameter {n!r}: bounds ({lo}, {hi}) {spec.unit} must be finite with "
                                 "lower < upper")
            if lo < spec.lower or (lo == spec.lower and not spec.lower_inclusive):
                raise InputError(f"free parameter {n!r}: lower bound {lo} {spec.unit} is outside the admissible "
                                 f"range ({'>=' if spec.lower_inclusive else '>'} {spec.lower})")
            p0 = self.start[n]
            if not lo <= p0 <= hi:
                raise InputError(f"free parameter {n!r}: start {p0} {spec.unit} is outside its bounds "
                                 f"[{lo}, {hi}]")
            self.bounds[n] = (lo, hi)
        self._c0_relative = "c0" in self.bounds and "P0" in self.bounds
        self._narrow_for_eq11()
        for n in self.free:
            lo, hi = self.bounds[n]
            if n == "c0" and self._c0_relative:
                p0_start = self.start["P0"]
                self._tf.append(Transform.for_parameter("c0", self.start["c0"] / p0_start, lo / p0_start,
                                                        hi / p0_start))
            else:
                self._tf.append(Transform.for_parameter(n, self.start[n], lo, hi))
        needs_stim = [n for n in self.free if SPECS[n].module in (0, 1, 2)]
        for t in self.trials:
            if np.size(t.stimulus_times_s) == 0:
                what = (f"Module 1/2 parameter(s) {needs_stim}" if needs_stim else f"parameter(s) {self.free}")
                raise InputError(f"trial '{t.trial_id}' has no stimulus: without one the model stays at rest and "
                                 f"the trial carries no information on {what}; drop it from the fit")
            if t.n_samples < 2:
                raise InputError(f"trial '{t.trial_id}' has fewer than 2 samples")
        self._scale: list[float | np.ndarray] = list(residual_scales(self.trials, self.weights, objective))
        if sample_weights is not None:
            if len(sample_weights) != len(self.trials):
                raise InputError(f"sample_weights must give one entry per trial ({len(self.trials)}), got "
                                 f"{len(sample_weights)}")
            for k, (t, w) in enumerate(zip(self.trials, sample_weights)):
                if w is None:
                    continue
                w = np.asarray(w, dtype=float)
                if w.shape != (t.n_samples,) or not np.all((w >= 0) & (w <= 1)):
                    raise InputError(f"trial '{t.trial_id}': sample weights must be {t.n_samples} values in [0, 1]")
                self._scale[k] = self._scale[k] * np.sqrt(w)

    def _narrow_for_eq11(self) -> None:
        """Narrow the bounds of c0 (and of P0 when c0 is held) so that c0/P0 >= -C0_OVER_P0_MIN everywhere in
        the search (with both free, c0's bounds are read as fractions of the start P0)."""
        floor = -C0_OVER_P0_MIN
        if "c0" in self.bounds:
            p0 = self.start["P0"] if "P0" in self.bounds else float(self.base["P0"])
            lo, hi = self.bounds["c0"]
            lo = max(lo, floor * p0)
            if not lo <= self.start["c0"] <= hi or not lo < hi:
                raise InputError(f"free parameter 'c0': start {self.start['c0']} N is outside (-P0, 0] with "
                                 f"P0 = {p0} N (eq 11 needs c0 > -P0)")
            self.bounds["c0"] = (lo, hi)
        elif "P0" in self.bounds:
            lo, hi = self.bounds["P0"]
            lo = max(lo, float(self.base["c0"]) / floor)
            if not lo <= self.start["P0"] <= hi:
                raise InputError(f"free parameter 'P0': start {self.start['P0']} N must exceed -c0 = "
                                 f"{-float(self.base['c0'])} N (eq 11 needs c0 > -P0)")
            self.bounds["P0"] = (lo, hi)

    # -- search space -------------------------------------------------------------------------------------
    @property
    def n_residuals(self) -> int:
        return int(sum(self.segments))

    def z_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounds of the search vector z."""
        def searched(name: str, p: float) -> float:
            return p / self.start["P0"] if name == "c0" and self._c0_relative else p

        lo = np.array([tf.to_z(searched(tf.name, self.bounds[tf.name][0])) for tf in self._tf])
        hi = np.array([tf.to_z(searched(tf.name, self.bounds[tf.name][1])) for tf in self._tf])
        return lo, hi

    def to_z(self, values: Mapping[str, float]) -> np.ndarray:
        """Search vector of the free parameters' ``values`` (parameter units)."""
        return np.array([tf.to_z(float(values["c0"]) / float(values["P0"]) if tf.name == "c0" and self._c0_relative
                                 else float(values[tf.name])) for tf in self._tf])

    def to_values(self, z: Sequence[float]) -> dict[str, float]:
        """The free parameters (parameter units) at search vector z."""
        vals = {tf.name: tf.to_p(float(zi)) for tf, zi in zip(self._tf, z)}
        if self._c0_relative:
            vals["c0"] *= vals["P0"]
        return vals

    def dp_dz(self, z: Sequence[float]) -> np.ndarray:
        """dp/dz at z (parameter units per unit of z): a vector (the diagonal) when every parameter is searched
        alone, the full k x k matrix dp_i/dz_j when c0 is searched as a fraction of P0."""
        vals = self.to_values(z)
        if not self._c0_relative:
            return np.array([tf.dp_dz(vals[tf.name]) for tf in self._tf])
        ic, ip = self.free.index("c0"), self.free.index("P0")
        ratio = vals["c0"] / vals["P0"]
        jac = np.diag([tf.dp_dz(ratio if tf.name == "c0" else vals[tf.name]) for tf in self._tf])
        jac[ic, ic] *= vals["P0"]
        jac[ic, ip] = ratio * jac[ip, ip]
        return jac

    def parameters(self, z: Sequence[float]) -> ParameterSet:
        """The complete ParameterSet at search vector z."""
        return self.base.with_values(**self.to_values(z))

    def reference(self) -> dict[str, dict[str, Any]]:
        """The transform of each free parameter (for the checkpoint)."""
        return {tf.name: {"ref": tf.ref, "log": tf.log, "scale": tf.scale,
                          **({"of": "c0/P0"} if tf.name == "c0" and self._c0_relative else {})}
                for tf in self._tf}

    def with_options(self, options: SimulationOptions) -> FitProblem:
        """The same problem (trials, weights, free parameters, search space) simulated with other ``options``."""
        other = copy.copy(self)
        other.options = options
        return other

    # -- evaluation ---------------------------------------------------------------------------------------
    def simulate_trials(self, z: Sequence[float], options: SimulationOptions | None = None) -> list[np.ndarray]:
        """Simulated force (N) of every trial at search vector z (with ``options``, default the problem's)."""
        params = self.parameters(z)
        opts = asdict(self.options if options is None else options)
        return [trial_simulation(params, t, **opts) for t in self.trials]

    @property
    def segments(self) -> list[int]:
        """Lengths of the independent pieces of the residual vector: the trials' sample counts."""
        return [t.n_samples for t in self.trials]

    def residuals_from(self, sims: Sequence[np.ndarray]) -> np.ndarray:
        """The residual vector of the simulated forces ``sims`` (N, one array per trial)."""
        return weighted_residuals(self._scale, sims, self.trials)

    def residuals(self, z: Sequence[float]) -> np.ndarray:
        """The residual vector at z (units: see :mod:`.objectives`)."""
        return self.residuals_from(self.simulate_trials(z))
