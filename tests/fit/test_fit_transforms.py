"""The search space's z <-> p maps (neuromuscle.fit.transforms): p never leaves the bounds searched, also where the
round trip through z rounds past them."""

import math

import pytest

from neuromuscle.fit.transforms import Transform
from neuromuscle.parameters import SPECS


@pytest.mark.parametrize("start", [5000.0, 7000.0, 11000.0, 333.3 * 17])
def test_a_bound_maps_back_inside(start):
    # staircase.tau's range ends at 120000 ms: ref exp(ln(120000 / ref)) is 120000.00000000001 for some starts,
    # which a parameter set refuses as outside the range
    lo, hi = SPECS["staircase.tau"].lower, SPECS["staircase.tau"].upper
    tf = Transform.for_parameter("staircase.tau", start, lo, hi)
    assert tf.log
    assert lo <= tf.to_p(tf.to_z(lo)) <= lo * (1 + 1e-15) and hi * (1 - 1e-15) <= tf.to_p(tf.to_z(hi)) <= hi
    assert tf.to_p(tf.to_z(start)) == pytest.approx(start, rel=1e-15)
    assert tf.to_p(math.log(hi / start) + 1.0) == hi  # beyond the bound (a trust region's overshoot): the bound


def test_a_linear_transform_is_clipped_too():
    tf = Transform.for_parameter("C1", 0.1, -1.0, 1.0) if SPECS["C1"].lower < 0 else \
        Transform("C1", 0.1, False, 1.0, -1.0, 1.0)
    assert not tf.log
    assert tf.to_p(tf.to_z(1.0) + 1e-3) == 1.0
