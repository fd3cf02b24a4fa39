"""Module 3 on real cat soleus data (neuromuscle.calibration.examples)."""

from __future__ import annotations

import math

from neuromuscle.calibration import real_data_calibration

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
