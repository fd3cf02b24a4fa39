"""neuromuscle.analysis.closed_form: eqs 13-16 (Hill/Mashima coefficients) and eq 18 (length compensation)."""

import numpy as np
import pytest

from neuromuscle.analysis.closed_form import hill_mashima_coefficients, length_compensation_coefficients
from neuromuscle.analysis.module3 import ce_velocity
from neuromuscle.errors import InputError

CT09_POINTS = [(-160.0, 1.0), (-1.0, 22.0), (1.0, 23.5), (80.0, 34.35)]
CT95_POINTS = [(-80.0, 8.0), (-1.0, 28.0), (1.0, 29.5), (80.0, 43.0)]


# ------------------------------------------------------------------------------------------- eqs 13-16

@pytest.mark.parametrize("points, p0, expected", [
    (CT09_POINTS, 23.0, (2.348, 24.348, -7.352, 30.297)),
    (CT95_POINTS, 28.9, (0.180, 31.311, -9.185, 31.858)),
])
def test_hill_mashima_reproduces_table1(points, p0, expected):
    coef = hill_mashima_coefficients(points, p0)
    got = (coef["a0"], coef["b0"], coef["c0"], coef["d0"])
    np.testing.assert_allclose(got, expected, atol=6e-4)


@pytest.mark.parametrize("points, p0", [(CT09_POINTS, 23.0), (CT95_POINTS, 28.9)])
def test_hill_mashima_coefficients_pass_through_the_points(points, p0):
    coef = {**hill_mashima_coefficients(list(reversed(points)), p0), "P0": p0}  # order does not matter
    for velocity, tension in points:
        assert ce_velocity(tension, p0, coef) == pytest.approx(velocity, rel=1e-9)


@pytest.mark.parametrize("points, p0, culprit", [
    ([(-160, 1), (-1, 22), (-2, 20), (80, 34.35)], 23.0, "points"),        # three shortening
    ([(-160, 1), (0, 23), (1, 23.5), (80, 34.35)], 23.0, "points"),         # V = 0
    ([(-160, 1), (-160, 1), (1, 23.5), (80, 34.35)], 23.0, r"points \(shortening\)"),  # same point twice
    ([(-160, 1), (-1, 22), (1, 24), (2, 25)], 23.0, r"points \(lengthening\)"),  # collinear with (0, P0)
    ([(-160, 1), (-1, 23), (1, 23.5), (80, 34.35)], 23.0, "shortening tensions"),
    ([(-160, 1), (-1, 22), (1, 22.5), (80, 34.35)], 23.0, "lengthening tensions"),
    ([(-160, 1), (-1, 22), (1, 23.5), (80, np.nan)], 23.0, "points"),
    ([(-160, 1), (-1, 22), (1, 23.5)], 23.0, "points"),
    (CT09_POINTS, 0.0, "P0_N"),
    (CT09_POINTS, np.inf, "P0_N"),
])
def test_hill_mashima_bad_inputs(points, p0, culprit):
    with pytest.raises(InputError, match=culprit):
        hill_mashima_coefficients(points, p0)



# ------------------------------------------------------------------------------------------------ eq 18

def test_length_compensation_ct09_split():
    coef = length_compensation_coefficients([(-16.0, 0.77), (-8.0, 1.0), (0.0, 1.08)], x_opt_mm=-8.0)
    got = [coef[k] for k in ("phi1", "phi2", "phi3", "phi4")]
    np.testing.assert_allclose(got, [0.02875, 1.23, 0.01, 1.08], atol=1e-12)


def test_length_compensation_ct95_one_line():
    coef = length_compensation_coefficients([(-10.0, 0.97), (-5.0, 1.0), (0.0, 1.03)], x_opt_mm=-5.0,
                                            split=False)
    got = [coef[k] for k in ("phi1", "phi2", "phi3", "phi4")]
    np.testing.assert_allclose(got, [0.006, 1.03, 0.006, 1.03], atol=1e-12)


def test_length_compensation_least_squares_with_more_points():
    pts = [(-16.0, 0.70), (-12.0, 0.92), (-8.0, 1.0), (-4.0, 1.05), (0.0, 1.07)]
    coef = length_compensation_coefficients(pts, x_opt_mm=-8.0)
    slope, intercept = np.polyfit([-16, -12, -8], [0.70, 0.92, 1.0], 1)
    assert coef["phi1"] == pytest.approx(slope) and coef["phi2"] == pytest.approx(intercept)
    slope, intercept = np.polyfit([-8, -4, 0], [1.0, 1.05, 1.07], 1)
    assert coef["phi3"] == pytest.approx(slope) and coef["phi4"] == pytest.approx(intercept)


@pytest.mark.parametrize("points, x_opt, split, culprit", [
    ([(-16, 0.77), (-8, 1.0), (0, 1.08)], -10.0, True, "at or below"),
    ([(-16, 0.77), (-8, 1.0), (0, 1.08)], 1.0, True, "at or above"),
    ([(-8, 0.9), (-8, 1.0)], -8.0, False, "distinct"),
    ([(-16, np.nan), (-8, 1.0), (0, 1.08)], -8.0, True, "points"),
    ([(-16, 0.77), (-8, 1.0), (0, 1.08)], np.nan, True, "x_opt_mm"),
    ([1.0, 2.0, 3.0], -8.0, True, "points"),
])
def test_length_compensation_bad_inputs(points, x_opt, split, culprit):
    with pytest.raises(InputError, match=culprit):
        length_compensation_coefficients(points, x_opt, split=split)

