"""``neuromuscle bench diagnose``'s CPU accounting: the time a child process spends is counted once it has ended,
and the workers' busy share is their CPU time over the wall time they had."""

from __future__ import annotations

import subprocess
import sys
import time

from neuromuscle.bench.diagnose import cpu_between, cpu_seconds

BURN = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.4:\n    pass\n"


def test_cpu_seconds_counts_an_ended_child_as_a_worker():
    before = cpu_seconds()
    subprocess.run([sys.executable, "-c", BURN], check=True)
    after = cpu_seconds()
    assert after["workers"] - before["workers"] >= 0.35
    assert after["main"] >= before["main"]


def test_cpu_seconds_counts_this_process_as_main():
    before = cpu_seconds()
    t = time.process_time()
    while time.process_time() - t < 0.2:
        pass
    after = cpu_seconds()
    assert after["main"] - before["main"] >= 0.15
    assert after["workers"] == before["workers"]


def test_cpu_between_gives_each_kind_and_the_workers_busy_share():
    used = cpu_between({"main": 1.0, "workers": 10.0}, {"main": 3.0, "workers": 190.0}, wall_s=100.0, workers=2)
    assert used == {"main": 2.0, "workers": 180.0, "workers_busy": 0.9}
    assert cpu_between({"main": 0.0, "workers": 0.0}, {"main": 0.0, "workers": 0.0}, 0.0, 2)["workers_busy"] == 0.0
