"""Random parameter sets of the sweep (``neuromuscle bench sweep``): every Modules 1-3 parameter of a base set
(CT09) times its own log-uniform factor, clipped into the parameter's physiological bounds.

The factor multiplies the value whatever its sign, so a negative parameter (g1, c0, C4 in CT09) keeps its sign
and has its magnitude scaled; a zero would stay zero (CT09 has none).  Parameters whose bounds allow a sign
change (C1, C4, phi1-phi4) therefore never change sign in the sweep.  A set the package refuses (a bound, or a
cross-parameter rule such as c0 > -P0) is redrawn from the same draw's stream and the refusal is counted.
Draw ``index`` of ``seed`` depends on nothing else: the same seed and index give the same set in any process.

Eq 18's two lines are not drawn independently: phi4 follows from phi1, phi2, phi3 and X_opt = g1 so that the
length factor keeps the base set's ratio across the optimum, phi(X_opt+) / phi(X_opt-) (CT09: 1.00/0.99).  The
paper's phi is continuous at the optimum to 1 %; independent factors on the four coefficients made it jump by tens
of percent there, a step in K5 (and with eq 20 in A) that is not physiology and that the two integrators place up to
one step apart (docs/validation/robustness.md).  phi4's own factor is still drawn, so every other draw keeps its
stream, and is reported as the ratio of the derived phi4 to the base's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.kim import COMPONENTS
from ..parameters import SPECS, ParameterSet, kim_parameter_names

#: Default range of the multiplicative factor (log-uniform between the two).
FACTOR_RANGE = (0.5, 2.0)
#: Redraws allowed before a draw gives up (each is counted in the summary).
MAX_REDRAWS = 1000


@dataclass(frozen=True)
class Draw:
    """One draw: its index, the parameter set, each Kim parameter's factor (1), the messages of the sets refused
    before it, the random-length seed, and whether its moving protocols use movement compensation (eqs 19-20)."""

    index: int
    params: ParameterSet
    factors: dict[str, float]
    refused: tuple[str, ...]
    length_seed: int
    movement_compensation: bool


def accept(params: ParameterSet) -> None:
    """Raise InputError when the Kim components refuse ``params`` (the rules checked when a unit is built)."""
    for comp in COMPONENTS:
        comp().values(params)


def continuous_phi4(values: dict[str, float], base: ParameterSet) -> float:
    """phi4 (1) that gives eq 18 at X_opt = g1 (mm) the base set's ratio phi(X_opt+)/phi(X_opt-) for the drawn
    phi1 (/mm), phi2 (1) and phi3 (/mm).  A value outside phi4's bounds is left for ``accept`` to refuse."""
    g1b = base["g1"]
    ratio = (base["phi3"] * g1b + base["phi4"]) / (base["phi1"] * g1b + base["phi2"])
    g1 = values["g1"]
    return ratio * (values["phi1"] * g1 + values["phi2"]) - values["phi3"] * g1


def draw(base: ParameterSet, seed: int, index: int, factor_range: tuple[float, float] = FACTOR_RANGE) -> Draw:
    """Draw ``index`` of the sweep ``seed`` around ``base``: factors log-uniform in ``factor_range``; odd draws use
    movement compensation."""
    rng = np.random.default_rng([seed, index])
    names = kim_parameter_names()
    lo, hi = np.log(factor_range)
    refused: list[str] = []
    for _ in range(MAX_REDRAWS):
        factors = np.exp(rng.uniform(lo, hi, size=len(names)))
        values = {n: float(np.clip(base[n] * f, SPECS[n].lower, SPECS[n].upper)) for n, f in zip(names, factors)}
        values["phi4"] = continuous_phi4(values, base)
        factors[names.index("phi4")] = values["phi4"] / base["phi4"]
        try:
            params = ParameterSet(f"sweep seed {seed} draw {index}", values,
                                  f"{base.name} x log-uniform {factor_range}")
            accept(params)
        except InputError as exc:
            refused.append(str(exc))
            continue
        return Draw(index, params, dict(zip(names, factors.tolist())), tuple(refused),
                    int(rng.integers(2**31 - 1)), index % 2 == 1)
    raise InputError(f"sweep seed {seed} draw {index}: {MAX_REDRAWS} sets refused in a row (last: {refused[-1]})")
