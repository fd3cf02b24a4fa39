"""openhdemg files through the openhdemg package: its JSON (written from the shared vastus lateralis sample) and its
bundled OTBiolab+ export load as discharges in ms and force in % MVC; bad files are refused naming file and field."""

import gzip
import json
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.openhdemg_files import load_openhdemg

openfiles = pytest.importorskip("openhdemg.library.openfiles")

SAMPLE = Path(__file__).resolve().parents[2].parent / "shared" / "real_data" / "human_vl_openhdemg_sample"
needs_sample = pytest.mark.skipif(not SAMPLE.is_dir(), reason=f"openhdemg sample folder {SAMPLE} is absent")


def write_json(path: Path, pulses: list, force: np.ndarray, fs: float = 2048.0) -> Path:
    """An openhdemg JSON file (through openhdemg's own writer) with these discharge samples and force."""
    import pandas as pd

    n = len(pulses)
    emgfile = {"SOURCE": "CUSTOMCSV", "FILENAME": path.name, "RAW_SIGNAL": pd.DataFrame(np.zeros((4, 1))),
               "REF_SIGNAL": pd.DataFrame(np.asarray(force, float)), "ACCURACY": pd.DataFrame(np.zeros((1, n))),
               "IPTS": pd.DataFrame(np.zeros((4, n))), "MUPULSES": [np.asarray(p) for p in pulses], "FSAMP": fs,
               "IED": 8.0, "EMG_LENGTH": len(force), "NUMBER_OF_MUS": n,
               "BINARY_MUS_FIRING": pd.DataFrame(np.zeros((4, n))), "EXTRAS": pd.DataFrame()}
    openfiles.save_json_emgfile(emgfile, str(path))
    return path


def sample_json(path: Path) -> Path:
    """The shared sample (4 units, force in % MVC) as an openhdemg JSON file; discharge samples from its start."""
    z = np.load(SAMPLE / "vl_4mu_force.npz")
    fs, t0 = float(z["fs"]), float(z["time_s"][0])
    pulses = [np.round((z[f"mu{i}_spike_times_s"] - t0) * fs).astype(int) for i in range(4)]
    return write_json(path, pulses, z["force_pct_mvc"], fs)


@needs_sample
def test_sample_json_loads_in_ms_and_percent_mvc(tmp_path):
    rec = load_openhdemg(sample_json(tmp_path / "vl.json"))
    z = np.load(SAMPLE / "vl_4mu_force.npz")
    assert rec.n_units == 4 and rec.fsamp_hz == 2048.0
    assert np.allclose(rec.discharges_ms[1], (z["mu1_spike_times_s"] - 7.0) * 1000.0, atol=0.25)
    assert np.allclose(rec.force_percent_mvc, z["force_pct_mvc"], atol=1e-4)
    assert 20.0 < rec.level_percent_mvc < 30.0  # plateau about 26 % MVC
    trial = rec.trial()
    assert len(trial.discharges_ms) == 4 and np.all(np.diff(rec.thresholds_percent_mvc()[trial.units]) >= 0)


def test_openhdemg_bundled_otb_export_loads():
    path = Path(openfiles.__file__).parent / "decomposed_test_files" / "otb_testfile.mat"
    if not path.is_file():
        pytest.skip("this openhdemg build ships no OTB test file")
    rec = load_openhdemg(path, kind="otb")
    assert rec.n_units >= 4 and rec.fsamp_hz == 2048.0 and 15.0 < rec.level_percent_mvc < 40.0


def test_bad_files_are_refused_naming_file_and_field(tmp_path):
    force = np.concatenate([np.zeros(200), np.full(800, 20.0)])
    with pytest.raises(InputError, match=r"late\.json: field 'MUPULSES' unit 0: sample 1000 lies outside"):
        load_openhdemg(write_json(tmp_path / "late.json", [[300, 400, 1000]], force))
    with pytest.raises(InputError, match=r"order\.json: field 'MUPULSES' unit 1"):
        load_openhdemg(write_json(tmp_path / "order.json", [[300, 400], [500, 450]], force))
    with pytest.raises(InputError, match=r"raw\.json: field 'REF_SIGNAL' is not in % MVC"):
        load_openhdemg(write_json(tmp_path / "raw.json", [[300, 400]], force * 1e6))
    # with the level given, a raw force is normalised: plateau at the level
    rec = load_openhdemg(tmp_path / "raw.json", level_percent_mvc=30.0)
    assert rec.force_percent_mvc[-1] == pytest.approx(30.0)
    # a field missing from the JSON: openhdemg's reader fails, the message names the file
    doc = json.loads(gzip.open(tmp_path / "late.json", "rt").read())
    del doc["MUPULSES"]
    with gzip.open(tmp_path / "nofield.json", "wt") as f:
        json.dump(doc, f)
    with pytest.raises(InputError, match=r"nofield\.json: not a readable openhdemg json file \(KeyError: 'MUPULSES'"):
        load_openhdemg(tmp_path / "nofield.json")
    (tmp_path / "junk.json").write_text("not gzip")
    with pytest.raises(InputError, match=r"junk\.json: not a readable openhdemg json file"):
        load_openhdemg(tmp_path / "junk.json")
    with pytest.raises(InputError, match=r"x\.mat: openhdemg file kind must be one of json, otb, demuse"):
        (tmp_path / "x.mat").write_bytes(b"")
        load_openhdemg(tmp_path / "x.mat")
    with pytest.raises(InputError, match="no such file"):
        load_openhdemg(tmp_path / "absent.json")


def test_command_route_on_an_openhdemg_file_records_its_provenance(tmp_path, small_caillet):
    import h5py

    from neuromuscle.pool.discharge_force import run_discharges
    from neuromuscle.pool.discharges import load_caillet

    rec = load_caillet(small_caillet(tmp_path / "X_20.mat"))
    pulses = [np.round(d * rec.fsamp_hz / 1000.0).astype(int) for d in rec.discharges_ms]
    src = write_json(tmp_path / "x.json", pulses, rec.force_percent_mvc, rec.fsamp_hz)
    s = run_discharges(src, tmp_path / "out", dt_ms=0.1)
    assert s["units"] == 4 and s["level_percent_mvc"] == pytest.approx(20.0, rel=0.05)
    with h5py.File(tmp_path / "out" / "discharges.h5", "r") as f:
        prov = json.loads(f.attrs["provenance"])
    assert prov["format"] == "openhdemg-json" and prov["openhdemg_version"] == version("openhdemg")
