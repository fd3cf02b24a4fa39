"""CVODE recording at an interval that is not a binary fraction (0.025 ms) under a played length: NEURON 9.0.2
aborted the whole process on an assertion (NetCvode::global_microstep) when an accumulated record time fell a
rounding error short of a played breakpoint.  Run in a child process, so that a regression fails this test
instead of killing the test session."""

import subprocess
import sys

import numpy as np

from neuromuscle import load_parameters, simulate
from neuromuscle.protocols import constant_rate, isokinetic_ramp
from neuromuscle.sim import Simulator

CHILD = """
from neuromuscle import load_parameters, simulate
from neuromuscle.protocols import constant_rate, isokinetic_ramp
from neuromuscle.sim import Simulator
r = simulate(load_parameters("CT09"), constant_rate(40, 350, start_ms=50), isokinetic_ramp(-10, -4, 50, 200, 400),
             400.0, simulator=Simulator(method="cvode"), record_dt_ms={dt})
print(r.t_ms.size, float(r.force_N.max()))
"""


def test_cvode_records_every_0_025_ms_under_a_ramp_without_aborting():
    out = subprocess.run([sys.executable, "-c", CHILD.format(dt=0.025)], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    n, peak = out.stdout.split()[-2:]
    assert int(n) == 16001 and 25.0 < float(peak) < 40.0


def test_cvode_samples_are_the_same_at_any_interval():
    p, spikes = load_parameters("CT09"), constant_rate(40, 350, start_ms=50)
    ramp = isokinetic_ramp(-10, -4, 50, 200, 400)
    a = simulate(p, spikes, ramp, 400.0, simulator=Simulator(method="cvode"), record_dt_ms=0.025)
    b = simulate(p, spikes, ramp, 400.0, simulator=Simulator(method="cvode"), record_dt_ms=0.5)
    assert np.array_equal(a.t_ms[::20], b.t_ms)
    np.testing.assert_allclose(a.force_N[::20], b.force_N, rtol=0, atol=1e-6 * b.force_N.max())


POOL_CHILD = """
import numpy as np
from neuromuscle import load_parameters
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.protocols import isokinetic_ramp
from neuromuscle.sim import Simulator
d = PoolDefinition(3, load_parameters("CT09"))
with Pool(d, motoneurons=False, length=isokinetic_ramp(-10, -4, 50, 200, 400)) as pool:
    pool.drive_discharges([np.arange(50.0, 350.0, 25.0)] * 3, 400.0)
    r = pool.run(400.0, simulator=Simulator(method="cvode"), record_dt_ms=0.025)
print(r.t_ms.size, float(r.pool_force_N.max()))
"""


def test_a_cvode_pool_records_every_0_025_ms_under_a_ramp_without_aborting():
    out = subprocess.run([sys.executable, "-c", POOL_CHILD], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    n, peak = out.stdout.split()[-2:]
    assert int(n) == 16001 and float(peak) > 0.0
