"""A pool run described as data (neuromuscle.pool.pool_file): defaults are the human pool; fields map onto the
definition, drive, length, simulator and recordings; unknown sections and fields, wrong types and impossible values
are refused naming the source and the field (or the flag that set it); TOML and JSON read alike."""

import json

import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool.pool_file import merge, pool_setup, read_document
from neuromuscle.protocols import LengthTrace


def test_defaults_are_the_human_pool():
    s = pool_setup({}, "test")
    d = s.definition
    assert d.n_units == 20 and d.type_fractions == (0.7, 0.2, 0.1) and d.axon_length_mm == 900.0
    assert sum(u.muscle["P0"] for u in d.units()) == pytest.approx(600.0)
    assert d.units()[-1].muscle["P0"] / d.units()[0].muscle["P0"] == pytest.approx(100.0)
    assert s.drive.values == (0.0, 0.7, 0.7, 0.0) and s.drive.times_ms == (0.0, 250.0, 375.0, 500.0)
    human = d.units()[0].motoneuron
    assert d.neuromodulation == 0.7 and human.g_km_S_per_cm2 == 0.002 and human.g_ks_S_per_cm2 == 0.03
    assert human.ca_decay_ms == pytest.approx(1.3 * 45.0)
    assert s.length == -8.0 and s.duration_ms == 500.0 and s.record_dt_ms == 1.0 and s.recordings is None
    assert (s.simulator.method, s.simulator.dt_ms, s.simulator.engine) == ("fixed", 0.025, "neuron")
    assert s.simulator.secondorder == 0
    assert pool_setup({"run": {"secondorder": 2}}, "test").simulator.secondorder == 2


def test_the_motoneuron_profile_and_an_explicit_neuromodulation():
    plain = pool_setup({"units": {"motoneurons": "default"}}, "test").definition
    assert plain.neuromodulation == 0.6 and not plain.motoneuron_overrides and not plain.motoneuron_scales
    assert plain.units()[0].motoneuron.g_km_S_per_cm2 == 0.0
    mine = pool_setup({"units": {"neuromodulation": 0.3}}, "test").definition
    assert mine.neuromodulation == 0.3 and mine.motoneuron_overrides["g_km_S_per_cm2"] == 0.002
    with pytest.raises(InputError, match=r"units\.motoneurons.*default, human"):
        pool_setup({"units": {"motoneurons": "cat"}}, "test")


def test_the_synaptic_noise_is_off_unless_set():
    human = pool_setup({}, "test").definition
    assert human.synaptic_noise_uS == 0.0 and human.noise_seed == 0
    mine = pool_setup({"units": {"synaptic_noise_uS": 0.02, "noise_seed": 9}}, "test").definition
    assert (mine.synaptic_noise_uS, mine.noise_seed) == (0.02, 9)
    quiet = pool_setup({"units": {"synaptic_noise_uS": 0}, "run": {"method": "cvode"}}, "test")
    assert quiet.definition.synaptic_noise_uS == 0.0 and quiet.simulator.method == "cvode"


def test_fields_reach_the_pieces():
    doc = {"name": "ta", "units": {"count": 5, "smallest_p0_N": 0.3, "p0_range": 10.0, "muscle": "fused",
                                   "synaptic_noise_uS": 0.0},
           "drive": {"kind": "synaptic", "times_ms": [0, 100, 200], "values_uS": [0, 0.4, 0.2]},
           "length": {"kind": "random", "seed": 3, "band_hz": 20.0},
           "run": {"duration_ms": 200.0, "record_dt_ms": 0.5, "method": "cvode"},
           "record": {"variables": ["mn.v", "act.A"], "units": [4, 0]}}
    s = pool_setup(doc, "test")
    assert s.definition.name == "ta" and s.definition.muscle_model == "fused"
    assert s.definition.units()[0].muscle["P0"] == pytest.approx(0.3)
    assert s.drive.values == (0.0, 0.4, 0.2) and isinstance(s.length, LengthTrace)
    assert s.length.t_ms[-1] == pytest.approx(200.0) and s.simulator.method == "cvode"
    assert s.recordings == (("mn.v", "act.A"), (4, 0))
    again = pool_setup(doc, "test")
    assert (again.length.xm_mm == s.length.xm_mm).all()   # the random length is seeded


def test_the_size_range_reaches_the_definition():
    s = pool_setup({"units": {"count": 5, "smallest_p0_N": 0.3, "max_size": 0.3, "size_spacing": 20.0}}, "test")
    d = s.definition
    assert (d.max_size, d.size_spacing) == (0.3, 20.0)
    sizes = [u.motoneuron.size for u in d.units()]
    assert sizes[0] == 0.0 and sizes[-1] == pytest.approx(0.3) and sizes == sorted(sizes)
    assert sizes[1] > 0.3 / 4    # spacing 20 crowds fewer units into the low end than uniform spacing
    default = pool_setup({"units": {"count": 5, "smallest_p0_N": 0.3}}, "test").definition
    assert (default.max_size, default.size_spacing) == (1.0, 1.0)


@pytest.mark.parametrize("doc, message", [
    ({"units": {"max_size": 1.5}}, "src: units.max_size must be in \\[0, 1\\] \\(a size index\\), got 1.5"),
    ({"units": {"max_size": "small"}}, "src: units.max_size must be a finite number, got 'small'"),
    ({"units": {"size_spacing": 0.5}}, "src: units.size_spacing must be >= 1 \\(1: sizes uniform in rank\\), got 0.5"),
    ({"drive": {"kind": "synaptic", "times_ms": [0, 600], "values_uS": [0, 1]}},
     "src: drive.times_ms reach 600 ms, beyond the run"),
    ({"run": {"record_dt_ms": 0.01}}, "src: run.record_dt_ms = 0.01 ms is shorter than run.dt_ms"),
    ({"run": {"engine": "gpu"}}, "src: run.engine must be one of neuron, coreneuron"),
    ({"run": {"secondorder": 3}}, "src: run.secondorder must be 0, 1 or 2"),
    ({"run": {"secondorder": 2, "method": "cvode"}}, "src: run.secondorder must be 0, 1 or 2 and 0 under CVODE"),
    ({"units": {"count": True}}, "src: units.count must be an integer >= 1, got True"),
    ({"units": {"types": [1, 0]}}, "src: units.types must be a list of 3 numbers"),
    ({"units": {"neuromodulation": -1}}, "src: units.neuromodulation must be >= 0"),
    ({"units": {"synaptic_noise_uS": -1}}, "src: units.synaptic_noise_uS must be >= 0"),
    ({"units": {"noise_seed": -1}}, "src: units.noise_seed must be an integer >= 0"),
    ({"units": {"synaptic_noise_uS": 0.05}, "run": {"method": "cvode"}},
     "src: run.method = 'cvode': the motoneurons' synaptic noise \\(units.synaptic_noise_uS = 0.05 uS"),
    ({"units": {"synaptic_noise_uS": 0.05}, "drive": {"kind": "current"}},
     "src: units.synaptic_noise_uS = 0.05 uS rides on the common synaptic drive .* not on 'current'"),
    ({"units": {"count": 3, "total_p0_N": 30, "muscle": "fused", "channels": "both"}},
     "src: units.channels must be one of fused, fused_fixed, separate"),
    ({"units": 3}, "src: \\[units\\] must be a section"),
    ({"record": {"variables": ["mn.v", "mn.v"]}}, "src: record.variables repeat"),
    ({"record": {"variables": "mn.v"}}, "src: record.variables must be a non-empty list"),
])
def test_bad_fields_name_source_and_field(doc, message):
    with pytest.raises(InputError, match=message):
        pool_setup(doc, "src")


def test_reconstructed_cells_from_the_motoneuron_section(tmp_path):
    from importlib import resources

    swc = resources.files("neuromuscle.data.morphology").joinpath("small_motoneuron.swc")
    (tmp_path / "cell.swc").write_text(swc.read_text())
    doc = {"motoneuron": {"swc": "cell.swc", "mechanisms": {"soma": {"mn_soma": {"gnaf": 0.5}}}}}
    assert pool_setup({}, "src").cells is None
    assert callable(pool_setup(doc, "src", base_dir=tmp_path).cells)
    with pytest.raises(InputError, match="src: \\[motoneuron\\]: .*cell.swc: no such SWC morphology file"):
        pool_setup(doc, "src", base_dir=tmp_path / "elsewhere")
    bad = {"motoneuron": {"swc": "cell.swc", "mechanisms": {"soma": {"mn_soma": {"gna": 0.5}}}}}
    with pytest.raises(InputError, match="soma: mn_soma has no parameter 'gna'"):
        pool_setup(bad, "src", base_dir=tmp_path)
    with pytest.raises(InputError, match="src: motoneuron.mechanisms must map section groups"):
        pool_setup({"motoneuron": {"swc": "cell.swc", "mechanisms": {"soma": ["mn_soma"]}}}, "src", base_dir=tmp_path)
    with pytest.raises(InputError, match="src: motoneuron.mechanisms is given without motoneuron.swc"):
        pool_setup({"motoneuron": {"mechanisms": {}}}, "src")


def test_a_flag_is_named_instead_of_the_field():
    with pytest.raises(InputError, match="^--peak-us must be > 0, got 0"):
        pool_setup({"drive": {"peak_uS": 0}}, "command line", {"drive.peak_uS": "--peak-us"})


def test_toml_and_json_read_alike_and_merge(tmp_path):
    (tmp_path / "a.toml").write_text('name = "x"\n[units]\ncount = 4\n[run]\nduration_ms = 100.0\n')
    (tmp_path / "a.json").write_text(json.dumps({"name": "x", "units": {"count": 4}, "run": {"duration_ms": 100.0}}))
    assert read_document(tmp_path / "a.toml") == read_document(tmp_path / "a.json")
    merged = merge(read_document(tmp_path / "a.toml"), {"units": {"params": "CT95"}})
    assert merged["units"] == {"count": 4, "params": "CT95"} and merged["run"] == {"duration_ms": 100.0}
    (tmp_path / "a.yaml").write_text("units: 3")
    with pytest.raises(InputError, match="a.yaml: a definition file ends in .toml or .json"):
        read_document(tmp_path / "a.yaml")
    (tmp_path / "b.json").write_text("[1, 2]")
    with pytest.raises(InputError, match="b.json: the definition must be a mapping"):
        read_document(tmp_path / "b.json")
    (tmp_path / "c.json").write_text("{units: 3")
    with pytest.raises(InputError, match="c.json: not valid JSON"):
        read_document(tmp_path / "c.json")
