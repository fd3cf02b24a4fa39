"""The machine's-limit probe (neuromuscle/bench/machine_limit.py): the motoneuron's fixed-step arithmetic as one C
loop compiles, runs and recruits the cells in size order; without a compiler the probe says so (None);
docs/validation/motoneuron_limit.py checks the loop against NEURON spike for spike."""

import subprocess

import numpy as np

from neuromuscle.bench.machine_limit import BUILDS, compile_loop, probe_ns, run_loop


def test_the_loop_fires_every_cell_under_the_drive(tmp_path):
    exe = compile_loop(tmp_path, BUILDS[0][1], "loop")
    ns, spikes = run_loop(exe, 20, 300.0, 0.025, 0.3, tmp_path / "out.txt")
    per_cell = np.loadtxt(tmp_path / "out.txt", ndmin=2)   # spike count, first spike (ms; -1: none) per cell
    assert ns > 0 and spikes == int(per_cell[:, 0].sum()) > 0
    # the cells in size order: the smallest fire first and most (Henneman), the largest not at all here
    counts, first = per_cell[:, 0], per_cell[:, 1]
    assert np.all(np.diff(counts) <= 0) and counts[0] > 0 and counts[-1] == 0
    assert 0 < first[0] < first[counts > 0][-1]
    none, _ = run_loop(exe, 20, 300.0, 0.025, 0.0, tmp_path / "quiet.txt")
    assert np.loadtxt(tmp_path / "quiet.txt", ndmin=2)[:, 0].sum() == 0   # no drive, no spike


def test_the_probe_times_the_loop_or_says_it_cannot(monkeypatch):
    assert probe_ns(n=50, duration_ms=20.0) > 0

    def no_compiler(*args, **kwargs):
        raise FileNotFoundError("cc")

    monkeypatch.setattr(subprocess, "run", no_compiler)
    assert probe_ns(n=50, duration_ms=20.0) is None
