"""``neuromuscle pool``: the plain form writes pool.h5 (with provenance), pool.nwb and pool.png with progress on
stderr; a definition file (TOML or JSON) with flags replacing its fields; bad input refused naming the file and the
field, with nothing written; an existing output kept unless --overwrite; under ``mpiexec -n 2`` the same pool as on
one rank, recordings included, written once."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from neuromuscle.cli import main
from neuromuscle.pool import load_pool_result
from neuromuscle.pool.mpi import mpi_available, mpiexec_command
from neuromuscle.pool.nwb import read_pool_nwb
from neuromuscle.pool.pool_file import pool_setup, read_document

pytestmark = pytest.mark.heavy(cost_s=65)

FILES = ("pool.h5", "pool.nwb", "pool.png")
NETWORKS = Path(__file__).resolve().parents[2] / "networks"


def test_the_plain_form_writes_hdf5_nwb_and_png(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["pool", "--units", "20", "--duration-ms", "500", "--drive", "ramp", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert "20 units on 1 rank(s), ramp drive, 500 ms" in captured.err and "100 %" in captured.err
    summary = json.loads(captured.out.strip().splitlines()[-1])
    assert all((out / f).is_file() for f in FILES) and (out / "pool.png").stat().st_size > 1000
    r = load_pool_result(out / "pool.h5")
    assert r.n_units == 20 and summary["recruited"] == sum(s.size > 0 for s in r.spikes_ms)
    # the recruitment ramp: units recruited in size order, human-like rates, derecruited by the end
    first = [s[0] for s in r.spikes_ms if s.size]
    assert len(first) >= 15 and first == sorted(first)
    rates = 1000.0 / np.concatenate([np.diff(s) for s in r.spikes_ms if s.size > 1])
    assert 5.0 < np.median(rates) < 35.0
    assert summary["medians_inside_human_range"] == 1.0 and len(summary["median_rates_p5_p50_p95_hz"]) == 3
    # Delta F needs test units recruited a second after their references, a coefficient of variation ten intervals
    # on the hold: neither in half a second
    assert summary["delta_f"]["pairs"] == 0 and summary["isi_cv_p5_p50_p95"] is None
    assert r.pool_force_N.argmax() < 0.85 * r.t_ms.size and r.pool_force_N[-1] < 0.5 * r.pool_force_N.max()
    prov = r.provenance
    assert prov["definition"]["drive"]["kind"] == "ramp" and prov["definition"]["units"]["count"] == 20
    assert prov["drive_detail"]["values_uS"] == [0.0, 0.7, 0.7, 0.0] and prov["mechanism_sha256"]
    assert prov["definition"]["units"]["motoneurons"] == "human" and prov["neuromodulation"] == 0.7
    assert prov["motoneuron_overrides"] == {"g_km_S_per_cm2": 0.002, "g_ks_S_per_cm2": 0.03}
    assert prov["versions"]["neuron"] and prov["muscle_parameters"]["name"] == "CT09"
    assert sum(u["P0_N"] for u in r.units) == pytest.approx(600.0)
    assert np.array_equal(read_pool_nwb(out / "pool.nwb").unit_force_N, r.unit_force_N)
    from nwbinspector import Importance, inspect_nwbfile

    serious = [m for m in inspect_nwbfile(nwbfile_path=str(out / "pool.nwb")) if m.importance in (
        Importance.CRITICAL, Importance.BEST_PRACTICE_VIOLATION, Importance.ERROR, Importance.PYNWB_VALIDATION)]
    assert not serious, [(m.check_function_name, m.message) for m in serious]
    # an existing output is kept
    before = (out / "pool.h5").read_bytes()
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--duration-ms", "50", "--out", str(out)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err and (out / "pool.h5").read_bytes() == before
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--duration-ms", "50", "--out", str(out),
                 "--overwrite", "--quiet"]) == 0
    assert load_pool_result(out / "pool.h5").n_units == 3 and capsys.readouterr().err == ""


TOML = """
name = "tibialis"
[units]
count = 4
types = [0.5, 0.25, 0.25]
smallest_p0_N = 0.5
[drive]
kind = "poisson"
rate_hz = 500.0
seed = 3
[length]
kind = "random"
seed = 2
band_hz = 20.0
[run]
duration_ms = 200.0
record_dt_ms = 0.5
[record]
variables = ["mn.v", "act.A", "ca.CaSPT", "mn.cai"]
units = [1, 3]
"""


def test_a_toml_file_with_a_flag_replacing_a_field(tmp_path, capsys):
    path = tmp_path / "pool.toml"
    path.write_text(TOML)
    out = tmp_path / "run"
    assert main(["pool", str(path), "--duration-ms", "150", "--out", str(out), "--quiet"]) == 0
    r = load_pool_result(out / "pool.h5")
    assert r.t_ms[-1] == 150.0 and r.t_ms[1] == 0.5 and r.drive == "poisson"
    assert [u["type"] for u in r.units] == ["S", "S", "FR", "FF"] and r.units[0]["P0_N"] == 0.5
    assert sorted(r.recordings) == ["act.A", "ca.CaSPT", "mn.cai", "mn.v"]
    assert all(rec.units == [1, 3] for rec in r.recordings.values())
    assert r.provenance["definition"]["length"] == {**r.provenance["definition"]["length"], "kind": "random",
                                                    "seed": 2}
    assert r.provenance["definition_file"] == str(path) and r.provenance["pool"] == "tibialis"


def test_the_shipped_example_definition_runs(tmp_path, capsys):
    example = NETWORKS / "human_pool.toml"
    assert main(["pool", str(example), "--units", "6", "--duration-ms", "300", "--record-units", "0,5",
                 "--out", str(tmp_path), "--quiet"]) == 0
    r = load_pool_result(tmp_path / "pool.h5")
    assert r.provenance["pool"] == "human" and r.t_ms[1] == 0.5
    assert sorted(r.recordings) == ["act.A", "ca.CaSPT", "mn.i_pic", "mn.v"] and r.recordings["mn.v"].units == [0, 5]
    full = json.loads(capsys.readouterr().out)
    assert full["recruited"] >= 5


REFLEX_TOML = """
[units]
count = 3
types = [1.0, 0.0, 0.0]
smallest_p0_N = 1.0
p0_range = 3.0
axon_length_mm = 150.0
neuromodulation = 1.0
[drive]
kind = "synaptic"
times_ms = [0.0, 700.0]
values_uS = [0.003, 0.003]
[length]
kind = "ramp"
mm = -10.0
to_mm = -4.0
velocity_mm_s = 30.0
start_ms = 100.0
[run]
duration_ms = 700.0
[reflex]
n_ia = 6
n_ii = 2
n_ib = 2
ia_weight_uS = 0.008
"""


def test_a_reflex_section_runs_the_stretch_reflex_and_cut_roots_open_it(tmp_path, capsys):
    """The [reflex] table with a ramp-and-hold length: the afferents fire at their equations' rates, the loop
    raises the discharge over cut dorsal roots, and the afferents' counts reach the summary and the provenance."""
    summaries, results = {}, {}
    for cut in (False, True):
        path = tmp_path / f"cut{cut}.toml"
        path.write_text(REFLEX_TOML + f"cut_dorsal_roots = {str(cut).lower()}\n")
        out = tmp_path / f"run{cut}"
        assert main(["pool", str(path), "--out", str(out)]) == 0
        captured = capsys.readouterr()
        assert "stretch reflex (6 Ia, 2 II, 2 Ib" in captured.err
        summaries[cut] = json.loads(captured.out.strip().splitlines()[-1])
        results[cut] = load_pool_result(out / "pool.h5")
    intact, cut = summaries[False], summaries[True]
    # the spindles read the same stretch either way; Ia: 82 /s at rest, 4.3 v^0.6 + 2 d above it
    assert intact["afferents"]["Ia"] == cut["afferents"]["Ia"] and intact["afferents"]["Ia"]["afferents"] == 6
    assert 90.0 < intact["afferents"]["Ia"]["mean_rate_hz"] < 110.0
    assert intact["spikes"] > cut["spikes"] and intact["peak_pool_force_N"] > cut["peak_pool_force_N"]
    assert cut["afferents"]["Ib_interneurons"]["spikes"] == 0 < intact["afferents"]["Ib_interneurons"]["spikes"]
    prov = results[False].provenance
    assert prov["afferents"] == intact["afferents"] and prov["definition"]["reflex"]["n_ia"] == 6
    assert prov["definition"]["length"]["kind"] == "ramp"


def test_the_shipped_stretch_reflex_definition_runs(tmp_path, capsys):
    assert main(["pool", str(NETWORKS / "stretch_reflex.toml"), "--units", "4",
                 "--out", str(tmp_path), "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["afferents"]["II"]["afferents"] == 4 and summary["afferents"]["Ib"]["spikes"] > 0


def test_the_shipped_stretch_reflex_definition_is_the_python_examples_pool(tmp_path, capsys, network_script):
    """networks/stretch_reflex.toml builds the units of networks/stretch_reflex.py (the cat soleus pool, sizes
    0-0.3) and, run by the command, discharges as that example's intact run does, spike for spike."""
    example = network_script("stretch_reflex")
    python_units = example.definition(10).units()
    setup = pool_setup(read_document(NETWORKS / "stretch_reflex.toml"), "stretch_reflex.toml")
    file_units = setup.definition.units()
    assert [u.motoneuron for u in file_units] == [u.motoneuron for u in python_units]
    assert [u.muscle["P0"] for u in file_units] == pytest.approx([u.muscle["P0"] for u in python_units], rel=1e-12)
    assert main(["pool", str(NETWORKS / "stretch_reflex.toml"), "--out", str(tmp_path), "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out)
    python_run = example.run(10, -10.0, -4.0, 30.0, 1200.0, 0.003, False)["result"]
    recruited = sum(s.size > 0 for s in python_run.spikes_ms)
    assert summary["recruited"] == recruited >= 8
    r = load_pool_result(tmp_path / "pool.h5")
    assert all(np.array_equal(a, b) for a, b in zip(r.spikes_ms, python_run.spikes_ms))


def test_size_flags_replace_the_files_fields(tmp_path, capsys):
    (tmp_path / "pool.toml").write_text('[units]\ncount = 3\nsmallest_p0_N = 0.5\nmax_size = 0.3\n'
                                        '[run]\nduration_ms = 50.0\n')
    assert main(["pool", str(tmp_path / "pool.toml"), "--max-size", "0.2", "--size-spacing", "5",
                 "--out", str(tmp_path / "run"), "--quiet"]) == 0
    units = load_pool_result(tmp_path / "run" / "pool.h5").provenance["definition"]["units"]
    assert (units["max_size"], units["size_spacing"]) == (0.2, 5.0)
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--max-size", "2", "--out", str(tmp_path / "x")]) == 2
    assert "--max-size must be in [0, 1] (a size index), got 2.0" in capsys.readouterr().err


def test_a_definition_without_a_reflex_section_builds_no_afferents(tmp_path, capsys):
    (tmp_path / "pool.toml").write_text('[units]\ncount = 2\nsmallest_p0_N = 0.5\n[run]\nduration_ms = 50.0\n')
    assert main(["pool", str(tmp_path / "pool.toml"), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    assert "afferents" not in json.loads(capsys.readouterr().out)
    assert "reflex" not in load_pool_result(tmp_path / "run" / "pool.h5").provenance["definition"]


def test_a_parameter_file_is_read_beside_the_definition(tmp_path, ct09):
    folder = tmp_path / "experiment"
    folder.mkdir()
    ct09.with_values(P0=30.0).save(folder / "mine.json")
    (folder / "pool.toml").write_text('[units]\ncount = 2\nparams = "mine.json"\nsmallest_p0_N = 0.5\n'
                                      '[run]\nduration_ms = 50.0\n')
    assert main(["pool", str(folder / "pool.toml"), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    prov = load_pool_result(tmp_path / "run" / "pool.h5").provenance
    assert prov["muscle_parameters"]["parameters"]["P0"]["value"] == 30.0


def test_a_json_file_gives_the_same_pool_as_the_flags(tmp_path):
    doc = {"units": {"count": 3, "total_p0_N": 30.0}, "drive": {"kind": "rise", "peak_uS": 0.5},
           "run": {"duration_ms": 150.0}}
    path = tmp_path / "pool.json"
    path.write_text(json.dumps(doc))
    assert main(["pool", str(path), "--out", str(tmp_path / "a"), "--quiet"]) == 0
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--drive", "rise", "--peak-us", "0.5",
                 "--duration-ms", "150", "--out", str(tmp_path / "b"), "--quiet"]) == 0
    a, b = load_pool_result(tmp_path / "a" / "pool.h5"), load_pool_result(tmp_path / "b" / "pool.h5")
    assert np.array_equal(a.unit_force_N, b.unit_force_N) and a.pool_force_N.max() > 0.0


def test_the_noise_flags_reach_the_pool_and_its_provenance(tmp_path):
    doc = {"units": {"count": 3, "total_p0_N": 30.0, "synaptic_noise_uS": 0.05, "noise_seed": 4},
           "drive": {"kind": "rise", "peak_uS": 0.5}, "run": {"duration_ms": 300.0}}
    path = tmp_path / "pool.json"
    path.write_text(json.dumps(doc))
    assert main(["pool", str(path), "--out", str(tmp_path / "a"), "--quiet"]) == 0
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--drive", "rise", "--peak-us", "0.5",
                 "--synaptic-noise-us", "0.05", "--noise-seed", "4", "--duration-ms", "300",
                 "--out", str(tmp_path / "b"), "--quiet"]) == 0
    assert main(["pool", str(path), "--noise-seed", "5", "--out", str(tmp_path / "c"), "--quiet"]) == 0
    a, b, c = (load_pool_result(tmp_path / x / "pool.h5") for x in "abc")
    assert all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms)) and sum(map(len, a.spikes_ms)) > 5
    assert not all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, c.spikes_ms))
    assert (a.provenance["synaptic_noise_uS"], a.provenance["noise_seed"]) == (0.05, 4)


def test_set_replaces_the_reduced_cells_parameters_over_the_profiles(tmp_path):
    base = ["pool", "--units", "3", "--total-p0-n", "30", "--drive", "rise", "--peak-us", "0.8", "--duration-ms",
            "400", "--quiet"]
    path = tmp_path / "pool.toml"
    path.write_text('[units]\nset = {g_km_S_per_cm2 = 0.0, cal_vhalf_mV = -52.0}\n')
    assert main(base + ["--out", str(tmp_path / "human")]) == 0
    assert main(base + ["--set", "g_km_S_per_cm2=0", "--set", "cal_vhalf_mV=-52", "--out", str(tmp_path / "a")]) == 0
    assert main([base[0], str(path)] + base[1:] + ["--out", str(tmp_path / "b")]) == 0
    human, a, b = (load_pool_result(tmp_path / x / "pool.h5") for x in ("human", "a", "b"))
    assert a.provenance["motoneuron_overrides"] == {"g_km_S_per_cm2": 0.0, "g_ks_S_per_cm2": 0.03,
                                                    "cal_vhalf_mV": -52.0}        # the profile's slow K kept
    assert all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, b.spikes_ms))      # flags = the file's table
    assert not all(np.array_equal(x, y) for x, y in zip(a.spikes_ms, human.spikes_ms))


def test_a_bad_setting_flag_is_refused_by_name(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["pool", "--set", "gkm=0", "--out", str(tmp_path / "run")])
    assert "argument --set: motoneuron setting 'gkm=0': no parameter 'gkm'" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("text, message", [
    ('[units]\ncount = 0\n', "pool.toml: units.count must be an integer >= 1, got 0"),
    ('[units]\ncuont = 3\n', "pool.toml: [units] has no field 'cuont'"),
    ('[drive]\nkind = "ramp"\npeak_uS = -1\n', "pool.toml: drive.peak_uS must be > 0, got -1"),
    ('[drive]\nkind = "tremor"\n', "pool.toml: drive.kind must be one of ramp, rise, synaptic, current, poisson"),
    ('[drive]\nkind = "synaptic"\ntimes_ms = [0, 100]\n', "pool.toml: drive.values_uS: the synaptic drive needs"),
    ('[units]\ntypes = [0.5, 0.5, 0.5]\n', "pool.toml: units.types (S, FR, FF fractions) must be >= 0 and sum to 1"),
    ('[units]\nparams = "CT99"\n', "pool.toml: units.params"),
    ('[run]\nduration_ms = "long"\n', "pool.toml: run.duration_ms must be a finite number"),
    ('[record]\nvariables = ["mn.w"]\n', "cannot record ['mn.w']"),
    ('[record]\nunits = [1]\n', "pool.toml: record.units is given without record.variables"),
    ('[muscle]\nP0 = 3\n', "pool.toml: unknown section 'muscle'"),
    ('[units\ncount = 3\n', "pool.toml: not valid TOML"),
    ('[reflex]\nn_ia = -1\n', "pool.toml: reflex.n_ia must be an integer >= 0, got -1"),
    ('[reflex]\nn_ia_ = 3\n', "pool.toml: [reflex] has no field 'n_ia_'"),
    ('[reflex]\ncut_dorsal_roots = "yes"\n', "pool.toml: reflex.cut_dorsal_roots must be true or false"),
    ('[reflex]\nia_weight_uS = {S = 0.004}\n', "pool.toml: reflex.ia_weight_uS needs one weight (uS) for each"),
    ('[reflex]\nia_weight_uS = {S = 0.004, FR = -1, FF = 0}\n', "pool.toml: reflex.ia_weight_uS.FR must be"),
    ('[reflex]\nii_delay_ms = 0\n', "pool.toml: reflex.ii_delay_ms must be > 0, got 0"),
    ('[length]\nkind = "ramp"\nvelocity_mm_s = 0\n', "pool.toml: length.velocity_mm_s must be > 0"),
    ('[length]\nkind = "ramp"\nstart_ms = 400\n', "pool.toml: [length]: duration_ms (500.0 ms) ends before"),
    ('[length]\nkind = "stretch"\n', "pool.toml: length.kind must be one of isometric, random, ramp"),
    ('[units]\nmax_size = -0.1\n', "pool.toml: units.max_size must be in [0, 1] (a size index), got -0.1"),
    ('[units]\nsize_spacing = 0\n', "pool.toml: units.size_spacing must be >= 1"),
    ('[units]\nset = 3\n', "pool.toml: units.set must be a table of motoneuron parameters and numbers"),
    ('[units]\nset = {g_km_S_per_cm2 = "x"}\n', "pool.toml: units.set: every value must be a number"),
    ('[units]\nset = {gkm = 0}\n', "pool.toml: units.set: motoneuron setting 'gkm=0': no parameter 'gkm'"),
    ('[units]\nset = {neuromodulation = 0}\n', "pool.toml: units.set: motoneuron setting 'neuromodulation=0'"),
    ('[units]\nset = {g_km_S_per_cm2 = 0}\n[motoneuron]\nswc = "cell.swc"\n',
     "pool.toml: units.set sets the reduced cells' parameters; reconstructed cells"),
])
def test_bad_definitions_are_refused_naming_file_and_field_with_nothing_written(tmp_path, capsys, text, message):
    path = tmp_path / "pool.toml"
    path.write_text(text)
    out = tmp_path / "run"
    assert main(["pool", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.startswith("neuromuscle: error:")
    assert not out.exists()


def test_bad_flags_are_refused_naming_the_flag(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["pool", "--units", "3", "--duration-ms", "-5", "--out", str(out)]) == 2
    assert "--duration-ms must be > 0, got -5" in capsys.readouterr().err
    assert main(["pool", "--units", "3", "--total-p0-n", "30", "--record-units", "7", "--record", "mn.v",
                 "--out", str(out)]) == 2
    assert "--record-units must be distinct unit indices 0..2" in capsys.readouterr().err
    assert main(["pool", "--units", "3", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "command line: [units]: parameter set 'CT09': parameter 'P0'" in err and "--total-p0-n" in err
    assert main(["pool", str(tmp_path / "absent.toml"), "--out", str(out)]) == 2
    assert "absent.toml: no such definition file" in capsys.readouterr().err
    assert not out.exists()


needs_mpi = pytest.mark.skipif(not mpi_available(), reason="the mpi extra is not installed (mpich + mpi4py: "
                                                           "pip install -e '.[test,mpi]')")


@needs_mpi
@pytest.mark.parametrize("engine", ["neuron", "coreneuron"])
def test_two_ranks_write_the_same_pool_and_recordings_as_one(tmp_path, engine):
    """Units 0, 2, 4 on rank 0 and 1, 3 on rank 1: rank 0 records two units, rank 1 one (CoreNEURON's
    every-step recordings are emptied at the same times on both)."""
    args = ["--units", "5", "--duration-ms", "200", "--engine", engine, "--record", "mn.v", "--record", "mn.i_pic",
            "--record", "act.A", "--record", "ca.CaSPT", "--record-units", "0,1,4"]
    runs = {}
    for n in (1, 2):
        out = tmp_path / f"ranks{n}"
        cmd = mpiexec_command(n, ["-m", "neuromuscle.cli", "pool", *args, "--out", str(out)])
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        assert proc.stderr.count("units on") == 1 and proc.stdout.count('"files"') == 1  # rank 0 alone speaks
        runs[n] = load_pool_result(out / "pool.h5")
    one, two = runs[1], runs[2]
    assert (one.ranks, two.ranks) == (1, 2) and sum(s.size for s in one.spikes_ms) > 5
    assert all(np.array_equal(a, b) for a, b in zip(one.spikes_ms, two.spikes_ms))
    assert np.array_equal(one.unit_force_N, two.unit_force_N)
    assert sorted(two.recordings) == ["act.A", "ca.CaSPT", "mn.i_pic", "mn.v"]
    for name, rec in one.recordings.items():
        assert two.recordings[name].units == [0, 1, 4] and np.array_equal(two.recordings[name].values, rec.values)
    nwb = read_pool_nwb(tmp_path / "ranks2" / "pool.nwb")
    assert np.array_equal(nwb.recordings["mn.v"].values, one.recordings["mn.v"].values)


@needs_mpi
def test_bad_input_under_mpi_is_one_message_and_nothing_written(tmp_path):
    out = tmp_path / "never"
    cmd = mpiexec_command(2, ["-m", "neuromuscle.cli", "pool", "--units", "1", "--total-p0-n", "5",
                              "--duration-ms", "50", "--out", str(out)])
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert proc.stderr.count("neuromuscle: error") == 1 and "2 MPI ranks for a pool of 1 units" in proc.stderr
    assert not out.exists()


def test_the_command_is_listed(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "pool" in capsys.readouterr().out


@needs_mpi
def test_a_pool_of_reconstructed_cells_on_two_ranks_is_the_one_rank_pool(tmp_path):
    """The shipped example of reconstructed cells (an SWC morphology read by Import3d on every rank), shortened."""
    runs = {}
    for n in (1, 2):
        out = tmp_path / f"ranks{n}"
        cmd = mpiexec_command(n, ["-m", "neuromuscle.cli", "pool", str(NETWORKS / "reconstructed_pool.toml"),
                                  "--units", "3", "--total-p0-n", "30", "--duration-ms", "300", "--out", str(out),
                                  "--quiet"])
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        runs[n] = load_pool_result(out / "pool.h5")
    one, two = runs[1], runs[2]
    assert one.provenance["definition"]["motoneuron"]["swc"].endswith("small_motoneuron.swc")
    assert sum(s.size for s in one.spikes_ms) > 5 and one.recordings["mn.v_dend"].units == [0]
    assert all(np.array_equal(a, b) for a, b in zip(one.spikes_ms, two.spikes_ms))
    assert np.array_equal(one.unit_force_N, two.unit_force_N)
    assert np.array_equal(one.recordings["mn.v"].values, two.recordings["mn.v"].values)
