"""Drives as data: the recruitment ramp's shape, the rise, checks before anything is built, and a drive applied to
a pool gives the same pool as the Pool method it stands for."""

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.drives import Drive


def test_recruitment_ramp_and_rise():
    ramp = Drive.recruitment_ramp(0.6, 2000.0)
    assert ramp.kind == "synaptic" and ramp.times_ms == (0.0, 1000.0, 1500.0, 2000.0)
    assert ramp.values == (0.0, 0.6, 0.6, 0.0) and ramp.end_ms() == 2000.0
    assert ramp.to_dict() == {"kind": "synaptic", "times_ms": [0.0, 1000.0, 1500.0, 2000.0],
                              "values_uS": [0.0, 0.6, 0.6, 0.0]}
    rise = Drive.rise("current", 40.0, 300.0)
    assert (rise.times_ms, rise.values) == ((0.0, 300.0), (0.0, 40.0))
    assert Drive("poisson", rate_hz=300.0, seed=4).to_dict() == {"kind": "poisson", "rate_hz": 300.0,
                                                                 "weight_uS": 0.15, "seed": 4}


@pytest.mark.parametrize("make, message", [
    (lambda: Drive("tremor"), "drive kind must be one of synaptic, current, poisson"),
    (lambda: Drive("synaptic", (0, 100), (0, -0.1)), "synaptic drive value 1 \\(uS\\)"),
    (lambda: Drive("current", (0, 100, 50), (0, 1, 2)), "current drive times"),
    (lambda: Drive("current", (0, 100), (0, 1, 2)), "2 times and 3 values"),
    (lambda: Drive("poisson", rate_hz=0.0), "Poisson rate"),
    (lambda: Drive.recruitment_ramp(0.0, 100.0), "peak synaptic drive"),
    (lambda: Drive.rise("synaptic", 0.5, -1.0), "run duration"),
])
def test_bad_drives_are_refused(make, message):
    with pytest.raises(InputError, match=message):
        make()


def test_a_drive_gives_the_pool_of_the_method_it_stands_for(ct09):
    d = PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)
    with Pool(d) as pool:
        pool.drive_synaptic([0.0, 100.0, 150.0, 200.0], [0.0, 0.6, 0.6, 0.0])
        direct = pool.run(200.0)
    with Pool(d) as pool:
        Drive.recruitment_ramp(0.6, 200.0).apply(pool)
        via = pool.run(200.0)
    assert sum(s.size for s in direct.spikes_ms) > 2
    assert np.array_equal(direct.unit_force_N, via.unit_force_N)


def test_the_phases_a_discharge_summary_reads():
    ramp = Drive.recruitment_ramp(0.6, 2000.0)
    assert ramp.held_at_peak_ms() == (1000.0, 1500.0) and ramp.falls_back()
    rise = Drive.rise("synaptic", 0.6, 500.0)
    assert rise.held_at_peak_ms() is None and not rise.falls_back()
    two = Drive("current", (0, 100, 400, 500, 600, 700), (0, 5, 5, 2, 5, 5))      # the longer hold at the peak
    assert two.held_at_peak_ms() == (100.0, 400.0) and not two.falls_back()
    kept = Drive("synaptic", (0, 100, 200), (0, 0.6, 0.4))                          # stays above half its peak
    assert not kept.falls_back() and kept.held_at_peak_ms() is None
    assert Drive("poisson").held_at_peak_ms() is None and not Drive("poisson").falls_back()
