"""Recorded discharges: the Caillet loader on the real files and its refusals; unit-force calibration recovers a
known P0 spread and delay from synthetic discharges."""

from pathlib import Path

import numpy as np
import pytest
import scipy.io

from neuromuscle import Simulator
from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.discharges import load_caillet
from neuromuscle.pool.force_calibration import unit_force_basis

CAILLET = Path(__file__).resolve().parents[2].parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"
needs_data = pytest.mark.skipif(not CAILLET.is_dir(), reason=f"Caillet real-data folder {CAILLET} is absent")


@needs_data
@pytest.mark.parametrize("name, units, level", [("S1_30_256.mat", 84, 30.0), ("TA_35_D.mat", 32, 35.0),
                                                ("GM_30.mat", 27, 30.0)])
def test_real_files_load_in_ms_and_percent_mvc(name, units, level):
    rec = load_caillet(CAILLET / name)
    assert rec.n_units == units and rec.fsamp_hz == 2048.0 and rec.level_percent_mvc == level
    m = scipy.io.loadmat(CAILLET / name)
    first = np.ravel(m["MUPulses"][0][0]).astype(float)
    assert np.allclose(rec.discharges_ms[0], (first - 1) / 2048.0 * 1000.0)  # samples (from 1) -> ms
    f = rec.force_percent_mvc
    assert abs(np.median(f[:2000])) < 1.0 and level * 0.9 < np.percentile(f, 90) < level * 1.1
    trial = rec.trial(pad_ms=1000.0)
    thr = rec.thresholds_percent_mvc()[trial.units]
    assert np.all(np.diff(thr) >= 0)  # recruitment order
    assert trial.duration_ms < 40_000.0 and min(d[0] for d in trial.discharges_ms) == pytest.approx(1000.0)
    assert max(d[-1] for d in trial.discharges_ms) <= trial.duration_ms
    if name == "GM_30.mat":  # discharges cover the first of three trapezoids only: the window stops there
        assert trial.start_ms + trial.duration_ms < 36_000.0


@needs_data
def test_a_window_from_rest_covers_the_ramp_no_unit_was_found_for():
    # S1_50_64L's lowest decomposed unit is recruited at 25 % MVC, 5.3 s after the force left rest
    rec = load_caillet(CAILLET / "S1_50_64L.mat")
    near = rec.trial(pad_ms=1000.0)
    whole = rec.trial(pad_ms=1000.0, from_rest=True)
    assert near.force_percent_mvc[0] > 15.0 and abs(np.median(whole.force_percent_mvc[:500])) < 0.5  # rest
    left, back = rec.rest_times_ms()
    assert whole.start_ms == pytest.approx(left - 500.0, abs=1.0) and left < min(d[0] for d in rec.discharges_ms)
    assert whole.start_ms + whole.duration_ms >= max(d[-1] for d in rec.discharges_ms) + 1000.0
    assert whole.start_ms + whole.duration_ms == pytest.approx(min(back + 500.0, rec.force_t_ms[-1]), abs=1.0)
    first = [d[0] + whole.start_ms for d in whole.discharges_ms]
    assert np.allclose(sorted(first), sorted(d[0] for d in rec.discharges_ms))  # the same discharges, shifted


def test_rest_times_are_where_the_force_last_leaves_and_first_returns_to_rest(tmp_path):
    ref = np.concatenate([np.zeros(2000), np.linspace(0, 1, 1000), np.ones(3000), np.linspace(1, 0, 1000),
                          np.zeros(1000)]) + 0.5
    pulses = np.empty((1, 1), dtype=object)
    pulses[0, 0] = np.array([[3500, 3600, 5900]], dtype=np.int32)
    scipy.io.savemat(tmp_path / "X_20.mat", {"MUPulses": pulses, "fsamp": np.array([[1000.0]]),
                                             "ref_signal": ref[None, :]})
    rec = load_caillet(tmp_path / "X_20.mat")
    left, back = rec.rest_times_ms()  # 1 % MVC of a 20 % plateau: 1/20 of each ramp
    assert left == pytest.approx(2049.0, abs=2.0) and back == pytest.approx(6951.0, abs=2.0)
    whole = rec.trial(pad_ms=200.0, from_rest=True)
    assert whole.start_ms == pytest.approx(left - 500.0, abs=1.0)
    assert whole.start_ms + whole.duration_ms == pytest.approx(back + 500.0, abs=1.0)
    assert rec.trial(pad_ms=200.0).start_ms == pytest.approx(3299.0)
    with pytest.raises(InputError, match=r"X_20\.mat: rest_percent_mvc"):
        rec.trial(from_rest=True, rest_percent_mvc=float("nan"))


def test_the_baseline_is_the_rest_even_when_the_first_unit_is_recruited_late_in_the_ramp(tmp_path):
    rng = np.random.default_rng(3)
    ref = np.concatenate([np.zeros(1000), np.linspace(0, 1, 2000), np.ones(3000)]) * 4.0 + 1.5
    ref += rng.normal(0.0, 0.01, ref.size)  # transducer noise, 0.25 % of the plateau
    pulses = np.empty((1, 1), dtype=object)
    pulses[0, 0] = np.array([[2600, 2700, 5000]], dtype=np.int32)  # first discharge at 80 % of the ramp
    scipy.io.savemat(tmp_path / "X_50.mat", {"MUPulses": pulses, "fsamp": np.array([[1000.0]]),
                                             "ref_signal": ref[None, :]})
    rec = load_caillet(tmp_path / "X_50.mat")
    assert abs(np.median(rec.force_percent_mvc[:1000])) < 0.1  # the median before the discharge: 7.5 %
    assert np.median(rec.force_percent_mvc[3000:]) == pytest.approx(50.0, abs=0.1)
    assert rec.thresholds_percent_mvc()[0] == pytest.approx(40.0, abs=0.3)


@needs_data
def test_two_grids_on_one_contraction_read_one_force():
    # S1_50_64L's first decomposed unit is recruited at 25 % MVC, S1_50_256's at 9 %: the same transducer record
    # normalised from each must agree, rest and plateau
    a, b = (load_caillet(CAILLET / f"S1_50_{g}.mat") for g in ("64L", "256"))
    assert a.force_percent_mvc.size == b.force_percent_mvc.size
    assert np.max(np.abs(a.force_percent_mvc - b.force_percent_mvc)) < 0.2


def _good(**change):
    pulses = np.empty((1, 2), dtype=object)
    pulses[0, 0] = np.array([[3000, 3200, 3400]], dtype=np.int32)
    pulses[0, 1] = np.array([[3100, 3350]], dtype=np.uint16)
    ref = np.concatenate([np.zeros(2500), np.ones(2500)]) + 0.5
    m = {"MUPulses": pulses, "fsamp": np.array([[2048.0]]), "ref_signal": ref[None, :]}
    m.update(change)
    return {k: v for k, v in m.items() if v is not None}


def _unit(values):
    a = np.empty((1, 1), dtype=object)
    a[0, 0] = np.array([values], dtype=float)
    return a


def test_small_good_file_loads(tmp_path):
    scipy.io.savemat(tmp_path / "X_20.mat", _good())
    rec = load_caillet(tmp_path / "X_20.mat")
    assert rec.level_percent_mvc == 20.0 and rec.force_percent_mvc[-1] == pytest.approx(20.0)
    assert np.array_equal(rec.recruitment_order(), [0, 1])  # same threshold: the earlier first discharge first


@pytest.mark.parametrize("change, message", [
    (dict(MUPulses=None), "field 'MUPulses' is missing"),
    (dict(fsamp=np.array([[0.0]])), "field 'fsamp' must be one positive rate"),
    (dict(ref_signal=np.array([[np.nan, 1.0]])), "field 'ref_signal' is not finite"),
    (dict(MUPulses=_unit([3000.0, 2999.0])), "field 'MUPulses' unit 0 must be strictly increasing"),
    (dict(MUPulses=_unit([3000.0, 3000.0])), "two equal times"),
    (dict(MUPulses=_unit([3000.5])), "sample indices must be integers"),
    (dict(MUPulses=_unit([3000.0, 9000.0])), "outside the force record"),
    (dict(ref_signal=np.zeros((1, 5000))), "never rises above its baseline"),
    (dict(MUPulses=np.zeros((2, 2))), "must be a 1 x n cell array"),
])
def test_bad_files_are_refused_naming_file_and_field(tmp_path, change, message):
    path = tmp_path / "bad_30.mat"
    scipy.io.savemat(path, _good(**change))
    with pytest.raises(InputError, match=message) as err:
        load_caillet(path)
    assert "bad_30.mat" in str(err.value)


def test_unreadable_and_unnamed_files_are_refused(tmp_path):
    (tmp_path / "junk_30.mat").write_text("not a mat file")
    with pytest.raises(InputError, match="junk_30.mat: not a readable MATLAB"):
        load_caillet(tmp_path / "junk_30.mat")
    scipy.io.savemat(tmp_path / "nolevel.mat", _good())
    with pytest.raises(InputError, match="no contraction level"):
        load_caillet(tmp_path / "nolevel.mat")
    assert load_caillet(tmp_path / "nolevel.mat", level_percent_mvc=10.0).level_percent_mvc == 10.0
    with pytest.raises(InputError, match="no such file"):
        load_caillet(tmp_path / "absent_30.mat")


def test_basis_weighted_by_p0_is_the_pool_force(ct09):
    """Module 3 is homogeneous in P0: a pool of units of different P0 under recorded discharges makes exactly the
    P0-weighted sum of the unit-force basis (force per newton of P0)."""
    rng = np.random.default_rng(1)
    n, duration = 5, 2000.0
    trains = []
    for i in range(n):  # later units start later and discharge faster, with jittered intervals
        t = 100.0 + 150.0 * i + np.cumsum(rng.normal(1000.0 / (10 + 3 * i), 8.0, 60))
        trains.append(t[t < duration - 100.0])
    d = PoolDefinition(n, ct09, smallest_p0_N=0.5, p0_range=20.0, type_fractions=(1.0, 0.0, 0.0))
    with Pool(d, motoneurons=False) as pool:
        pool.drive_discharges(trains, duration)
        truth = pool.run(duration, Simulator(method="fixed", dt_ms=0.05), record_dt_ms=1.0)
    t, g = unit_force_basis(trains, duration, ct09, dt_ms=0.05)
    p0 = np.array([u["P0_N"] for u in truth.units])
    assert np.ptp(p0) > 5.0
    np.testing.assert_allclose(p0 @ g, truth.pool_force_N - truth.pool_force_N[0], atol=1e-9 * p0.sum())
