"""Module 3 calibration (neuromuscle.calibration.module3): closed form, least squares, KSE input errors."""

from __future__ import annotations

import numpy as np
import pytest

from neuromuscle.calibration import (calibrate_force_length, calibrate_force_velocity, calibrate_kse,
                                     gaussian_force_length, hill_tension, mashima_tension)
from neuromuscle.errors import InputError
from neuromuscle.measured import Trial

def test_force_velocity_closed_form_matches_table1():
    pts = [(-160, 1), (-1, 22), (1, 23.5), (80, 34.35)]
    r = calibrate_force_velocity([p[0] for p in pts], [p[1] for p in pts], 23.0)
    assert r.values["a0"] == pytest.approx(2.348, abs=2e-3)
    assert r.values["d0"] == pytest.approx(30.297, abs=2e-3)
    assert r.errors["rms"] < 1e-9


def test_force_length_and_velocity_least_squares(ct09):
    x = np.linspace(-24, 0, 7)
    r = calibrate_force_length(x, gaussian_force_length(x, -8.0, 21.4, 23.0))
    assert r.values == pytest.approx({"g1": -8.0, "g2": 21.4, "P0": 23.0}, rel=1e-6)
    v = np.array([-150.0, -60.0, -5.0, 5.0, 30.0, 90.0])
    T = np.where(v < 0, hill_tension(v, 2.35, 24.35, 23.0), mashima_tension(v, -7.4, 30.3, 23.0))
    r = calibrate_force_velocity(v, T, 23.0)
    assert r.values == pytest.approx({"a0": 2.35, "b0": 24.35, "c0": -7.4, "d0": 30.3}, rel=1e-5)
    with pytest.raises(InputError, match="lengthening"):
        calibrate_force_velocity([-1.0, -2.0, 3.0], [20.0, 19.0, 24.0], 23.0)


@pytest.mark.parametrize("v", [[-150.0, -60.0, 5.0, 90.0], [-150.0, -60.0, -5.0, 5.0, 30.0, 90.0]])
def test_force_velocity_stays_in_eq11s_range(v):
    """Lengthening points above what eq 11 allows with c0 <= 0 (noise, or a muscle stronger in lengthening than
    the Mashima curve) give c0 in (-P0, 0], never an inadmissible set; the closed form falls back to the bounded
    fit and says so."""
    v = np.array(v)
    T = np.where(v < 0, hill_tension(v, 2.35, 24.35, 23.0), mashima_tension(v, 5.0, 30.3, 23.0))
    r = calibrate_force_velocity(v, T, 23.0)
    assert -23.0 < r.values["c0"] <= 0.0 and r.values["d0"] > 0
    assert any("c0 within (-P0, 0]" in n for n in r.notes)
    assert r.values["a0"] == pytest.approx(2.35, rel=1e-5)


def test_kse_refuses_lengthening(ct09):
    t = np.linspace(0, 0.1, 101)
    tr = Trial(trial_id="s", protocol="step", time_s=t, force=np.ones_like(t), force_unit="N",
               length_unit="mm", length=np.linspace(-8, -7, 101))
    with pytest.raises(InputError, match="does not shorten"):
        calibrate_kse(tr, 23.0)
