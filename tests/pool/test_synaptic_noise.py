"""Each motoneuron's own synaptic noise (mod/MnNoise.mod, PoolDefinition.synaptic_noise_uS): an Ornstein-Uhlenbeck
conductance of the set standard deviation and correlation time at any step, replayed exactly, independent between
cells and seeds, refused under the variable step; the human profile's cells then discharge as irregularly as the
recorded human units."""

from dataclasses import replace

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool import discharge_stats as ds
from neuromuscle.pool.follow_force import HUMAN_MUSCLES
from neuromuscle.pool.motoneuron import IRREGULAR_NOISE_US, PROFILES, motoneuron_profile
from neuromuscle.sim import Simulator


@pytest.mark.parametrize("dt_ms", [0.025, 0.1])
def test_the_noise_is_an_ornstein_uhlenbeck_conductance_at_any_step(dt_ms):
    from neuromuscle.model.mechanisms import load_mechanisms

    load_mechanisms()
    from neuron import h

    sec = h.Section(name="noise_probe")
    noise = h.MnNoise(sec(0.5))
    noise.sigma, noise.tau = 0.05, 5.0
    noise.rng.set_ids(7, 0, 2)
    g = h.Vector().record(noise._ref_g)
    h.load_file("stdrun.hoc")
    kept = h.dt, h.steps_per_ms
    try:
        h.dt, h.steps_per_ms = dt_ms, 1.0 / dt_ms
        h.finitialize(-70.0)
        h.continuerun(20000.0)
        x = np.array(g)
    finally:
        h.dt, h.steps_per_ms = kept
        del noise, g, sec                    # the probe leaves nothing in later tests' runs
    lag = int(round(5.0 / dt_ms))
    assert np.mean(x) == pytest.approx(0.0, abs=0.004)
    assert np.std(x) == pytest.approx(0.05, rel=0.05)
    assert np.corrcoef(x[:-lag], x[lag:])[0, 1] == pytest.approx(np.exp(-1.0), abs=0.05)  # correlation time 5 ms


def _spikes(definition, simulator=None, duration_ms=1000.0):
    with Pool(definition, length=-8.0) as pool:
        pool.drive_synaptic([0.0, 200.0, duration_ms], [0.0, 0.6, 0.6])
        return pool.run(duration_ms, simulator).spikes_ms


def test_noise_replays_and_differs_between_seeds(ct09):
    d = PoolDefinition(3, ct09, muscle_model="fused", synaptic_noise_uS=0.05)
    a, b = _spikes(d), _spikes(d)
    quiet = _spikes(replace(d, synaptic_noise_uS=0.0))
    other = _spikes(replace(d, noise_seed=1))
    assert sum(s.size for s in a) > 20
    assert all(np.array_equal(x, y) for x, y in zip(a, b))
    assert not any(np.array_equal(x, y) for x, y in zip(a, quiet))
    assert not any(np.array_equal(x, y) for x, y in zip(a, other))
    # each cell draws its own stream: the same cell twice in one pool does not fire the same train
    twins = _spikes(PoolDefinition(2, ct09, muscle_model="fused", synaptic_noise_uS=0.05, max_size=0.0))
    assert not np.array_equal(twins[0], twins[1])


@pytest.mark.parametrize("bad", [dict(synaptic_noise_uS=-0.01), dict(synaptic_noise_tau_ms=0.0),
                                 dict(noise_seed=-1), dict(noise_seed=2**32)])
def test_bad_noise_settings_are_refused(ct09, bad):
    with pytest.raises(InputError, match=next(iter(bad))):
        PoolDefinition(3, ct09, **bad)


def test_the_variable_step_and_other_drives_are_refused_with_noise(ct09):
    d = PoolDefinition(2, ct09, synaptic_noise_uS=0.05)
    with Pool(d) as pool:
        pool.drive_synaptic([0.0, 100.0], [0.0, 0.6])
        with pytest.raises(InputError, match="synaptic noise .* needs the fixed step"):
            pool.run(100.0, Simulator(method="cvode"))
    with Pool(d) as pool:
        pool.drive_current_ramp([0.0, 100.0], [0.0, 20.0])
        with pytest.raises(InputError, match="rides on the common synaptic drive .* not on the current drive"):
            pool.run(100.0)


def test_the_noise_follows_the_square_root_of_the_drive(ct09):
    """sigma(t) = synaptic_noise_uS sqrt(g(t) / 1 uS) in the drive's steps: none before the drive starts."""
    d = PoolDefinition(1, ct09, muscle_model="fused", synaptic_noise_uS=0.05)
    with Pool(d) as pool:
        pool.drive_synaptic([0.0, 100.0, 200.0, 300.0], [0.0, 0.0, 0.64, 0.64])
        pool.record(["mn.v"])
        from neuron import h

        sigma = h.Vector().record(pool._noise[0]._ref_sigma, 1.0)
        pool.run(300.0)
    s = np.array(sigma)
    assert np.all(s[:100] == 0.0)
    assert s[250] == pytest.approx(0.05 * np.sqrt(0.64), rel=0.02)


def test_human_cells_with_noise_discharge_as_irregularly_as_human_units():
    """Twelve cells of the human TA pool with IRREGULAR_NOISE_US at a steady drive of 0.6 uS (rates 16-21 Hz):
    every cell's interspike intervals vary within the recorded 5th-95th percentiles of the human units' (0.11-0.42),
    their median near the recorded median; without noise (every profile's setting) the discharge is nearly periodic
    (CV < 0.05)."""
    assert all(p.synaptic_noise_uS == 0.0 for p in PROFILES.values())
    muscle = HUMAN_MUSCLES["TA"]
    options = {**motoneuron_profile("human").pool_options(), "synaptic_noise_uS": IRREGULAR_NOISE_US}
    scales = dict(muscle.motoneuron_scales)
    for k, f in options.pop("motoneuron_scales").items():
        scales[k] = scales.get(k, 1.0) * f
    d = muscle.definition(12, motoneuron_scales=scales, **options)
    window = (2500.0, 10500.0)
    with Pool(d) as pool:
        pool.drive_synaptic([0.0, 500.0, window[1]], [0.0, 0.6, 0.6])
        cv = ds.isi_cv(pool.run(window[1]).spikes_ms, window)
    lo, hi = ds.HUMAN_ISI_CV
    assert np.all(np.isfinite(cv)) and np.all((cv >= lo) & (cv <= hi)), cv
    assert np.median(cv) == pytest.approx(ds.HUMAN_ISI_CV_MEDIAN, abs=0.05)
    with Pool(replace(d, synaptic_noise_uS=0.0)) as pool:
        pool.drive_synaptic([0.0, 500.0, window[1]], [0.0, 0.6, 0.6])
        assert np.nanmax(ds.isi_cv(pool.run(window[1]).spikes_ms, window)) < 0.05
