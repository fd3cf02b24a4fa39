"""Staged calibration (neuromuscle.calibration.staged): synthetic CT09 data recovers the parameters; stages
without data are skipped with the reason."""

from __future__ import annotations

import pytest
from calibration_synthetic import OPTS, synthetic_data

from neuromuscle.calibration import staged_calibration
from neuromuscle.measured import read_measured, write_measured

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
