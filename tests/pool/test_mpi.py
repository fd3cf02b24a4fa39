"""Pools under real MPI (``mpiexec -n 2`` in a subprocess): the same spikes and force, bit for bit, as on one rank
(Poisson drive, current ramp, the local variable time step, the fused muscle with and without substeps, the human
cells with their synaptic noise); more ranks than units and a launcher NEURON did not join are refused with nothing
written."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from neuromuscle.pool import load_pool_result
from neuromuscle.pool.mpi import mpi_available, mpiexec_command

needs_mpi = pytest.mark.skipif(not mpi_available(), reason="the mpi extra is not installed (mpich + mpi4py: "
                                                           "pip install -e '.[test,mpi]')")
MODULE = ["-m", "neuromuscle.pool.run_mpi"]


def _launch(n_ranks, args, env=None):
    cmd = mpiexec_command(n_ranks, MODULE + args) if n_ranks else [sys.executable, *MODULE, *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)


def _run(n_ranks, out, args):
    proc = _launch(n_ranks, [*args, "--out", str(out), "--json"])
    assert proc.returncode == 0, proc.stderr[-3000:]
    return load_pool_result(out), json.loads(proc.stdout[proc.stdout.index("{"):])


@needs_mpi
@pytest.mark.parametrize("args", [["--drive", "poisson", "--units", "6", "--duration-ms", "300"],
                                  ["--drive", "ramp", "--units", "6", "--duration-ms", "300"],
                                  ["--drive", "ramp", "--units", "3", "--duration-ms", "150", "--method", "cvode",
                                   "--local-dt"],
                                  ["--drive", "ramp", "--units", "6", "--duration-ms", "300", "--muscle", "fused"],
                                  ["--drive", "poisson", "--units", "6", "--duration-ms", "300", "--muscle", "fused",
                                   "--substeps", "4"],
                                  ["--drive", "synaptic", "--units", "6", "--duration-ms", "300",
                                   "--motoneurons", "human", "--synaptic-noise-us", "0.05"]],
                         ids=["poisson", "ramp", "local_dt", "fused", "fused_substeps", "human_noise"])
def test_two_ranks_give_the_same_pool_as_one(tmp_path, args):
    one, rep1 = _run(1, tmp_path / "one.h5", args)
    two, rep2 = _run(2, tmp_path / "two.h5", args)
    assert (one.ranks, two.ranks) == (1, 2) and (rep1["ranks"], rep2["ranks"]) == (1, 2)
    assert len(rep2["peak_rss_mib_per_rank"]) == 2 and rep2["peak_rss_mib"] > 50.0
    assert sum(s.size for s in one.spikes_ms) > 10 and one.pool_force_N.max() > 0.1
    assert all(np.array_equal(a, b) for a, b in zip(one.spikes_ms, two.spikes_ms))
    assert np.array_equal(one.unit_force_N, two.unit_force_N)  # bit-identical, not close
    assert rep1["spikes"] == rep2["spikes"] == sum(s.size for s in two.spikes_ms)


@needs_mpi
def test_more_ranks_than_units_is_refused_under_mpi(tmp_path):
    out = tmp_path / "never.h5"
    proc = _launch(2, ["--units", "1", "--duration-ms", "50", "--out", str(out)])
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert "2 MPI ranks for a pool of 1 units" in proc.stderr
    assert proc.stderr.count("neuromuscle: error") == 1  # one message, from rank 0
    assert not out.exists()


def test_launcher_that_neuron_did_not_join_is_refused(tmp_path):
    """A launcher's two ranks with no loadable MPI library: each NEURON would run the whole pool alone."""
    out = tmp_path / "never.h5"
    env = {**os.environ, "PMI_SIZE": "2", "MPI_LIB_NRN_PATH": str(tmp_path / "no_libmpi.so")}
    proc = _launch(0, ["--units", "2", "--duration-ms", "50", "--out", str(out)], env=env)
    assert proc.returncode == 2
    assert "the MPI launcher started 2 ranks but NEURON joined 1" in proc.stderr
    assert not out.exists()


def test_noise_without_the_synaptic_drive_is_refused(tmp_path):
    out = tmp_path / "never.h5"
    proc = _launch(0, ["--units", "2", "--duration-ms", "50", "--drive", "ramp", "--synaptic-noise-us", "0.05",
                       "--out", str(out)])
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert "--synaptic-noise-us needs --method fixed and --drive synaptic" in proc.stderr
    assert not out.exists()
