"""Pools under CoreNEURON: the same spikes, unit forces and pool force as under NEURON, bit for bit (a current ramp
with any muscle model and either channel set, Poisson input, recorded discharges, the synaptic drive at dt 0.05
ms in either of CoreNEURON's layouts, each cell's synaptic noise), also when the run is made in chunks to bound the
every-step recordings, and on two MPI ranks; a simulator of the other engine is refused.  NEURON's
threshold-crossing interpolation (``CVode.condition_order(2)``) changes nothing under either engine's fixed step.
Under Crank-Nicolson (secondorder 2) the engines give the same spikes and forces (to rounding with the three muscle
mechanisms)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from neuromuscle import InputError
from neuromuscle.pool import PoolDefinition, load_pool_result
from neuromuscle.pool import pool as pool_module
from neuromuscle.pool.mpi import mpi_available, mpiexec_command
from neuromuscle.pool.pool import Pool
from neuromuscle.sim import Simulator


def _run(definition, engine, drive="ramp", duration_ms=300.0, secondorder=0):
    with Pool(definition, length=-8.0, engine=engine, motoneurons=drive != "discharges") as pool:
        if drive == "ramp":
            pool.drive_current_ramp([0.0, duration_ms], [0.0, 20.0])
        elif drive == "poisson":
            pool.drive_poisson(400.0, 0.15, seed=1)
        else:
            pool.drive_discharges([list(10.0 + 30.0 * np.arange(9) + i) for i in range(definition.n_units)],
                                  duration_ms)
        return pool.run(duration_ms, Simulator(engine=engine, secondorder=secondorder) if secondorder else None)


def _assert_same(a, b):
    assert sum(s.size for s in a.spikes_ms) > 10 and a.pool_force_N.max() > 0.1
    assert all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms))
    np.testing.assert_array_equal(b.unit_force_N, a.unit_force_N)


@pytest.mark.parametrize("muscle, substeps, channels", [("modules", 1, "fused"), ("fused", 8, "fused"),
                                                        ("fused", 1, "separate"), ("fused_fixed", 8, "fused_fixed")])
def test_coreneuron_pool_is_neurons_bit_for_bit(ct09, muscle, substeps, channels):
    d = PoolDefinition(6, ct09, muscle_model=muscle, muscle_substeps=substeps, motoneuron_channels=channels)
    a, b = _run(d, "neuron"), _run(d, "coreneuron")
    _assert_same(a, b)
    assert b.provenance["settings"]["engine"] == "coreneuron"


def test_coreneuron_runs_the_late_adaptation_bit_for_bit(ct09):
    d = PoolDefinition(4, ct09, muscle_model="fused", muscle_substeps=8,
                       motoneuron_overrides={"g_ks_S_per_cm2": 0.1, "ks_tau_ms": 100.0})
    a, b = _run(d, "neuron", duration_ms=400.0), _run(d, "coreneuron", duration_ms=400.0)
    _assert_same(a, b)
    bare = _run(PoolDefinition(4, ct09, muscle_model="fused", muscle_substeps=8), "neuron", duration_ms=400.0)
    assert sum(s.size for s in a.spikes_ms) < sum(s.size for s in bare.spikes_ms)   # the slow K acts


@pytest.mark.parametrize("muscle, substeps, channels", [("modules", 1, "fused"), ("fused", 8, "fused"),
                                                        ("fused_fixed", 8, "fused_fixed")])
def test_coreneuron_under_crank_nicolson_is_neurons_bit_for_bit(ct09, muscle, substeps, channels):
    """secondorder 2: both engines halve dt in the mechanisms' METHOD euler blocks, which count the whole step.  The
    same spikes; the forces bit for bit with KimUnit (its derivatives are zero) and to rounding with the three
    mechanisms (KimCa's and KimForce's mean rates are added in two halves, in each engine's own order)."""
    d = PoolDefinition(6, ct09, muscle_model=muscle, muscle_substeps=substeps, motoneuron_channels=channels)
    a, b = _run(d, "neuron", secondorder=2), _run(d, "coreneuron", secondorder=2)
    assert sum(s.size for s in a.spikes_ms) > 10 and a.pool_force_N.max() > 0.1
    assert all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms))
    if muscle != "modules":
        np.testing.assert_array_equal(b.unit_force_N, a.unit_force_N)
    assert np.abs(b.unit_force_N - a.unit_force_N).max() <= 1e-12 * a.unit_force_N.max()
    assert b.provenance["settings"]["secondorder"] == 2
    # the muscle is the same under either scheme; only the membrane's discharges differ
    assert not all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, _run(d, "neuron").spikes_ms))


@pytest.mark.parametrize("drive", ["poisson", "discharges"])
def test_coreneuron_takes_every_drive(ct09, drive):
    d = PoolDefinition(4, ct09, muscle_model="fused")
    _assert_same(_run(d, "neuron", drive), _run(d, "coreneuron", drive))


def test_coreneuron_takes_the_synaptic_noise_bit_for_bit(ct09):
    """Each cell's own noise (MnNoise, a Random123 stream per cell) draws the same numbers under either engine."""
    d = PoolDefinition(4, ct09, muscle_model="fused", synaptic_noise_uS=0.05)
    runs = []
    for engine in ("neuron", "coreneuron"):
        with Pool(d, length=-8.0, engine=engine) as pool:
            pool.drive_synaptic([0.0, 300.0], [0.0, 0.6])
            runs.append(pool.run(300.0, Simulator(engine=engine)))
    _assert_same(*runs)
    assert runs[1].provenance["synaptic_noise_uS"] == 0.05


@pytest.mark.parametrize("cell_permute", [0, 1])
def test_either_coreneuron_layout_is_neurons_bit_for_bit(ct09, cell_permute):
    """The synaptic drive, the membrane at dt 0.05 ms and the muscle every 4 steps (the fast option)."""
    d = PoolDefinition(6, ct09, muscle_model="fused", muscle_substeps=4)
    runs = []
    for engine in ("neuron", "coreneuron"):
        with Pool(d, length=-8.0, engine=engine) as pool:
            pool.drive_synaptic([0.0, 300.0], [0.0, 0.6])
            runs.append(pool.run(300.0, Simulator(dt_ms=0.05, engine=engine, cell_permute=cell_permute)))
    _assert_same(*runs)
    assert runs[1].provenance["settings"]["cell_permute"] == cell_permute
    with pytest.raises(InputError, match="cell_permute"):
        Simulator(engine="coreneuron", cell_permute=2)


def _synaptic_run(definition, simulator):
    with Pool(definition, length=-8.0, engine=simulator.engine) as pool:
        pool.drive_synaptic([0.0, 300.0], [0.0, 0.6])
        return pool.run(300.0, simulator)


@pytest.mark.parametrize("engine", ["neuron", "coreneuron"])
def test_the_fixed_step_does_not_interpolate_threshold_crossings(ct09, engine):
    """CVode.condition_order(2) places a NetCon's threshold crossing inside the step under CVODE only: under the
    fixed step (NEURON's, and CoreNEURON's, which accepts the setting) a spike keeps the time of the step that
    detects it, bit for bit, so the package offers no such setting (docs/validation/speed.md).  Under CVODE the
    same pool's spikes do move, so the setting reaches NEURON: if a NEURON release starts interpolating under
    the fixed step, this fails and the fast path's spike timing is worth measuring again."""
    d = PoolDefinition(4, ct09, muscle_model="fused", muscle_substeps=4)
    first, second = (_synaptic_run(d, Simulator(dt_ms=0.05, engine=engine, condition_order=k)) for k in (1, 2))
    _assert_same(first, second)
    steps = np.concatenate(second.spikes_ms) / 0.05
    assert np.allclose(steps, np.round(steps), rtol=0.0, atol=1e-6)   # every spike at a step's end
    if engine == "neuron":
        cv1, cv2 = (_synaptic_run(d, Simulator(method="cvode", condition_order=k)) for k in (1, 2))
        assert [s.size for s in cv1.spikes_ms] == [s.size for s in cv2.spikes_ms]
        moved = max(abs(a[0] - b[0]) for a, b in zip(cv1.spikes_ms, cv2.spikes_ms) if a.size)
        assert 1e-6 < moved < 0.05   # the first spikes, by microseconds (the later ones drift further apart)
        assert cv2.provenance["settings"]["condition_order"] == 2
    with pytest.raises(InputError, match="condition_order"):
        Simulator(condition_order=3)


def test_a_run_in_chunks_is_the_run_in_one(ct09, monkeypatch):
    """Chunks of ~9 ms (events in flight across their ends, samples taken between them) change nothing."""
    d = PoolDefinition(6, ct09, muscle_model="fused")
    whole = _run(d, "coreneuron")
    monkeypatch.setattr(pool_module, "STEP_RECORD_BUDGET_BYTES", 6 * 40 * 8 * 9)
    _assert_same(whole, _run(d, "coreneuron"))


def test_a_run_whose_last_chunk_coreneuron_ends_a_step_short_is_completed(ct09, monkeypatch):
    """Two chunks, 1048.575 and 51.425 ms: CoreNEURON stops the second one step before 1100 ms; the run still ends
    at 1100 ms (it used to call psolve without end), as NEURON's."""
    from neuron import h

    d = PoolDefinition(2, ct09, muscle_model="fused", muscle_substeps=8)
    monkeypatch.setattr(pool_module, "STEP_RECORD_BUDGET_BYTES", 2 * 40 * 8 * 1048.576)
    runs = []
    for engine in ("neuron", "coreneuron"):
        with Pool(d, length=-8.0, engine=engine) as pool:
            pool.drive_synaptic([0.0, 1100.0], [0.0, 0.6])
            runs.append(pool.run(1100.0, Simulator(engine=engine)))
            assert abs(h.t - 1100.0) < 1e-6
    _assert_same(*runs)


def test_a_simulator_of_the_other_engine_is_refused(ct09):
    with Pool(PoolDefinition(2, ct09), engine="coreneuron") as pool:
        pool.drive_current_ramp([0.0, 50.0], [0.0, 20.0])
        with pytest.raises(InputError, match="built for engine 'coreneuron'"):
            pool.run(50.0, Simulator())
    with pytest.raises(InputError, match="engine must be one of"):
        Pool(PoolDefinition(2, ct09), engine="gpu")


@pytest.mark.skipif(not mpi_available(), reason="the mpi extra is not installed (pip install -e '.[test,mpi]')")
def test_coreneuron_on_two_ranks_is_neuron_on_one(tmp_path):
    args = ["-m", "neuromuscle.pool.run_mpi", "--units", "6", "--duration-ms", "300", "--drive", "ramp",
            "--muscle", "fused", "--json"]
    results = {}
    for name, cmd in (("neuron", [sys.executable, *args, "--out", str(tmp_path / "n.h5")]),
                      ("coreneuron", mpiexec_command(2, [*args, "--engine", "coreneuron",
                                                         "--out", str(tmp_path / "c.h5")]))):
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        report = json.loads(proc.stdout[proc.stdout.index("{"):])
        assert report["engine"] == name
        results[name] = load_pool_result(tmp_path / ("n.h5" if name == "neuron" else "c.h5"))
    assert results["coreneuron"].ranks == 2
    _assert_same(results["neuron"], results["coreneuron"])
