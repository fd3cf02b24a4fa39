"""The example networks run their small defaults from a temporary folder and write their outputs."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from neuromuscle.pool import load_pool_result
from neuromuscle.pool.discharge_stats import HUMAN_PEAK_RATE_HZ

NETWORKS = Path(__file__).resolve().parents[2] / "networks"
CAILLET = NETWORKS.parent.parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"


def test_cat_soleus_pool_default(tmp_path, monkeypatch, network_script):
    monkeypatch.chdir(tmp_path)
    s = network_script("cat_soleus_pool").main(["--out", "out"])
    assert s["units"] == 20 and s["recruited"] >= 15 and 5.0 < s["peak_pool_force_N"] <= 23.0
    r = load_pool_result(tmp_path / "out" / "cat_soleus_ramp.h5")
    assert [u["type"] for u in r.units].count("S") == 19 and r.provenance["pool"] == "cat_soleus"
    with h5py.File(tmp_path / "out" / "cat_soleus_ramp.h5") as f:
        rel = f["force_frequency/relative"][()]
        assert rel.shape == (2, 10) and rel[0, -1] > 0.9 and rel[0, 0] < 0.1  # fused at 100 Hz, not at 2 Hz
        assert "mechanism_sha256" in f["force_frequency"].attrs["provenance"]
    for png in ("cat_soleus_ramp.png", "cat_soleus_summary.png"):
        assert (tmp_path / "out" / png).stat().st_size > 10_000


def test_human_pool_default(tmp_path, network_script):
    s = network_script("human_pool").main(["--out", str(tmp_path / "out")])
    assert s["units"] == 20 and s["recruited"] == 20
    # human motoneurons at the example's drive: every unit's median rate within the recorded human range
    assert s["medians_inside_human_range"] == 1.0 and s["unit_peak_rate_max_hz"] <= 1.5 * HUMAN_PEAK_RATE_HZ
    moving = load_pool_result(tmp_path / "out" / "human_length.h5")
    ramp = load_pool_result(tmp_path / "out" / "human_ramp.h5")
    assert {u["type"] for u in ramp.units} == {"S", "FR", "FF"}
    assert moving.provenance["length_mm"] != ramp.provenance["length_mm"]  # the random length was used
    assert (tmp_path / "out" / "human_summary.png").stat().st_size > 10_000
    with pytest.raises(Exception, match="already holds"):
        network_script("human_pool").main(["--out", str(tmp_path / "out")])  # no silent overwrite


def test_reconstructed_pool_prints_its_figures(tmp_path, capsys, network_script):
    """The pool of reconstructed_pool.toml, shortened: every unit recruited by the ramp, the figures printed as
    JSON and written beside the result and its figure."""
    s = network_script("reconstructed_pool").main(["--out", str(tmp_path / "out"), "--units", "3",
                                                   "--duration-ms", "400"])
    assert json.loads(capsys.readouterr().out.strip().splitlines()[-1]) == s
    assert json.loads((tmp_path / "out" / "reconstructed_pool.json").read_text()) == s
    assert s["units"] == 3 and s["recruited"] == 3 and s["peak_pool_force_N"] > 0.0
    assert s["unit0_v_range_mV"][1] > 0.0 and s["unit0_v_dend_range_mV"][1] > s["unit0_v_dend_range_mV"][0]
    r = load_pool_result(tmp_path / "out" / "pool.h5")
    assert r.provenance["definition"]["motoneuron"]["swc"].endswith("small_motoneuron.swc")
    assert (tmp_path / "out" / "reconstructed_pool.png").stat().st_size > 10_000


@pytest.mark.slow
@pytest.mark.skipif(not CAILLET.is_dir(), reason=f"Caillet real-data folder {CAILLET} is absent")
def test_recorded_discharges_default(tmp_path, network_script):
    s = network_script("recorded_discharges").main(["--out", str(tmp_path / "out")])
    assert s["file"] == "S1_30_36L.mat" and s["units"] == 17
    assert s["human_units"]["nrmse_heldout_percent"] < 30.0 and s["twitch_sum"]["nrmse_heldout_percent"] < 30.0
    with h5py.File(tmp_path / "out" / "discharges.h5") as f:
        assert f.attrs["force_unit"] == "% MVC" and f["unit_p0_relative"].shape == (17,)
        assert f["predicted_force_human_units"].shape == f["recorded_force"].shape
    assert (tmp_path / "out" / "discharges.png").stat().st_size > 10_000


@pytest.mark.skipif(not CAILLET.is_dir(), reason=f"Caillet real-data folder {CAILLET} is absent")
def test_pool_vs_recorded_briefly(tmp_path, network_script):
    script = network_script("pool_vs_recorded")
    s = script.main(["--out", str(tmp_path / "out"), "--units", "12", "--corrections", "1", "--dt-ms", "0.05",
                     "--neuromodulation", "0.6", "--set", "ks_tau_ms=8000",   # g_ks 0: the slow K stays out
                     "--scale", "ca_decay_ms=1.1", "--calibration-top-uS", "1.3",
                     "--calibration-ramp-ms", "12000"])
    row = s["files"][0]
    assert row["pool"]["motoneuron_overrides"] == {"ks_tau_ms": 8000.0} and row["pool"]["neuromodulation"] == 0.6
    assert row["pool"]["motoneuron_scales"] == {"ca_decay_ms": 1.1} and row["pool"]["calibration_top_uS"] == 1.3
    assert row["pool"]["calibration_ramp_ms"] == 12000.0
    for bad in (["--set", "ks_tau_ms"], ["--scale", "ks_tau_ms=2"],      # no value; not a size-dependent one
                ["--calibration-ramp-ms", "0"], ["--calibration-top-uS", "nan"]):
        with pytest.raises(SystemExit):
            script.main(["--out", str(tmp_path / "bad"), *bad])
    assert row["file"] == "S1_30_36L.mat" and row["muscle"] == "TA"
    assert row["nrmse_percent"] < 10.0 < row["nrmse_percent_passes"][0]   # the correction brings the force in
    crit = row["summary"]["criteria"]
    assert set(crit) == {"medians_inside", "peak_ratio", "thresholds_ks", "onion_skin", "delta_f_hz"}
    assert row["summary"]["model_units"] >= 3 and crit["peak_ratio"]["value"] < 3.0
    assert np.isfinite(crit["delta_f_hz"]["recorded"])
    ident = row["summary"]["identified"]                           # the units a decomposition would find
    assert ident["identification"]["count"] == 17 == sum(ident["identification"]["weights"])
    assert set(ident["criteria"]) == set(crit) and row["identification"]["seed"] == 0
    assert row["identification"]["depth_attenuation"] == ident["identification"]["model"]["depth_attenuation"]
    for name in ("S1_30_36L.png", "S1_30_36L.json", "S1_30_36L_pool.h5", "pool_vs_recorded.md"):
        assert (tmp_path / "out" / name).stat().st_size > 200
    assert load_pool_result(tmp_path / "out" / "S1_30_36L_pool.h5").drive == "synaptic"
    assert row["pool"]["p0_spread_fitted_to"] == "published thresholds" and row["pool"]["fit_seeds"] is None


@pytest.mark.skipif(not CAILLET.is_dir(), reason=f"Caillet real-data folder {CAILLET} is absent")
def test_pool_vs_recorded_with_the_spread_fitted_to_the_file(tmp_path, network_script):
    script = network_script("pool_vs_recorded")
    row = script.main(["--out", str(tmp_path / "out"), "--units", "12", "--corrections", "0", "--dt-ms", "0.05",
                       "--p0-spread", "recording", "--motoneurons", "human", "--set", "g_ks_S_per_cm2=0.01",
                       "--scale", "ca_decay_ms=2", "--calibration-top-uS", "1.6", "--selection", "sampled"])["files"][0]
    pool = row["pool"]
    assert row["identification"]["selection"] == "sampled"         # the units drawn in proportion to their weights
    # the human profile, with --set replacing one of its values and --scale multiplying its AHP factor
    assert pool["motoneurons"] == "human" and pool["neuromodulation"] == 0.7
    assert pool["motoneuron_overrides"] == {"g_km_S_per_cm2": 0.002, "g_ks_S_per_cm2": 0.01}
    assert pool["motoneuron_scales"] == {"ca_decay_ms": pytest.approx(2.6)}
    assert pool["p0_spread_fitted_to"] == "recorded thresholds" and pool["fit_seeds"] == [100, 109]
    assert 30.5 < pool["fit_active_below_percent_mvc"] < 32.0   # S1_30_36L's force peaks above its 30 % plateau
    assert 0.0 <= pool["identified_thresholds_ks_fit"] < 0.5 and 1.5 <= pool["p0_range"] <= 100.0
    assert row["units"]["p0_N"][-1] == pytest.approx(pool["p0_range"])
