"""What a pool run reports of its units' discharges (``run_mpi.discharge_summary``), on trains whose rates,
hysteresis and irregularity are known."""

import numpy as np
import pytest

from neuromuscle.pool.drives import Drive
from neuromuscle.pool.run_mpi import DELTA_F_REFERENCES, discharge_summary

RAMP = Drive.recruitment_ramp(1.0, 20000.0)           # up over 10 s, held to 15 s, down by 20 s


def _train(on_uS: float, off_uS: float, jitter: float = 0.0, seed: int = 0) -> np.ndarray:
    """Discharges of a unit recruited at drive ``on_uS`` on the way up and derecruited at ``off_uS`` on the way
    down, its rate 8 Hz + 20 Hz/uS above its recruitment drive, each interval scaled by 1 + ``jitter`` x N(0, 1)."""
    t = np.arange(0.0, 20000.0, 1.0)
    g = np.interp(t, RAMP.times_ms, RAMP.values)
    firing = (g >= on_uS) & (t <= 15000.0) | (g >= off_uS) & (t > 15000.0)
    rate = np.where(firing, 8.0 + 20.0 * (g - on_uS), 0.0)
    count = np.cumsum(rate) / 1000.0
    spikes = t[np.flatnonzero(np.diff(np.floor(count)) > 0) + 1]
    if jitter:
        isi = np.diff(spikes) * (1.0 + jitter * np.random.default_rng(seed).standard_normal(spikes.size - 1))
        spikes = spikes[0] + np.concatenate([[0.0], np.cumsum(np.clip(isi, 5.0, None))])
    return spikes


def test_delta_f_and_irregularity_of_a_ramp():
    # each unit derecruited 0.1 uS below its recruitment drive: the earlier unit's rate, 20 Hz/uS, is then
    # 2 Hz lower at the test unit's derecruitment than at its recruitment
    trains = [_train(on, on - 0.1, jitter=0.2, seed=k) for k, on in enumerate((0.15, 0.3, 0.45, 0.6))]
    s = discharge_summary(trains, RAMP)
    assert s["delta_f"]["pairs"] >= 3 and s["delta_f"]["median_hz"] == pytest.approx(2.0, abs=0.6)
    lo, mid, hi = s["isi_cv_p5_p50_p95"]
    assert 0.12 < lo <= mid <= hi < 0.3                 # the jitter's 0.2, measured on the hold
    assert s["medians_inside_human_range"] is not None and len(s["median_rates_p5_p50_p95_hz"]) == 3
    regular = discharge_summary([_train(on, on) for on in (0.15, 0.3, 0.45, 0.6)], RAMP)
    assert abs(regular["delta_f"]["median_hz"]) < 0.5 and regular["isi_cv_p5_p50_p95"][2] < 0.02


def test_no_delta_f_where_the_drive_does_not_fall_back_and_no_cv_without_a_hold():
    trains = [_train(on, on) for on in (0.15, 0.3)]
    s = discharge_summary(trains, Drive.rise("synaptic", 1.0, 20000.0))
    assert s["delta_f"] is None and s["isi_cv_p5_p50_p95"] is None
    p = discharge_summary(trains, Drive("poisson"))
    assert p["delta_f"] is None and p["isi_cv_p5_p50_p95"] is None


def test_a_ramp_without_a_qualifying_pair_reports_no_value():
    s = discharge_summary([_train(0.3, 0.3)], RAMP)                   # one unit: nothing to pair it with
    assert s["delta_f"] == {"median_hz": None, "test_units": 0, "pairs": 0}


def test_each_test_unit_is_paired_with_at_most_the_references_recruited_closest_before_it():
    trains = [_train(on, on - 0.05) for on in np.linspace(0.05, 0.9, 80)]
    s = discharge_summary(trains, RAMP)["delta_f"]
    assert s["test_units"] > 60 and s["pairs"] <= DELTA_F_REFERENCES * s["test_units"]    # all pairs: about 2500
    assert s["pairs"] > (DELTA_F_REFERENCES - 3) * (s["test_units"] - DELTA_F_REFERENCES)
