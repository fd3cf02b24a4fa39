"""The stretch-reflex loop (neuromuscle.pool.reflex): a stretch with the loop intact makes more force and more
discharge than with the dorsal roots cut, the Ib pathway reaches the motoneurons through its interneurons, the
example's afferent rates follow Prochazka's equations, CoreNEURON and two MPI ranks give NEURON's one-rank run;
bad definitions are refused by name."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from neuromuscle import InputError, load_parameters
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.mpi import mpi_available, mpiexec_command
from neuromuscle.pool.reflex import ReflexDefinition, attach_reflex
from neuromuscle.protocols.lengths import isokinetic_ramp
from neuromuscle.sim import Simulator

NETWORKS = Path(__file__).resolve().parents[2] / "networks"
LENGTH = isokinetic_ramp(-10.0, -4.0, 30.0, 100.0, 700.0)


def _definition(n=4):
    return PoolDefinition(n, load_parameters("CT09"), smallest_p0_N=1.0, p0_range=3.0, type_fractions=(1.0, 0, 0),
                          max_size=0.2, axon_length_mm=150.0, neuromodulation=1.0)


def _run(reflex, engine="neuron", tonic_uS=0.003, n=4):
    with Pool(_definition(n), length=LENGTH, engine=engine) as pool:
        r = attach_reflex(pool, reflex)
        pool.drive_synaptic([0.0, 700.0], [tonic_uS, tonic_uS])
        result = pool.run(700.0, Simulator(method="fixed", dt_ms=0.025, engine=engine))
        spikes = r.spikes()
        r.destroy()
    return result, spikes


def test_the_loop_makes_more_force_than_cut_dorsal_roots():
    intact, aff_intact = _run(ReflexDefinition(n_ia=6, n_ib=2, xref_mm=-10.0))
    cut, aff_cut = _run(ReflexDefinition(n_ia=6, n_ib=2, xref_mm=-10.0, cut_dorsal_roots=True))
    # the afferents read the same stretch either way: the same spikes
    assert all(np.array_equal(a, b) for a, b in zip(aff_intact["Ia"], aff_cut["Ia"]))
    assert sum(s.size for s in aff_intact["Ia"]) > 6 * 0.7 * 80
    hold = intact.t_ms > 400.0
    assert intact.pool_force_N[hold].mean() > 1.5 * cut.pool_force_N[hold].mean() + 0.1
    assert sum(s.size for s in intact.spikes_ms) > sum(s.size for s in cut.spikes_ms) + 5
    assert all(s.size == 0 for s in aff_cut["Ib_interneurons"])


def test_ib_inhibition_lowers_the_discharge():
    """The same Ia input, with and without the Ib interneurons' inhibition."""
    excite_only, _ = _run(ReflexDefinition(n_ia=6, n_ib=2, xref_mm=-10.0, ib_weight_uS=0.0))
    inhibited, aff = _run(ReflexDefinition(n_ia=6, n_ib=2, xref_mm=-10.0, ib_weight_uS=0.5))
    assert sum(s.size for s in aff["Ib_interneurons"]) > 10
    assert sum(s.size for s in inhibited.spikes_ms) < sum(s.size for s in excite_only.spikes_ms)


def test_group_ii_excitation_raises_the_discharge_and_weight_0_leaves_it_unconnected():
    """Group II afferents with weight 0 change nothing (bit for bit against no group II afferents); with a weight,
    after their longer delay, they raise the discharge."""
    none, _ = _run(ReflexDefinition(n_ia=6, n_ii=0, n_ib=2, xref_mm=-10.0))
    off, aff = _run(ReflexDefinition(n_ia=6, n_ii=4, n_ib=2, xref_mm=-10.0, ii_weight_uS=0.0))
    on, _ = _run(ReflexDefinition(n_ia=6, n_ii=4, n_ib=2, xref_mm=-10.0, ii_weight_uS=0.004))
    assert sum(s.size for s in aff["II"]) > 4 * 0.7 * 80
    assert all(np.array_equal(a, b) for a, b in zip(none.spikes_ms, off.spikes_ms))
    np.testing.assert_array_equal(none.unit_force_N, off.unit_force_N)
    assert sum(s.size for s in on.spikes_ms) > sum(s.size for s in off.spikes_ms) + 5


def test_ia_weights_go_by_motoneuron_type():
    """The test pool is all type S: Ia weights on FR and FF alone change nothing, on S they raise the discharge."""
    cut, _ = _run(ReflexDefinition(n_ia=6, n_ib=0, xref_mm=-10.0, cut_dorsal_roots=True))
    others, _ = _run(ReflexDefinition(n_ia=6, n_ib=0, xref_mm=-10.0, ia_weight_uS={"S": 0.0, "FR": 0.01, "FF": 0.01}))
    s_only, _ = _run(ReflexDefinition(n_ia=6, n_ib=0, xref_mm=-10.0, ia_weight_uS={"S": 0.004, "FR": 0.0, "FF": 0.0}))
    assert all(np.array_equal(a, b) for a, b in zip(cut.spikes_ms, others.spikes_ms))
    assert sum(s.size for s in s_only.spikes_ms) > sum(s.size for s in cut.spikes_ms) + 5


def test_cvode_runs_the_loop_as_the_fixed_step_does():
    """The afferents sample by self-events, which CVODE steps to: the same discharge, the force within 5 %."""
    reflex = ReflexDefinition(n_ia=6, n_ib=2, xref_mm=-10.0)
    results = []
    for sim in (Simulator(method="fixed", dt_ms=0.025), Simulator(method="cvode")):
        with Pool(_definition(4), length=LENGTH) as pool:
            attach_reflex(pool, reflex)
            pool.drive_synaptic([0.0, 700.0], [0.003, 0.003])
            results.append(pool.run(700.0, sim))
    fixed, cvode = results
    assert [s.size for s in fixed.spikes_ms] == [s.size for s in cvode.spikes_ms] and fixed.spikes_ms[0].size > 2
    assert cvode.pool_force_N[-1] == pytest.approx(fixed.pool_force_N[-1], rel=0.05)


def test_coreneuron_gives_neurons_reflex_bit_for_bit():
    reflex = ReflexDefinition(n_ia=3, n_ii=1, n_ib=2, xref_mm=-10.0)
    a, aff_a = _run(reflex, n=2)
    b, aff_b = _run(reflex, engine="coreneuron", n=2)
    assert sum(s.size for s in a.spikes_ms) > 0
    assert all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms))
    np.testing.assert_array_equal(a.unit_force_N, b.unit_force_N)
    for kind in aff_a:
        assert all(np.array_equal(x, y) for x, y in zip(aff_a[kind], aff_b[kind])), kind


@pytest.mark.parametrize("kwargs, message", [
    ({"n_ia": -1}, "n_ia must be an integer >= 0"),
    ({"ia_weight_uS": {"S": 0.01}}, "one weight for each motoneuron type"),
    ({"ia_delay_ms": 0.0}, "ia_delay_ms"),
    ({"fusimotor": -5.0}, "fusimotor"),
    ({"ii_weight_uS": -0.001}, "ii_weight_uS"),
    ({"ii_delay_ms": 0.0}, "ii_delay_ms"),
])
def test_bad_definitions_are_refused(kwargs, message):
    with pytest.raises(InputError, match=message):
        ReflexDefinition(**kwargs)


def test_the_example_refuses_a_run_without_a_hold(tmp_path, network_script):
    with pytest.raises(InputError, match="the hold window needs the run to last at least 900 ms"):
        network_script("stretch_reflex").main(["--out", str(tmp_path / "out"), "--duration-ms", "600"])


def test_a_reflex_on_a_pool_without_motoneurons_is_refused():
    with Pool(_definition(2), length=-8.0, motoneurons=False) as pool:
        with pytest.raises(InputError, match="has no motoneurons: a reflex needs them"):
            attach_reflex(pool)


def test_a_reflex_after_the_drive_is_refused():
    with Pool(_definition(2), length=-8.0) as pool:
        pool.drive_synaptic([0.0, 10.0], [0.0, 0.0])
        with pytest.raises(InputError, match="attach the reflex before the drive"):
            attach_reflex(pool)


def test_the_example_compares_intact_and_cut_and_its_rates_follow_the_equations(tmp_path, network_script):
    s = network_script("stretch_reflex").main(["--out", str(tmp_path / "out"), "--units", "6", "--duration-ms", "1000"])
    assert json.loads((tmp_path / "out" / "stretch_reflex.json").read_text()) == s
    assert (tmp_path / "out" / "stretch_reflex.png").stat().st_size > 10_000
    assert s["intact"]["force_N"]["hold"] > s["cut"]["force_N"]["hold"] and s["reflex_force_gain"] > 1.0
    for kind in ("Ia", "II"):
        for window, expected in s["equation_rate_hz"][kind].items():
            assert s["afferent_rate_hz"][kind][window] == pytest.approx(expected, abs=3.0), (kind, window)
    ia = s["afferent_rate_hz"]["Ia"]
    assert ia["ramp"] > ia["hold"] > ia["rest"]        # velocity, then length
    assert s["afferent_rate_hz"]["Ib"]["hold"] > s["afferent_rate_hz"]["Ib"]["rest"]
    # the figures set beside the recorded ones: Ia's dynamic index is the velocity term at 30 mm/s, the hold's
    # rate per mm the stretch coefficients; group II has no dynamic index
    fig = s["afferent_figures"]
    assert fig["Ia"]["dynamic_index_hz"] == pytest.approx(4.3 * 30.0 ** 0.6, abs=3.0)
    assert fig["Ia"]["hold_per_mm_hz"] == pytest.approx(2.0, abs=0.3)
    assert fig["II"]["hold_per_mm_hz"] == pytest.approx(13.5, abs=0.5)
    assert abs(fig["II"]["dynamic_index_hz"]) < 5.0
    assert all(p["source"] and p["published"] for p in s["published"])


@pytest.mark.skipif(not mpi_available(), reason="the mpi extra is not installed")
def test_two_ranks_give_the_reflex_of_one(tmp_path):
    args = [str(NETWORKS / "stretch_reflex.py"), "--units", "4", "--duration-ms", "1000"]
    out = {}
    for n in (1, 2):
        cmd = mpiexec_command(n, [*args, "--out", str(tmp_path / f"r{n}")])
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        out[n] = json.loads((tmp_path / f"r{n}" / "stretch_reflex.json").read_text())
    assert (out[1].pop("ranks"), out[2].pop("ranks")) == (1, 2)
    assert out[1] == out[2] and out[1]["reflex_force_gain"] > 1.0
