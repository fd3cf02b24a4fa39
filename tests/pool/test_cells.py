"""Motoneuron cells behind one interface: the built-in reduced cell through its factory gives the pool it always
gave; a reconstructed cell read from the shipped SWC morphology by Import3d, with the channels named, has its
sections, segments and mechanisms, fires under the common synaptic drive and drives its muscle unit in a pool whose
voltages are recorded; a cell you build (a hoc template, a Python class) is wrapped the same way; bad morphologies,
mechanisms and cells are refused naming the file, group, mechanism, parameter or cell."""

from importlib import resources

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.cells import (ReconstructedMotoneuron, built_cells, mechanism_parameters,
                                    reconstructed_cells, reduced_cells, wrap_cell)
from neuromuscle.pool.drives import Drive

SWC = resources.files("neuromuscle.data.morphology").joinpath("small_motoneuron.swc")

#: The reduced S cell's channels and leak, named for the reconstructed one.
MECHANISMS = {"all": {"pas": {"g": 1.0 / 8000.0, "e": -70.0}},
              "soma": {"pas": {"g": 1.0 / 600.0},
                       "mn_soma": {"gnaf": 0.6, "gkdr": 0.15, "gcan": 0.01, "gkca": 0.012, "ena": 50.0, "ek": -80.0,
                                   "taur": 45.0, "kd": 0.002}},
              "dend": {"mn_pic": {"gbar": 3.6e-5, "vhalf": -57.0, "slope": 4.0}}}


def test_the_reduced_factory_is_the_default_pool(ct09):
    d = PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)
    runs = []
    for cells in (None, reduced_cells("fused")):
        with Pool(d, cells=cells) as pool:
            Drive.rise("synaptic", 0.6, 200.0).apply(pool)
            runs.append(pool.run(200.0))
    assert sum(s.size for s in runs[0].spikes_ms) > 2
    assert np.array_equal(runs[0].unit_force_N, runs[1].unit_force_N)


def test_a_reconstructed_cell_has_the_morphology_and_the_named_channels():
    cell = ReconstructedMotoneuron(SWC, MECHANISMS, axon_delay_ms=7.5, name="rc")
    try:
        assert len(cell.sections) == 19 and len(cell.dends) == 18 and cell.soma.name() == "rc.soma[0]"
        assert cell.soma.L == pytest.approx(50.0) and cell.axon_delay_ms == 7.5
        assert all(sec.nseg % 2 == 1 and sec.L / sec.nseg <= 100.0 for sec in cell.sections)
        assert 1.5e5 < cell.membrane_area_um2() < 2.5e5
        assert cell.soma(0.5).mn_soma.gnaf == 0.6 and cell.soma(0.5).pas.g == pytest.approx(1 / 600)
        assert cell.dends[0](0.5).pas.g == pytest.approx(1 / 8000) and cell.dends[0](0.5).mn_pic.gbar == 3.6e-5
        assert not cell.dends[0].has_membrane("mn_soma")
        assert set(cell.recordables()) == {"v", "v_dend"}
    finally:
        cell.destroy()


def test_a_pool_of_reconstructed_cells_fires_and_pulls(ct09):
    d = PoolDefinition(3, ct09, smallest_p0_N=0.2, p0_range=20.0)
    with Pool(d, cells=reconstructed_cells(SWC, MECHANISMS)) as pool:
        Drive.recruitment_ramp(0.6, 400.0).apply(pool)
        pool.record(["mn.v", "mn.v_dend", "act.A"], units=[0])
        r = pool.run(400.0, record_dt_ms=0.1)
    spikes = r.spikes_ms[0]
    assert spikes.size > 3 and all(s.size == spikes.size for s in r.spikes_ms)  # one morphology: the same cell
    rates = 1000.0 / np.diff(spikes)
    assert 5.0 < rates.min() and rates.max() < 60.0
    v = r.recordings["mn.v"].values[0]
    assert v[0] == pytest.approx(-70.0) and v.max() > 0.0
    assert r.recordings["mn.v_dend"].values[0].max() < v.max()      # the spike is smaller in the dendrite
    # the largest unit pulls hardest, each unit only after its first spike reaches it down its axon
    assert r.unit_force_N[2].max() > r.unit_force_N[0].max() > 0.0
    arrival = spikes[0] + r.units[0]["axon_delay_ms"]
    assert r.recordings["act.A"].values[0][r.t_ms < arrival - 0.5].max() < 0.05


def test_bad_morphologies_and_mechanisms_are_refused(tmp_path):
    with pytest.raises(InputError, match="absent.swc: no such SWC morphology file"):
        reconstructed_cells(tmp_path / "absent.swc", MECHANISMS)
    with pytest.raises(InputError, match="mechanisms for 'somata': section groups are all, soma, dend, apic, axon"):
        reconstructed_cells(SWC, {"somata": {"pas": {}}})
    with pytest.raises(InputError, match="soma: no density mechanism 'mn_sodium' is compiled"):
        reconstructed_cells(SWC, {"soma": {"mn_sodium": {}}})
    with pytest.raises(InputError, match="dend: mn_pic has no parameter 'gmax'; parameters: gbar"):
        reconstructed_cells(SWC, {"dend": {"mn_pic": {"gmax": 1e-4}}})
    with pytest.raises(InputError, match="all.pas.g"):
        reconstructed_cells(SWC, {"all": {"pas": {"g": float("nan")}}})
    no_soma = tmp_path / "no_soma.swc"
    no_soma.write_text("1 3 0 0 0 5 -1\n2 3 100 0 0 4 1\n")
    with pytest.raises(InputError, match="no_soma.swc: the morphology has no soma"):
        ReconstructedMotoneuron(no_soma, {}, axon_delay_ms=5.0)
    assert mechanism_parameters("pas") == ["g", "e"] and mechanism_parameters("KimCa") is None


HOC_TEMPLATE = """
begintemplate TwoDendriteMN
public soma, dend, all
create soma, dend[2]
objref all
proc init() {
    all = new SectionList()
    soma { L = 50 diam = 50 insert pas g_pas = 1/600 e_pas = -70 insert mn_soma all.append() }
    for i = 0, 1 {
        connect dend[i](0), soma(1)
        dend[i] { L = 1500 diam = 8 nseg = 5 insert pas g_pas = 1/8000 e_pas = -70
                  insert mn_pic gbar_mn_pic = $1 all.append() }
    }
}
endtemplate TwoDendriteMN
"""


class PythonMN:
    """A user's cell as a Python class: a soma with the spike channels and one passive dendrite."""

    def __init__(self):
        from neuron import h

        self.soma = h.Section(name="soma", cell=self)
        self.dend = h.Section(name="dend", cell=self)
        self.dend.connect(self.soma(1.0))
        self.soma.L = self.soma.diam = 50.0
        self.dend.L, self.dend.diam, self.dend.nseg = 1500.0, 8.0, 5
        for sec, g in ((self.soma, 1 / 600), (self.dend, 1 / 8000)):
            sec.insert("pas")
            for seg in sec:
                seg.pas.g, seg.pas.e = g, -70.0
        self.soma.insert("mn_soma")


def test_cells_you_build_from_a_hoc_template_or_a_python_class(ct09, tmp_path):
    from neuron import h

    hoc = tmp_path / "two_dendrite_mn.hoc"
    hoc.write_text(HOC_TEMPLATE)
    assert h.load_file(str(hoc)) == 1
    d = PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)
    results = {}
    for label, build in (("hoc", lambda spec, name: h.TwoDendriteMN(3.6e-5)),
                         ("python", lambda spec, name: PythonMN())):
        with Pool(d, cells=built_cells(build)) as pool:
            assert len(pool.cells[0].sections) == (3 if label == "hoc" else 2)
            Drive.rise("synaptic", 0.6, 300.0).apply(pool)
            pool.record(["mn.v", "mn.v_dend"], units=[1])
            results[label] = pool.run(300.0, record_dt_ms=0.1)
    for r in results.values():
        assert all(s.size > 2 for s in r.spikes_ms) and r.pool_force_N.max() > 0.0
        assert r.recordings["mn.v"].values.max() > 0.0
        # each unit's spikes reach its muscle after its own axon delay (the unit's motoneuron parameters)
        assert r.units[0]["axon_delay_ms"] != r.units[1]["axon_delay_ms"]
    # two different cells: a hoc template with two dendrites and a PIC, a Python class with one passive dendrite
    assert not np.array_equal(results["hoc"].spikes_ms[0], results["python"].spikes_ms[0])


def test_a_cell_without_the_named_soma_is_refused():
    class NoSoma:
        pass

    with pytest.raises(InputError, match="mn0: the cell .* has no section 'soma'"):
        wrap_cell(NoSoma(), axon_delay_ms=5.0, name="mn0")
    with pytest.raises(InputError, match="mn0: axon_delay_ms"):
        wrap_cell(PythonMN(), axon_delay_ms=0.0, name="mn0")


def test_excitability_measures_any_cell_of_the_interface():
    """The current-clamp measurements use only the interface: a reconstructed cell has a rheobase, fires faster
    under more synaptic conductance, and keeps no synaptic mechanism after the measurement."""
    from neuromuscle.pool.excitability import rheobase_nA, synaptic_rates_hz

    cell = ReconstructedMotoneuron(SWC, MECHANISMS, axon_delay_ms=7.5, name="probe", v_rest_mV=-70.0)
    try:
        rheobase = rheobase_nA(cell)
        assert 0.5 < rheobase < 100.0
        rates = synaptic_rates_hz(cell, [0.05, 0.3, 0.6], duration_ms=800.0, skip_ms=400.0)
        assert rates[0] < rates[1] < rates[2] and rates[2] > 5.0
        assert not any(sec.has_membrane("mn_syn") for sec in cell.sections)
    finally:
        cell.destroy()


def test_the_pic_gate_step_reaches_reconstructed_cells_and_is_refused_without_a_pic(ct09):
    """PoolDefinition(pic_substeps=k) acts on every mn_pic segment of the user's cells; cells with no mn_pic are
    refused by name rather than the setting being dropped."""
    d = PoolDefinition(2, ct09, pic_substeps=6)
    with Pool(d, cells=reconstructed_cells(SWC, MECHANISMS)) as pool:
        gates = {seg.mn_pic.substeps for c in pool.cells.values() for sec in c.sections
                 if sec.has_membrane("mn_pic") for seg in sec}
        assert gates == {6.0}
    no_pic = {k: v for k, v in MECHANISMS.items() if k != "dend"}
    with pytest.raises(InputError, match="pic_substeps = 6 needs mn_pic"):
        Pool(d, cells=reconstructed_cells(SWC, no_pic))
