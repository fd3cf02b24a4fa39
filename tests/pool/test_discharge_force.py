"""Force from a discharge file, end to end: both models fitted on the first half, HDF5 with provenance (parameters,
versions, mechanism hash, input file and its hash), figure and summary; a bad file is refused writing nothing."""

import hashlib
import json
from pathlib import Path

import h5py
import numpy as np
import pytest
import scipy.io

from neuromuscle.errors import InputError
from neuromuscle.pool.discharge_force import FILES, calibration_thresholds, read_discharges, run_discharges

FS = 2048.0


def test_run_writes_both_fits_with_provenance(tmp_path, small_caillet):
    src = small_caillet(tmp_path / "X_20.mat")
    s = run_discharges(src, tmp_path / "out", dt_ms=0.1)
    assert s["units"] == 4 and s["level_percent_mvc"] == 20.0
    for model in ("human_units", "twitch_sum"):
        assert s[model]["nrmse_heldout_percent"] < 30.0 and s[model]["nrmse_calibration_percent"] < 30.0
    for name in FILES:
        assert (tmp_path / "out" / name).stat().st_size > 500
    with h5py.File(tmp_path / "out" / FILES[0], "r") as f:
        prov = json.loads(f.attrs["provenance"])
        assert prov["input_sha256"] == hashlib.sha256(src.read_bytes()).hexdigest()
        assert prov["input_file"].endswith("X_20.mat") and len(prov["mechanism_sha256"]) == 64
        assert prov["format"] == "caillet" and "openhdemg_version" not in prov
        assert prov["parameters"]["kim_m3.P0"] > 0 and "neuron" in prov["versions"]
        assert json.loads(f.attrs["human_units_fit"])["nrmse_heldout_percent"] == pytest.approx(
            s["human_units"]["nrmse_heldout_percent"])
        assert f["predicted_force_human_units"].shape == f["recorded_force"].shape == f["t_ms"].shape
        assert len(f["discharges_ms"]) == 4 and np.all(np.diff(f["threshold_percent_mvc"][()]) >= 0)
    # an existing report is not replaced
    with pytest.raises(InputError, match="refusing to overwrite"):
        run_discharges(src, tmp_path / "out", dt_ms=0.1)


def test_bad_file_is_refused_and_nothing_is_written(tmp_path):
    scipy.io.savemat(tmp_path / "Y_30.mat", {"fsamp": np.array([[FS]]), "ref_signal": np.zeros((1, 100))})
    with pytest.raises(InputError, match=r"Y_30\.mat: field 'MUPulses' is missing"):
        run_discharges(tmp_path / "Y_30.mat", tmp_path / "out")
    assert not (tmp_path / "out").exists()
    with pytest.raises(InputError, match="the rest is held out"):
        run_discharges(tmp_path / "Y_30.mat", tmp_path / "out", calibration_fraction=1.0)
    with pytest.raises(InputError, match=r"Y_30\.csv: cannot tell the format"):
        read_discharges(tmp_path / "Y_30.csv")
    with pytest.raises(InputError, match="format must be one of"):
        read_discharges(tmp_path / "Y_30.mat", fmt="excel")


CAILLET = Path(__file__).resolve().parents[2].parent / "shared" / "real_data" / "human_mu_spike_trains_caillet"


@pytest.mark.skipif(not CAILLET.is_dir(), reason=f"Caillet real-data folder {CAILLET} is absent")
def test_real_file_thresholds_come_from_the_calibration_half():
    rec = read_discharges(CAILLET / "S1_30_36L.mat")
    assert rec.n_units == 17 and rec.level_percent_mvc == 30.0
    trial = rec.trial()
    whole = rec.thresholds_percent_mvc()[trial.units]
    half = calibration_thresholds(trial, 0.5 * trial.duration_ms)
    assert np.allclose(half, whole)  # every unit of this trial is recruited on the ramp up, in the first half
    early = calibration_thresholds(trial, 6000.0)  # a window ending on the ramp: later units get its top force
    late = np.array([d[0] for d in trial.discharges_ms]) >= 6000.0
    assert late.any() and np.allclose(early[late], trial.force_percent_mvc[trial.force_t_ms < 6000.0].max())
    assert np.allclose(early[~late], whole[~late])
