"""neuromuscle.literature.scott_brown_loeb_1996: the digitized points (needs the real-data folder: the test fails
without it)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from neuromuscle.literature import load_scott_brown_loeb_1996


def test_scott_brown_loeb_loader(real_data: Path) -> None:
    pts = load_scott_brown_loeb_1996(real_data / "cat_digitized_literature")
    assert pts.active_length_L0.shape == pts.active_force_F0.shape == pts.active_specimen.shape == (65,)
    assert pts.passive_length_L0.shape == pts.passive_force_F0.shape == (45,)
    assert pts.velocity_L0_per_s.shape == pts.velocity_force_F0.shape == (86,)
    assert set(pts.active_specimen) == {"S8", "S9", "S10", "S11", "S12"}
    for arr in (pts.active_length_L0, pts.active_force_F0, pts.passive_length_L0, pts.velocity_L0_per_s):
        assert np.all(np.isfinite(arr))
    assert 0.9 < pts.active_force_F0.max() < 1.1
    assert pts.velocity_L0_per_s.min() < 0 < pts.velocity_L0_per_s.max()  # shortening and lengthening
