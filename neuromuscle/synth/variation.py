"""Per-preparation parameter variation: every parameter of Modules 1-3 moved from the base set by its own
log-normal factor, kept inside the physiological range of the parameter registry."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..parameters import ParameterSet, kim_parameter_names, registry

#: Relative margin kept from a bound when a drawn value is pulled back inside the range.
BOUND_MARGIN = 1e-3


def vary_parameters(base: ParameterSet, variation: float, rng: np.random.Generator,
                    name: str = "synthetic") -> ParameterSet:
    """``base`` with every Kim Modules 1-3 parameter multiplied by exp(variation z), z ~ N(0, 1) drawn from
    ``rng`` in the registry's order (variation: the log-sd, e.g. 0.2 for about 20 %), each value clipped into
    its physiological range (the sign of a parameter never changes).  variation = 0 returns the base values."""
    if isinstance(variation, bool) or not isinstance(variation, (int, float)) or not 0.0 <= variation <= 1.0:
        raise InputError(f"variation must be a log-sd between 0 and 1 (e.g. 0.2 for about 20 %), got {variation!r}")
    reg = registry()
    names = kim_parameter_names()
    factors = np.exp(variation * rng.standard_normal(len(names)))
    values = {}
    for flat, f in zip(names, factors):
        spec = reg[flat]
        v = float(base[flat]) * float(f)
        span = spec.upper - spec.lower
        lo = spec.lower + (BOUND_MARGIN * span if not spec.lower_inclusive else 0.0)
        values[flat] = float(np.clip(v, lo, spec.upper))
    if values["c0"] <= -values["P0"]:  # eq 11's asymptote must lie above Fc (KimForce refuses otherwise)
        values["c0"] = -0.9 * values["P0"]
    return ParameterSet(name, values, f"{base.name} with every Module 1-3 parameter times exp({variation:g} z)")


#: A drawn preparation is kept when its isometric twitch at the optimum peaks within this fraction of P0 (cat
#: soleus and gastrocnemius units: about 0.1-0.3; CT09 0.155) ...
TWITCH_PEAK_RANGE = (0.08, 0.35)
#: ... and its resting force stays below this fraction of P0 (CT09: 0.0036).
REST_FORCE_MAX = 0.01
#: Draws tried before giving up.
MAX_DRAWS = 200


def twitch_phenotype(params: ParameterSet) -> tuple[float, float]:
    """(twitch peak, resting force) as fractions of P0: an isometric twitch at the optimum g1, baseline model
    (eq 18 and eqs 19-20 off), fixed step 0.05 ms."""
    from ..model.kim import kim_excitation
    from ..sim import simulate

    r = simulate(params, [300.0], float(params["g1"]), 700.0, excitation=kim_excitation(False, False), dt_ms=0.05,
                 record=("force.F",), record_dt_ms=0.5)
    P0 = float(params["P0"])
    return float(r.force_N.max()) / P0, float(r.force_N[int(290.0 / 0.5)]) / P0


def draw_preparation(base: ParameterSet, variation: float, rng: np.random.Generator,
                     name: str = "synthetic") -> tuple[ParameterSet, int]:
    """A physiological preparation: :func:`vary_parameters` drawn again from ``rng`` until the twitch peak lies in
    TWITCH_PEAK_RANGE and the resting force below REST_FORCE_MAX (fractions of P0).  Returns the set and the
    number of draws it took; InputError after MAX_DRAWS (variation too large for a physiological unit)."""
    for n in range(1, MAX_DRAWS + 1):
        params = vary_parameters(base, variation, rng, name)
        peak, rest = twitch_phenotype(params)
        if TWITCH_PEAK_RANGE[0] <= peak <= TWITCH_PEAK_RANGE[1] and rest <= REST_FORCE_MAX:
            return params, n
    raise InputError(f"no physiological preparation in {MAX_DRAWS} draws at variation {variation:g} around "
                     f"{base.name} (twitch peak {TWITCH_PEAK_RANGE} P0, rest <= {REST_FORCE_MAX} P0); lower it")
