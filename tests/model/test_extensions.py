"""Model extensions: found by name, wired to their port, off (or neutral) bit-identical to the baseline, and the
NMODL checked against an independent SciPy integration of the same equations (fixed step and CVODE)."""

import numpy as np
import pytest

from neuromuscle import InputError, MuscleUnit, simulate
from neuromuscle.model.extensions import registry
from neuromuscle.protocols import constant_rate
from neuromuscle.reference import reference_simulate


def test_catalogue_is_found_by_scanning_the_folder():
    cat = registry()
    assert "fatigue" in cat
    assert cat["fatigue"].targets == {"ca.release_gain": "gain", "force.capacity_gain": "cgain"}


def test_unknown_extension_and_bad_parameters_are_refused(ct09):
    with pytest.raises(InputError, match="unknown extension 'fatgue'"):
        MuscleUnit(ct09, extensions={"fatgue": {}})
    with pytest.raises(InputError, match="'k' = 0.5 1 is outside its physiological range"):
        MuscleUnit(ct09, extensions={"fatigue": {"k": 0.5}})
    with pytest.raises(InputError, match="unknown parameter"):
        MuscleUnit(ct09, extensions={"fatigue": {"kk": 0.1}})


MOVEMENT_ONLY = {"lengthening_below_optimum", "movement_induced_depression", "force_enhancement_after_stretch",
                 "force_depression_after_shortening"}


@pytest.mark.parametrize("name", sorted(MOVEMENT_ONLY))
def test_an_extension_that_needs_movement_leaves_a_constant_length_alone(ct09, name):
    """``needs_movement``: at a constant length the force is the baseline's bit for bit at any of the extension's
    values (the screening relies on it and does not simulate such trials), and a movement changes it."""
    from neuromuscle.protocols import isokinetic_ramp

    ext = registry()[name]
    assert {n for n, e in registry().items() if e.needs_movement()} == MOVEMENT_ONLY
    values = {p.name: p.upper if p.neutral is not None else p.default for p in ext.parameters}
    spikes = constant_rate(40, 900.0, start_ms=50.0)
    for length in (-8.0, -14.0):
        base = simulate(ct09, spikes, length, 1000.0)
        on = simulate(ct09, spikes, length, 1000.0, extensions={name: values})
        np.testing.assert_array_equal(on.force_N, base.force_N)
    lengths = (-6.0, -14.0) if ext.after < 0 else (-14.0, -6.0)  # shortening for depression, else a stretch
    ramp = isokinetic_ramp(*lengths, 40.0, 300.0, 1000.0)
    moved = simulate(ct09, spikes, ramp, 1000.0, extensions={name: values})
    assert np.max(np.abs(moved.force_N - simulate(ct09, spikes, ramp, 1000.0).force_N)) > 1e-3 * base.force_N.max()


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_neutral_extension_reproduces_the_baseline(ct09, method):
    """Fixed step: bit-identical.  CVODE: the extension's state joins the error norm and moves the adaptive
    steps, so the traces agree to the integrator's tolerance, not bit for bit (off, absent, is bit-identical)."""
    spikes = constant_rate(50, 600.0, start_ms=50.0)
    base = simulate(ct09, spikes, -8.0, 800.0, method=method)
    neutral = simulate(ct09, spikes, -8.0, 800.0, method=method, extensions={"fatigue": {"k": 0.0}})
    if method == "fixed":
        np.testing.assert_array_equal(base.force_N, neutral.force_N)
    else:
        assert np.max(np.abs(base.force_N - neutral.force_N)) < 1e-4 * base.force_N.max()
    assert neutral.settings["extensions"] == ["fatigue"]


@pytest.fixture(scope="module")
def fatigue_twin(ct09):
    """The SciPy twin of a 60 Hz train under fatigue (~20 s), shared by both integrators' tests."""
    spikes = constant_rate(60, 1400.0, start_ms=50.0)
    values = {"k": 0.03, "tau_rec": 3000.0, "kc": 0.5}
    twin = registry()["fatigue"].reference_modulation(values, spikes)
    return spikes, values, twin, reference_simulate(ct09, spikes, -8.0, 1500.0, record_dt_ms=0.5, modulation=twin)


@pytest.mark.parametrize("method", ["fixed", "cvode"])
def test_fatigue_matches_its_scipy_twin(ct09, fatigue_twin, method):
    spikes, values, twin, ref = fatigue_twin
    sim = simulate(ct09, spikes, -8.0, 1500.0, method=method, record_dt_ms=0.5,
                   extensions={"fatigue": values}, record=("force.F", "fatigue.gain", "fatigue.cgain"))
    n = min(ref.t_ms.size, sim.t_ms.size)
    err = sim.force_N[:n] - ref.force_N[:n]
    # the baseline's own tolerances against SciPy (tests/sim/test_accuracy.py: random trains)
    assert np.sqrt(np.mean(err**2)) < 0.005 * ref.force_N.max(), method
    assert np.max(np.abs(err)) < 0.015 * ref.force_N.max(), method
    gain_ref = np.array([twin["release_gain"](t) for t in sim.t_ms[:n]])
    np.testing.assert_allclose(sim["fatigue.gain"][:n], gain_ref, atol=2e-3)
    cgain_ref = np.array([twin["capacity_gain"](t) for t in sim.t_ms[:n]])
    np.testing.assert_allclose(sim["fatigue.cgain"][:n], cgain_ref, atol=1e-3)
    # and it is an effect: the late plateau sits clearly below the unfatigued one
    base = simulate(ct09, spikes, -8.0, 1500.0, method=method, record_dt_ms=0.5)
    late = slice(int(1300 / 0.5), int(1450 / 0.5))
    assert sim.force_N[late].mean() < 0.95 * base.force_N[late].mean()


def test_fatigue_lowers_a_saturated_tetanus_through_the_force_capacity(ct09):
    """At 100 Hz activation saturates: the release loss alone leaves the tetanus's late plateau nearly where it
    was, the capacity loss lowers it by about kc D."""
    spikes = constant_rate(100, 1400.0, start_ms=50.0)
    late = slice(int(1300 / 0.5), int(1450 / 0.5))
    plateau = {kc: simulate(ct09, spikes, -8.0, 1500.0, record_dt_ms=0.5, record=("force.F", "fatigue.gain"),
                            extensions={"fatigue": {"k": 0.01, "tau_rec": 10_000.0, "kc": kc}})
               for kc in (0.0, 1.0)}
    base = simulate(ct09, spikes, -8.0, 1500.0, record_dt_ms=0.5).force_N[late].mean()
    release_only, both = (plateau[kc].force_N[late].mean() for kc in (0.0, 1.0))
    depletion = 1.0 - plateau[1.0]["fatigue.gain"][late].mean()
    assert depletion > 0.5
    assert release_only > 0.9 * base
    assert both == pytest.approx(release_only * (1.0 - depletion), rel=0.1)


def test_extension_from_the_command_line(tmp_path, capsys):
    from neuromuscle.cli import main

    out = tmp_path / "f.h5"
    assert main(["simulate", "--protocol", "train", "--rate-hz", "80", "--train-ms", "600", "--duration-ms", "900",
                 "--extension", "fatigue:k=0.05,tau_rec=2000", "--out", str(out)]) == 0
    assert main(["simulate", "--extension", "fatigue:k", "--out", str(tmp_path / "g.h5")]) == 2
    assert "expected NAME[:PARAM=VALUE" in capsys.readouterr().err
