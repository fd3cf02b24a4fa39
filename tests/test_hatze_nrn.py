"""Hatze's excitation as an NMODL mechanism (HatzeExc): agrees with the exact SciPy integration and drives
Module 3 through the same interface as Kim's Modules 1-2."""

import numpy as np
import pytest

from neuromuscle import InputError, simulate
from neuromuscle.hatze.excitation import simulate_excitation
from neuromuscle.hatze.parameters import load_theta

STIMS_S = np.array([0.05, 0.15, 0.16, 0.2])


@pytest.fixture(scope="module")
def exact():
    return simulate_excitation(STIMS_S, 0.4, load_theta(), dt_s=1e-4)


@pytest.mark.parametrize("method, tol", [("fixed", 2e-3), ("cvode", 1e-4)])
def test_active_state_matches_exact_solution(ct09, exact, method, tol):
    t_s, _, gamma, q = exact
    r = simulate(ct09, STIMS_S * 1000.0, -8.0, 400.0, method=method, record_dt_ms=0.1, excitation="hatze",
                 rtol=1e-8)
    n = min(r.A.size, q.size)
    assert np.max(np.abs(r.A[:n] - q[:n])) < tol * q.max()
    assert np.max(np.abs(r.atil[:n] - gamma[:n])) < 2 * tol * gamma.max()  # gamma is recorded as atil
    assert r.settings["excitation"] == "hatze" and r.ca_M == {}


def test_hatze_activation_drives_module_3(ct09):
    spikes = np.arange(100.0, 600.0, 50.0)
    fixed = simulate(ct09, spikes, -8.0, 800.0, excitation="hatze")
    cv = simulate(ct09, spikes, -8.0, 800.0, excitation="hatze", method="cvode")
    assert fixed.force_N.max() > 0.3 * ct09["P0"]
    n = min(fixed.force_N.size, cv.force_N.size)
    assert np.max(np.abs(fixed.force_N[:n] - cv.force_N[:n])) < 0.005 * cv.force_N.max()
    # the same spikes through Kim's Modules 1-2 give a different activation
    kim = simulate(ct09, spikes, -8.0, 800.0)
    assert abs(kim.force_N.max() - fixed.force_N.max()) > 0.01


def test_overlapping_pulses_and_unknown_model_are_refused(ct09):
    with pytest.raises(InputError, match="may not overlap"):
        simulate(ct09, [100.0, 100.5], -8.0, 300.0, excitation="hatze")
    with pytest.raises(InputError, match="excitation must be"):
        simulate(ct09, [100.0], -8.0, 300.0, excitation="huxley")
