"""The length and movement side of the catalogue: eq 18 selectable alone by name (a switch extension of KimCa),
a Ca2+ sensitivity falling on eq 19's time course, on a movement clock that runs down at rest
(mod/ExtMovement.mod, KimAct's C1_shift port; the paper's eqs 19-20 stay the baseline's own switches), the release
loss while lengthening below the optimum
(mod/ExtLengthening.mod), and the history-dependent element (force enhancement after stretch, force depression after
shortening) driving KimForce's force_offset.  Off or neutral: bit-identical to the baseline in fixed step; on:
the NMODL (fixed step and CVODE) against the SciPy twin under movement; the effects have their stated sign."""

from pathlib import Path

import numpy as np
import pytest

from neuromuscle import InputError, kim_excitation, simulate
from neuromuscle.model.extensions import SwitchExtension, registry
from neuromuscle.protocols import constant_rate, isokinetic_ramp, random_length
from neuromuscle.reference import reference_simulate

pytestmark = pytest.mark.heavy(cost_s=85)

FE, FD = "force_enhancement_after_stretch", "force_depression_after_shortening"
LDA, MID, LBO = "length_dependent_activation", "movement_induced_depression", "lengthening_below_optimum"
BASELINE = Path(__file__).resolve().parents[1] / "baselines" / "unit_traces.npz"


def _protocols():
    """600 ms, as in the tests of Module 3 (tests/sim/test_robust.py), short enough for the SciPy twin."""
    return {
        "lengthening_ramp": isokinetic_ramp(-12.0, -4.0, 40.0, 150.0, 600.0, sample_ms=1.0),
        "stretch_hold": isokinetic_ramp(-12.0, -6.0, 100.0, 200.0, 600.0, sample_ms=1.0),
        "shortening_hold": isokinetic_ramp(-4.0, -10.0, 100.0, 200.0, 600.0, sample_ms=1.0),
        "random_length": random_length(600.0, seed=4, sample_rate_hz=100.0, numtaps=21),
    }


SPIKES = constant_rate(30, 500.0, start_ms=50.0)

# each extension: its values (not neutral), added to the baseline a diagnosis calibrates (eqs 18-20 off), and
# the switches that turn the same equation on in the twin
CASES = {
    LDA: ({"phi1": 0.02, "phi2": 1.16, "phi3": 0.012, "phi4": 1.096}, dict(length_compensation=True)),
    MID: ({"k": 0.1, "t50": 100.0, "width": 100.0, "trec": 500.0, "v0": 3.0}, {}),
    LBO: ({"k": 0.5, "v0": 20.0}, {}),
    FE: ({"k": 0.3, "L": 3.0, "tau": 1000.0}, {}),
    FD: ({"k": 0.3, "L": 3.0, "tau": 1000.0}, {}),
}


def test_the_five_are_found_by_name_with_neutral_values():
    cat = registry()
    assert issubclass(cat[LDA], SwitchExtension) and cat[LDA].suffix == ""
    assert {p.name: p.neutral for p in cat[LDA].parameters} == {"phi1": 0.0, "phi2": 1.0, "phi3": 0.0, "phi4": 1.0}
    # eq 18's parameters are the baseline's own: a fit of the extension varies kim_m1.phi1 ...
    assert cat[LDA].qualified("phi1") == "kim_m1.phi1"
    # the movement clock that runs down at rest is a mechanism of its own, with eq 19's time course as its own
    assert not issubclass(cat[MID], SwitchExtension) and cat[MID].suffix == "ExtMovement"
    assert {p.name: p.neutral for p in cat[MID].parameters} == {"k": 0.0, "t50": None, "width": None,
                                                               "trec": None, "v0": None}
    assert cat[MID].targets == {"act.C1_shift": "shift"} and cat[MID].qualified("k") == f"{MID}.k"
    t50, width = cat[MID].param("t50"), cat[MID].param("width")
    assert (t50.default, t50.lower, t50.upper, width.default, width.lower) == (400.0, 0.0, 5000.0, 160.0, 1.0)
    assert not issubclass(cat[LBO], SwitchExtension) and cat[LBO].suffix == "ExtLengthening"
    assert {p.name: p.neutral for p in cat[LBO].parameters} == {"k": 0.0, "v0": None}
    assert cat[LBO].targets == {"ca.release_gain": "gain"} and cat[LBO].qualified("k") == "lengthening_below_optimum.k"
    for name in (FE, FD):
        assert cat[name].targets == {"force.force_offset": "offset"}
        assert {p.name: p.neutral for p in cat[name].parameters} == {"k": 0.0, "L": None, "tau": None}


def _fixed(ct09, trace, **kw):
    return simulate(ct09, SPIKES, trace, 600.0, record_dt_ms=0.5, **kw)


@pytest.mark.parametrize("name, neutral, eq_off", [
    (LDA, {"phi1": 0.0, "phi2": 1.0, "phi3": 0.0, "phi4": 1.0}, dict(length_compensation=False)),
    (MID, {"k": 0.0}, {}),
    (LBO, {"k": 0.0}, {}),
    (FE, {"k": 0.0}, {}),
    (FD, {"k": 0.0}, {}),
])
def test_neutral_extension_is_bit_identical_to_the_baseline_under_movement(ct09, name, neutral, eq_off):
    trace = _protocols()["random_length"]
    base = _fixed(ct09, trace, excitation=kim_excitation(**eq_off))
    ext = _fixed(ct09, trace, excitation=kim_excitation(**eq_off), extensions={name: neutral})
    np.testing.assert_array_equal(base.force_N, ext.force_N)
    assert ext.settings["extensions"] == [name]


def test_neutral_extensions_reproduce_the_stored_baseline_traces():
    """tests/baselines/unit_traces.npz (see tests/model/test_ports_off_is_baseline.py) still matches with a
    neutral extension added: eq 18 neutral on the CT95 case without eq 18, the history element on the random
    length case with the movement compensation."""
    from test_ports_off_is_baseline import cases  # tests/model is on the path (pytest's rootdir-relative import)

    ref = np.load(BASELINE)
    for case, ext in (("ct95_train40_nolencomp", {LDA: {"phi1": 0.0, "phi2": 1.0, "phi3": 0.0, "phi4": 1.0}}),
                      ("train20_randlen_movcomp", {FE: {"k": 0.0}}), ("train20_randlen_movcomp", {FD: {"k": 0.0}})):
        r = simulate(**cases()[case], extensions=ext)
        old = ref[f"{case}/force.F"]
        n = min(old.size, r.force_N.size)
        np.testing.assert_array_equal(r.force_N[:n], old[:n], err_msg=f"{case} + {list(ext)}")


def _eq20_only(**kw):
    """kim_excitation with eq 20 (the lengthening divisor) alone switched on in KimAct."""
    exc = kim_excitation(**kw)
    exc["act"].lengthening_divisor = True
    return exc


def test_selected_equations_equal_the_seed_switches(ct09):
    """Eq 18 selected by name is kim_excitation(length_compensation=True) and turns on nothing else; the movement
    extension lowers A during movement without switching on the paper's eqs 19-20 (they stay KimAct's own)."""
    trace = _protocols()["lengthening_ramp"]
    lencomp = _fixed(ct09, trace, excitation=kim_excitation(length_compensation=True))
    lda = _fixed(ct09, trace, excitation=kim_excitation(length_compensation=False), extensions={LDA: {}})
    np.testing.assert_array_equal(lencomp.force_N, lda.force_N)
    # already on: selecting it changes nothing but the parameters given
    again = _fixed(ct09, trace, excitation=kim_excitation(length_compensation=True), extensions={LDA: {}})
    np.testing.assert_array_equal(lencomp.force_N, again.force_N)
    phi = {"phi1": 0.02, "phi2": 1.16}
    given = _fixed(ct09, trace, extensions={LDA: phi})
    np.testing.assert_array_equal(given.force_N, _fixed(ct09.with_values(phi), trace).force_N)

    base = _fixed(ct09, trace, record=("force.F", "act.alpha_t", "act.A"))
    mid = _fixed(ct09, trace, extensions={MID: {}}, record=("force.F", "act.alpha_t", "act.A"))
    lbo = _fixed(ct09, trace, excitation=_eq20_only(), record=("force.F", "act.alpha_t", "act.A"))
    assert np.all(mid["act.alpha_t"] == 2.0) and np.all(lbo["act.alpha_t"] == 2.0)  # eq 19 in neither
    assert mid.settings["model"]["act"] == {"component": "KimActivation", "movement_compensation": False,
                                            "eq19_movement_depression": False, "eq20_lengthening_divisor": False}
    moving = base.t_ms > 160.0
    assert np.all(mid.A[moving] <= base.A[moving] + 1e-15) and np.all(lbo.A[moving] <= base.A[moving] + 1e-15)
    assert mid.A[moving].mean() < base.A[moving].mean() - 1e-3 and not np.array_equal(mid.A, lbo.A)


@pytest.mark.parametrize("protocol", list(_protocols()))
@pytest.mark.parametrize("name", list(CASES))
def test_extension_matches_its_scipy_twin_under_movement(ct09, name, protocol):
    values, twin_switches = CASES[name]
    trace = _protocols()[protocol]
    cls = registry()[name]
    if issubclass(cls, SwitchExtension):
        ref = reference_simulate(ct09.with_values(values), SPIKES, trace, 600.0, record_dt_ms=0.5, rtol=1e-6,
                                 **{"length_compensation": False, **twin_switches})
    else:
        ref = reference_simulate(ct09, SPIKES, trace, 600.0, record_dt_ms=0.5, rtol=1e-6, length_compensation=False,
                                 modulation=cls.reference_modulation(values, SPIKES))
    scale = ref.force_N.max()
    for method in ("fixed", "cvode"):
        sim = simulate(ct09, SPIKES, trace, 600.0, method=method, record_dt_ms=0.5,
                       excitation=kim_excitation(length_compensation=False), extensions={name: values})
        n = min(sim.t_ms.size, ref.t_ms.size)
        err = sim.force_N[:n] - ref.force_N[:n]
        # the baseline's own tolerances against SciPy under movement (tests/sim/test_robust.py, test_accuracy.py)
        assert np.sqrt(np.mean(err**2)) < 0.002 * scale, (method, np.sqrt(np.mean(err**2)) / scale)
        assert np.max(np.abs(err)) < 0.005 * scale, (method, np.max(np.abs(err)) / scale)
    # the extension does something on this protocol, except what its sign excludes: no enhancement without
    # lengthening, no depression without shortening, no release loss without lengthening
    plain = simulate(ct09, SPIKES, trace, 600.0, record_dt_ms=0.5, excitation=kim_excitation(length_compensation=False))
    effect = np.max(np.abs(plain.force_N[:n] - ref.force_N[:n])) / scale
    if (name, protocol) in {(FE, "shortening_hold"), (FD, "lengthening_ramp"), (FD, "stretch_hold"),
                            (LBO, "shortening_hold")}:
        assert effect < 0.005, effect
    else:
        assert effect > 0.01, effect


def _hold_force(ct09, trace, x_end, ext):
    spikes = constant_rate(40, 1000.0, start_ms=50.0)
    late = slice(int(850 / 0.5), int(1000 / 0.5))
    runs = [simulate(ct09, spikes, t, 1050.0, record_dt_ms=0.5, extensions=e).force_N[late].mean()
            for t, e in ((trace, ext), (trace, None), (x_end, None))]
    return runs  # moved with the extension, moved baseline, isometric at the final length


def test_force_enhancement_stays_above_the_isometric_force_after_an_active_stretch(ct09):
    stretch = isokinetic_ramp(-12.0, -6.0, 50.0, 300.0, 1050.0, sample_ms=1.0)  # stretch 300-420 ms, hold
    fe, base, iso = _hold_force(ct09, stretch, -6.0, {FE: {}})
    assert abs(base - iso) < 0.01 * iso  # the baseline forgets the stretch
    assert fe > 1.03 * iso, (fe, iso)
    shortening = isokinetic_ramp(-2.0, -6.0, 50.0, 300.0, 1050.0, sample_ms=1.0)
    fe_short, _, iso = _hold_force(ct09, shortening, -6.0, {FE: {}})
    assert fe_short == pytest.approx(iso, rel=0.01)  # shortening does not enhance


def test_force_depression_stays_below_the_isometric_force_after_active_shortening(ct09):
    shortening = isokinetic_ramp(-2.0, -8.0, 50.0, 300.0, 1050.0, sample_ms=1.0)
    fd, base, iso = _hold_force(ct09, shortening, -8.0, {FD: {}})
    assert abs(base - iso) < 0.01 * iso
    assert fd < 0.97 * iso, (fd, iso)
    stretch = isokinetic_ramp(-14.0, -8.0, 50.0, 300.0, 1050.0, sample_ms=1.0)
    fd_stretch, _, iso = _hold_force(ct09, stretch, -8.0, {FD: {}})
    assert fd_stretch == pytest.approx(iso, rel=0.01)  # stretching does not depress


def test_history_element_leaves_isometric_trials_untouched(ct09):
    spikes = constant_rate(40, 400.0, start_ms=50.0)
    base = simulate(ct09, spikes, -8.0, 500.0)
    for name in (FE, FD):
        r = simulate(ct09, spikes, -8.0, 500.0, extensions={name: {"k": 1.0}}, record=("force.F", f"{name}.D"))
        np.testing.assert_array_equal(base.force_N, r.force_N)
        assert np.all(r[f"{name}.D"] == 0.0)


def test_lengthening_release_loss_acts_below_the_optimum_while_lengthening_and_most_at_low_rates(ct09):
    """The release loss: nothing in isometric trials, in shortening or above the optimum; while lengthening below
    the optimum, a relative force loss larger at 10 Hz than in a 100 Hz tetanus (the paper's <= 20 Hz)."""
    below = isokinetic_ramp(-16.0, -10.0, 20.0, 200.0, 700.0, sample_ms=1.0)  # ct09 g1 = -8 mm
    above = isokinetic_ramp(-6.0, 0.0, 20.0, 200.0, 700.0, sample_ms=1.0)
    shortening = isokinetic_ramp(-10.0, -16.0, 20.0, 200.0, 700.0, sample_ms=1.0)
    ext = {LBO: {"k": 0.5, "v0": 10.0}}
    loss = {}
    for rate in (10, 100):
        spikes = constant_rate(rate, 650.0, start_ms=20.0)
        for name, trace in (("below", below), ("above", above), ("shortening", shortening), ("iso", -12.0)):
            base = simulate(ct09, spikes, trace, 700.0, record_dt_ms=0.5)
            r = simulate(ct09, spikes, trace, 700.0, record_dt_ms=0.5, extensions=ext)
            if name == "below":
                ramp = (base.t_ms >= 250.0) & (base.t_ms <= 500.0)
                loss[rate] = 1.0 - r.force_N[ramp].mean() / base.force_N[ramp].mean()
            else:
                np.testing.assert_array_equal(r.force_N, base.force_N, err_msg=f"{name} at {rate} Hz")
    assert loss[10] > 0.05 and loss[10] > 2.0 * loss[100], loss


def test_bad_selections_are_refused(ct09):
    with pytest.raises(InputError, match="switches an equation of KimCalcium"):
        simulate(ct09, SPIKES, -8.0, 100.0, excitation="hatze", extensions={LDA: {}})
    with pytest.raises(InputError, match="'k' = -1 1 is outside its physiological range"):
        simulate(ct09, SPIKES, -8.0, 100.0, extensions={LBO: {"k": -1.0}})
    with pytest.raises(InputError, match="'k' = 2 1 is outside"):
        simulate(ct09, SPIKES, -8.0, 100.0, extensions={FD: {"k": 2.0}})
    with pytest.raises(InputError, match="unknown parameter"):
        simulate(ct09, SPIKES, -8.0, 100.0, extensions={MID: {"C3": 50.0}})  # not eq 19's


def test_length_extensions_from_the_command_line(tmp_path):
    from neuromuscle.cli import main

    common = ["simulate", "--protocol", "train", "--rate-hz", "40", "--start-ms", "50", "--train-ms", "500",
              "--duration-ms", "600", "--length", "ramp", "--xm-mm", "-12", "--ramp-mm", "6",
              "--velocity-mm-s", "50", "--no-length-compensation"]
    assert main([*common, "--extension", f"{FE}:k=0.4,L=3", "--extension", f"{LDA}:phi1=0.02",
                 "--extension", MID, "--out", str(tmp_path / "a.h5")]) == 0


def test_movement_depression_deepens_while_moving_and_recovers_at_rest(ct09):
    """The movement clock counts time spent moving and runs down at rest with trec: after a 120 ms stretch and a
    2 s hold, the force is back at the baseline's with trec = 100 ms and still depressed with trec = 1e5 ms (the
    paper's clock, which never stops); an isometric trial is untouched whatever the values (the clock stays 0)."""
    stretch = isokinetic_ramp(-12.0, -6.0, 50.0, 300.0, 2500.0, sample_ms=1.0)  # moves 300-420 ms, then held
    spikes = constant_rate(20, 2400.0, start_ms=50.0)
    late = slice(int(2200 / 0.5), int(2450 / 0.5))
    during = slice(int(380 / 0.5), int(430 / 0.5))
    base = simulate(ct09, spikes, stretch, 2500.0, record_dt_ms=0.5)
    runs = {trec: simulate(ct09, spikes, stretch, 2500.0, record_dt_ms=0.5, record=("force.F", f"{MID}.c"),
                           extensions={MID: {"k": 0.1, "t50": 50.0, "width": 50.0, "trec": trec, "v0": 2.0}})
            for trec in (100.0, 1e5)}
    for r in runs.values():  # depressed by the movement's end
        assert r.force_N[during].mean() < 0.9 * base.force_N[during].mean()
    assert runs[100.0].force_N[late].mean() == pytest.approx(base.force_N[late].mean(), rel=0.005)
    assert runs[1e5].force_N[late].mean() < 0.8 * base.force_N[late].mean()
    clock = runs[100.0][f"{MID}.c"]
    assert clock.max() == pytest.approx(120.0, rel=0.05) and clock[late].max() < 1e-3  # ~1 ms/ms while moving
    iso = simulate(ct09, spikes, -8.0, 2500.0, record_dt_ms=0.5, record=("force.F", f"{MID}.c"),
                   extensions={MID: {"k": 0.5, "t50": 0.0, "width": 1.0, "trec": 20.0, "v0": 0.5}})
    np.testing.assert_array_equal(iso.force_N, simulate(ct09, spikes, -8.0, 2500.0, record_dt_ms=0.5).force_N)
    assert np.all(iso[f"{MID}.c"] == 0.0)
