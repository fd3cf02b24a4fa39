"""Regenerate tests/baselines/unit_traces.npz from the current code (see tests/model/test_ports_off_is_baseline.py)."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "model"))
from test_ports_off_is_baseline import BASELINE, cases  # noqa: E402

from neuromuscle import simulate  # noqa: E402

out = {}
for name, kw in cases().items():
    r = simulate(**kw)
    out[f"{name}/t_ms"] = r.t_ms
    for trace, values in r.traces.items():
        out[f"{name}/{trace}"] = values
np.savez_compressed(BASELINE, **out)
print(f"wrote {BASELINE}")
