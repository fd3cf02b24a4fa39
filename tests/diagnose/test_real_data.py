"""Herzog & Leonard 2002 for the diagnosis: the conversion (networks/herzog_leonard_to_measured.py,
neuromuscle.literature.herzog_leonard_measured) and the baseline calibrated from tetani at one rate.

Real-data tests are skipped, with the reason, when ../shared/real_data is absent beside the checkout (CI has it)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from neuromuscle.cli import main
from neuromuscle.diagnose.baseline import calibrate_baseline
from neuromuscle.diagnose.phases import describe_all
from neuromuscle.measured import MeasuredData, find_problems, read_measured

ROOT = Path(__file__).resolve().parents[2]
REAL_DATA = ROOT.parent / "shared" / "real_data"
HL = REAL_DATA / "cat_soleus_herzog_leonard_2002"
SCRIPT = ROOT / "networks" / "herzog_leonard_to_measured.py"
needs_real_data = pytest.mark.skipif(not HL.is_dir(), reason=f"real data folder {HL} is absent "
                                     "(../shared/real_data beside the checkout; CI has it)")


@pytest.fixture(scope="module")
def converted(tmp_path_factory) -> Path:
    """The Figure 7 trials converted by the script, as a user runs it."""
    out = tmp_path_factory.mktemp("hl") / "hl2002.h5"
    run = subprocess.run([sys.executable, str(SCRIPT), "--out", str(out), "--real-data", str(REAL_DATA)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "15 trials" in run.stdout and "peak force" in run.stdout
    return out


@needs_real_data
def test_conversion_passes_the_validator_and_keeps_the_traces(converted: Path) -> None:
    from neuromuscle.literature import load_herzog_leonard_2002

    assert main(["data", "check", str(converted)]) == 0  # `neuromuscle data check FILE`
    data = read_measured(converted)
    assert find_problems(data) == []
    source = load_herzog_leonard_2002(HL)
    assert sorted(data.trials) == sorted(i for i, t in source.trials.items()
                                         if t.attrs["figure"].startswith("Figure7") and t.protocol != "passive")
    pre = data.extra_attrs["/preprocessing"]
    for tid, t in data.trials.items():
        src = source.trials[tid]
        n = t.time_s.size
        np.testing.assert_array_equal(t.time_s, src.time_s[:n])  # a window of the source samples
        passive = data.extra_datasets[f"/preprocessing/source/{tid}/passive_force_N"][:n]
        np.testing.assert_allclose(t.force + passive, src.force[:n], rtol=0, atol=1e-12)
        x = t.length_at() - pre["length_shift_mm"]
        assert np.sqrt(np.mean((x - src.length[:n]) ** 2)) < 0.06  # the transducer's noise, ~0.04 mm
        s = t.stimulus_times_s
        np.testing.assert_allclose(np.diff(s), 1.0 / 30.0, rtol=1e-9)
        assert 0.9 < s[0] < 1.1 and t.time_s[-1] == pytest.approx(s[-1] + 0.5, abs=0.011)
        assert t.protocol in ("isometric", "stretch") and (t.protocol == "isometric") == (t.length is None)
    # the passive force left in the isometric trials before activation is within the fit's scatter
    for tid in ("Figure7A_F43", "Figure7B_F51", "Figure7C_F59"):
        t = data.trials[tid]
        assert abs(np.median(t.force[t.time_s < 0.8])) < 0.5
    assert set(data.extra_datasets) >= {f"/preprocessing/passive/{p}/force_N" for p in
                                        ("Figure7A_F49", "Figure7B_F58", "Figure7C_F66")}


@needs_real_data
def test_preprocessing_is_documented_in_the_file(converted: Path) -> None:
    data = read_measured(converted)
    pre = data.extra_attrs["/preprocessing"]
    for word in ("Stimulus times", "30 Hz", "Length", "shift_mm", "Passive force", "Window"):
        assert word in pre["description"]
    assert pre["stimulus_rate_hz"] == 30.0 and pre["length_shift_mm"] == -8.0 and pre["tail_s"] == 0.5
    assert 100.0 < pre["model_rise50_ms"] < 120.0 and 110.0 < pre["model_fall50_ms"] < 130.0
    assert pre["passive_rms_N"] < 0.6
    for t in data.trials.values():
        for key in ("stimulation", "length_reference", "length_preprocessing", "passive_subtracted",
                    "passive_force_enhancement_N"):
            assert key in t.attrs, (t.trial_id, key)
    # force after deactivation above the passive curve grows with the stretch (Herzog & Leonard's finding)
    pfe = {k: data.trials[k].attrs["passive_force_enhancement_N"] for k in ("Figure7A_F45", "Figure7A_F47",
                                                                             "Figure7A_F50")}
    assert pfe["Figure7A_F45"] < pfe["Figure7A_F47"] < pfe["Figure7A_F50"] and pfe["Figure7A_F50"] > 2.0


@needs_real_data
def test_script_refuses_to_overwrite_and_names_unknown_figures(converted: Path, tmp_path: Path) -> None:
    before = converted.stat().st_mtime_ns
    run = subprocess.run([sys.executable, str(SCRIPT), "--out", str(converted), "--real-data", str(REAL_DATA)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "exists" in run.stderr and converted.stat().st_mtime_ns == before
    out = tmp_path / "x.h5"
    run = subprocess.run([sys.executable, str(SCRIPT), "--out", str(out), "--real-data", str(REAL_DATA),
                          "--figures", "Figure9"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "Figure9" in run.stderr and not out.exists()


@needs_real_data
def test_baseline_from_tetani_at_one_rate_misses_the_force_after_the_stretch(converted: Path, ct09) -> None:
    """Reduced form of the real-data diagnosis: Figure 7A's two isometric trials calibrate; at one rate C1 and C2
    are held; the isometric fit is within 6 % NRMSE, and after the 0 -> 9 mm stretch the measured force stays
    above the model's (force enhancement the baseline cannot make)."""
    from neuromuscle.analysis.metrics import nrmse_percent

    full = read_measured(converted)
    ids = ["Figure7A_F43", "Figure7A_F44", "Figure7A_F50"]
    data = MeasuredData(trials={i: full.trials[i] for i in ids}, attrs=full.attrs, path=full.path)
    b = calibrate_baseline(data, describe_all(data.trials), ["Figure7A_F43", "Figure7A_F44"], ct09)
    assert "C1" in b.held and "C2" in b.held and b.parameters["C1"] == ct09["C1"]
    assert "g2" in b.free and "KSE" not in b.free  # two isometric lengths, no movement among the calibration
    for i in ("Figure7A_F43", "Figure7A_F44"):
        assert nrmse_percent(data.trials[i].force, b.simulated[i]) < 6.0
    t = data.trials["Figure7A_F50"]
    hold = (t.time_s > 7.0) & (t.time_s < 9.5)  # seconds after the stretch ended (5.17 s)
    assert np.mean(t.force[hold] - b.simulated["Figure7A_F50"][hold]) > 3.0


@needs_real_data
@pytest.mark.slow
def test_the_full_diagnosis_names_force_enhancement(converted: Path) -> None:
    """The demo's diagnosis (Figure 7B held out, as networks/herzog_leonard_diagnosis.py runs it) names force
    enhancement after stretch first, and no other catalogue cause, removing at least a quarter of the held-out
    error above noise (rule R4's floor)."""
    from neuromuscle.diagnose import diagnose_data

    data = read_measured(converted)
    held = [i for i, t in data.trials.items() if t.attrs.get("figure") == "Figure7B"]
    d = diagnose_data(data, heldout=held, workers=2)
    assert d.named[:1] == ["force_enhancement_after_stretch"], d.named
    assert set(d.named) <= {"force_enhancement_after_stretch", "unexplained"}, d.named
    assert d.steps[0].candidates["force_enhancement_after_stretch"].evidence.excess_removed >= 0.25


@needs_real_data
def test_diagnosis_script_refuses_an_unknown_heldout_figure(converted: Path, tmp_path: Path) -> None:
    """networks/herzog_leonard_diagnosis.py (its full run is a benchmark; the baseline test above is its reduced
    form) names a held-out figure that no trial comes from, writes nothing, exits 2."""
    out = tmp_path / "report"
    run = subprocess.run([sys.executable, str(ROOT / "networks" / "herzog_leonard_diagnosis.py"), "--out", str(out),
                          "--data", str(converted), "--heldout-figure", "Figure9"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "Figure9" in run.stderr
    assert not out.exists() or not any(out.iterdir())
