"""Every script in networks/ runs as a user would run it (python networks/NAME.py OUT.png) and produces output."""

import subprocess
import sys
from pathlib import Path

import pytest

NETWORKS = Path(__file__).resolve().parents[2] / "networks"


#: Scripts with another interface (--out FILE.h5 or --out DIR), each run by its own tests: the data conversions
#: (tests/diagnose/test_real_data.py) and the pool networks (tests/pool/test_networks.py).
NOT_EXAMPLES = ("herzog_leonard_to_measured.py", "herzog_leonard_diagnosis.py", "cat_soleus_pool.py",
                "human_pool.py", "recorded_discharges.py", "pool_vs_recorded.py", "stretch_reflex.py",
                "reconstructed_pool.py")


@pytest.mark.parametrize("script", sorted(p.name for p in NETWORKS.glob("*.py") if p.name not in NOT_EXAMPLES))
def test_network_script_runs(script, tmp_path):
    png = tmp_path / "out.png"
    out = subprocess.run([sys.executable, str(NETWORKS / script), str(png)], cwd=tmp_path, capture_output=True,
                         text=True, timeout=600)
    assert out.returncode == 0, out.stdout + out.stderr
    assert png.is_file() and png.stat().st_size > 1000
    assert "peak force" in out.stdout
