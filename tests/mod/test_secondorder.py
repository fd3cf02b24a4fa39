"""NEURON's secondorder (Crank-Nicolson for the membrane) with the mechanisms that advance their own states inside a
METHOD euler block, which NEURON calls with dt halved under secondorder 1 and 2 (mod/fixed_step.inc): the muscle,
which does not depend on v, gives the same force under each."""

import numpy as np
import pytest

from neuromuscle import InputError, Simulator, simulate
from neuromuscle.model.kim_unit import kim_fused
from neuromuscle.protocols import constant_rate, random_length

DURATION_MS = 1200.0
SPIKES = constant_rate(20, 1000.0, start_ms=100.0)


def _force(ct09, secondorder: int, moving: bool, **models) -> np.ndarray:
    length = random_length(DURATION_MS, seed=3) if moving else -8.0
    return simulate(ct09, SPIKES, length, DURATION_MS, simulator=Simulator(dt_ms=0.025, secondorder=secondorder),
                    **models).force_N


@pytest.mark.parametrize("name, models, moving", [
    ("three mechanisms, isometric", {}, False),
    ("three mechanisms, random length", {}, True),
    ("KimUnit every step", {"excitation": kim_fused()}, True),
    ("KimUnit every 4 steps", {"excitation": kim_fused(substeps=4)}, True),
    ("Hatze excitation and MTC", {"excitation": "hatze", "contraction": "hatze"}, False),
])
def test_the_muscle_is_the_same_under_every_secondorder(ct09, name, models, moving):
    ref = _force(ct09, 0, moving, **models)
    assert ref.max() > 1.0
    for order in (1, 2):
        # the same steps; only the derivatives METHOD euler adds (zero or the step's mean rate) are added in two
        # halves (before the mechanisms counted the step, the states covered half of it: 30 % of peak off)
        diff = np.abs(_force(ct09, order, moving, **models) - ref).max()
        assert diff <= 1e-9 * ref.max(), f"{name}, secondorder {order}: {diff:.3g} N"


def test_secondorder_is_checked_and_recorded():
    with pytest.raises(InputError, match="secondorder must be 0, 1 or 2"):
        Simulator(secondorder=3)
    with pytest.raises(InputError, match="fixed step only"):
        Simulator(method="cvode", secondorder=2)
    assert Simulator(secondorder=2).settings()["secondorder"] == 2
    assert "secondorder" not in Simulator().settings()
