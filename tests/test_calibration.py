"""Staged calibration (neuromuscle.calibration): synthetic CT09 data recovers the parameters; real data runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from neuromuscle.calibration import (FORCE_LENGTH_PATH, FORCE_VELOCITY_PATH, calibrate_force_length,
                                     calibrate_force_velocity, calibrate_kse, gaussian_force_length,
                                     hill_tension, mashima_tension, real_data_calibration, staged_calibration)
from neuromuscle.errors import InputError
from neuromuscle.fitting import SimulationOptions, trial_simulation
from neuromuscle.measured import MeasuredData, Trial, read_measured, write_measured

DT = 0.1
SETTLE = 300.0
OPTS = SimulationOptions(dt_ms=DT, record_dt_ms=0.5, settle_ms=SETTLE)


def _trial(params, tid, protocol, t, stims, length_const=None, length=None, noise=0.0, rng=None):
    tr = Trial(trial_id=tid, protocol=protocol, time_s=t, force=np.zeros_like(t), force_unit="N",
               length_unit="mm", length_const=length_const, length=length,
               stimulus_times_s=np.asarray(stims, dtype=float))
    f = trial_simulation(params, tr, DT, record_dt_ms=0.5 if length is None else DT, settle_ms=SETTLE)
    tr.force = f + (rng.normal(0.0, noise, f.size) if noise else 0.0)
    return tr


def synthetic_data(params, noise=0.005, seed=1, full=True) -> MeasuredData:
    """CT09-like preparation: twitch + 10/20/40 Hz at g1, twitches at g1 -/+ 8 mm, a step shortening during a
    100 Hz train, isometric force-length and isokinetic velocity-tension points (extra datasets)."""
    rng = np.random.default_rng(seed)
    g1 = params["g1"]
    t = np.arange(0.0, 0.45, 0.002)
    trials = [_trial(params, "twitch_opt", "twitch", t, [0.02], g1, noise=noise, rng=rng)]
    if full:
        for rate in (10, 20, 40):
            trials.append(_trial(params, f"train{rate}", "train", t, np.arange(0.02, 0.3, 1.0 / rate), g1,
                                 noise=noise, rng=rng))
        for x in (g1 - 8.0, g1 + 8.0):
            trials.append(_trial(params, f"twitch_{x:g}mm", "twitch", t, [0.02], x, noise=noise, rng=rng))
    ts = np.arange(0.0, 0.2, 0.0001)
    xs = np.interp(ts, [0.0, 0.15, 0.1505, 0.2], [g1, g1, g1 - 0.5, g1 - 0.5])
    trials.append(_trial(params, "step", "step", ts, np.arange(0.0, 0.2, 0.01), length=xs))
    xl = np.linspace(g1 - 16, g1 + 8, 9)
    fl = gaussian_force_length(xl, g1, params["g2"], params["P0"]) + rng.normal(0, 0.05, xl.size)
    vs = np.array([-160.0, -80.0, -40.0, -10.0, -1.0])
    vl = np.array([1.0, 10.0, 40.0, 80.0])
    fv = np.concatenate([hill_tension(vs, params["a0"], params["b0"], params["P0"]),
                         mashima_tension(vl, params["c0"], params["d0"], params["P0"])])
    fv = fv + rng.normal(0, 0.05, fv.size)
    return MeasuredData(trials={tr.trial_id: tr for tr in trials}, attrs={"source": "synthetic CT09"},
                        extra_datasets={FORCE_LENGTH_PATH: np.column_stack([xl, fl]),
                                        FORCE_VELOCITY_PATH: np.column_stack([np.concatenate([vs, vl]), fv])})


def test_force_velocity_closed_form_matches_table1():
    pts = [(-160, 1), (-1, 22), (1, 23.5), (80, 34.35)]
    r = calibrate_force_velocity([p[0] for p in pts], [p[1] for p in pts], 23.0)
    assert r.values["a0"] == pytest.approx(2.348, abs=2e-3)
    assert r.values["d0"] == pytest.approx(30.297, abs=2e-3)
    assert r.errors["rms"] < 1e-9


def test_force_length_and_velocity_least_squares(ct09):
    x = np.linspace(-24, 0, 7)
    r = calibrate_force_length(x, gaussian_force_length(x, -8.0, 21.4, 23.0))
    assert r.values == pytest.approx({"g1": -8.0, "g2": 21.4, "P0": 23.0}, rel=1e-6)
    v = np.array([-150.0, -60.0, -5.0, 5.0, 30.0, 90.0])
    T = np.where(v < 0, hill_tension(v, 2.35, 24.35, 23.0), mashima_tension(v, -7.4, 30.3, 23.0))
    r = calibrate_force_velocity(v, T, 23.0)
    assert r.values == pytest.approx({"a0": 2.35, "b0": 24.35, "c0": -7.4, "d0": 30.3}, rel=1e-5)
    with pytest.raises(InputError, match="lengthening"):
        calibrate_force_velocity([-1.0, -2.0, 3.0], [20.0, 19.0, 24.0], 23.0)


def test_staged_calibration_recovers_ct09(ct09, tmp_path):
    path = write_measured(tmp_path / "synthetic.h5", synthetic_data(ct09))
    data = read_measured(path)
    start = ct09.with_values(KSE=0.3, a0=3.0, b0=30.0, c0=-5.0, d0=20.0, g2=15.0, P0=20.0,
                             C1=0.128 * 1.15, C2=0.093 * 0.85, C3=61.206 * 1.2, alpha=2.2,
                             phi1=0.0, phi2=1.0, phi3=0.0, phi4=1.0)
    res = staged_calibration(data, start, options=OPTS, max_iterations=20)
    p = res.parameters
    assert [s.stage for s in res.stages] == ["force-length", "force-velocity", "KSE", "module2",
                                             "length-compensation"]
    assert all(s.skipped is None for s in res.stages)
    assert p["g1"] == pytest.approx(-8.0, abs=0.3) and p["g2"] == pytest.approx(21.4, rel=0.03)
    assert p["P0"] == pytest.approx(23.0, rel=0.01)
    for k, v in {"a0": 2.35, "b0": 24.35, "c0": -7.4, "d0": 30.3}.items():
        assert p[k] == pytest.approx(v, rel=0.1), k
    assert p["KSE"] == pytest.approx(0.4, rel=0.08)
    m2 = res.stage("module2")
    assert max(v for k, v in m2.errors.items() if k.startswith("nrmse_")) < 3.0
    for k in ("C1", "C3"):
        assert p[k] == pytest.approx(ct09[k], rel=0.1), k
    # phi at the three lengths (the CT09 lines are discontinuous at g1: compare values, not slopes)
    def phi(pp, x):
        return pp["phi1"] * x + pp["phi2"] if x <= pp["g1"] else pp["phi3"] * x + pp["phi4"]
    for x in (-16.0, -8.0, 0.0):
        assert phi(p, x) == pytest.approx(phi(ct09, x), rel=0.04), x
    assert "length-compensation" in res.summary()


def test_stages_skipped_with_reason(ct09):
    data = synthetic_data(ct09, full=False)
    data.extra_datasets.clear()
    res = staged_calibration(data, ct09, options=OPTS, max_iterations=3, module2_free=("C3",))
    by = {s.stage: s for s in res.stages}
    assert "force_length" in by["force-length"].skipped
    assert by["KSE"].skipped is None and by["KSE"].values["KSE"] == pytest.approx(0.4, rel=0.08)
    assert by["module2"].skipped is None and by["module2"].trials == ["twitch_opt"]
    assert "length" in by["length-compensation"].skipped


def test_kse_refuses_lengthening(ct09):
    t = np.linspace(0, 0.1, 101)
    tr = Trial(trial_id="s", protocol="step", time_s=t, force=np.ones_like(t), force_unit="N",
               length_unit="mm", length=np.linspace(-8, -7, 101))
    with pytest.raises(InputError, match="does not shorten"):
        calibrate_kse(tr, 23.0)


def test_real_data_calibration(real_data):
    out = real_data_calibration(real_data)
    fl = out["scott_brown_loeb_1996"]["force_length"]
    fv = out["scott_brown_loeb_1996"]["force_velocity"]
    assert 0.85 < fl["g1_L0"] < 1.1 and 0.2 < fl["g2_L0"] < 0.8
    assert math.isfinite(fl["rms_F0"]) and fl["rms_F0"] < 0.12
    assert math.isfinite(fv["rms_F0"]) and fv["rms_F0"] < 0.15
    assert all(fv[k] > 0 for k in ("a0_F0", "b0_L0_per_s", "d0_L0_per_s"))
    hl = out["herzog_leonard_2002"]
    assert 15 < hl["isometric_0mm_N"]["mean"] < 40 and 0 < hl["active_ratio_9mm_over_0mm"] < 1.5
