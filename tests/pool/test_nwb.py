"""A pool's result as NWB: nwbinspector finds no critical issue and no best-practice violation; the file reads back
to the same spikes, forces, unit table, recordings and provenance; an existing file is kept; a file that is not a
pool is refused."""

import json

import numpy as np
import pytest

from neuromuscle.errors import InputError
from neuromuscle.pool import Pool, PoolDefinition
from neuromuscle.pool.drives import Drive
from neuromuscle.pool.nwb import read_pool_nwb, write_pool_nwb


@pytest.fixture(scope="module")
def result(ct09):
    d = PoolDefinition(3, ct09, smallest_p0_N=0.2, p0_range=20.0, type_fractions=(0.4, 0.3, 0.3), name="small")
    with Pool(d) as pool:
        Drive.recruitment_ramp(0.6, 300.0).apply(pool)
        pool.record(["mn.v", "act.A"], units=[0, 2])
        return pool.run(300.0, record_dt_ms=0.5)


@pytest.fixture(scope="module")
def nwb_file(result, tmp_path_factory):
    return result.save_nwb(tmp_path_factory.mktemp("nwb") / "pool.nwb")


def test_nwbinspector_finds_no_critical_issue_or_violation(nwb_file):
    from nwbinspector import Importance, inspect_nwbfile

    messages = list(inspect_nwbfile(nwbfile_path=str(nwb_file)))
    serious = [m for m in messages if m.importance in (Importance.CRITICAL, Importance.BEST_PRACTICE_VIOLATION,
                                                       Importance.ERROR, Importance.PYNWB_VALIDATION)]
    assert not serious, [(m.check_function_name, m.message) for m in serious]


def test_a_cvode_pool_passes_too(ct09, tmp_path):
    """CVODE interpolates spike times: the Units table's resolution is then the spacing of doubles, still set."""
    from nwbinspector import Importance, inspect_nwbfile

    from neuromuscle.sim import Simulator

    with Pool(PoolDefinition(2, ct09, smallest_p0_N=0.2, p0_range=20.0)) as pool:
        Drive.rise("synaptic", 0.6, 150.0).apply(pool)
        r = pool.run(150.0, Simulator(method="cvode", v_init_mV=-70.0))
    path = r.save_nwb(tmp_path / "cvode.nwb")
    serious = [m for m in inspect_nwbfile(nwbfile_path=str(path)) if m.importance in (
        Importance.CRITICAL, Importance.BEST_PRACTICE_VIOLATION, Importance.ERROR, Importance.PYNWB_VALIDATION)]
    assert not serious, [(m.check_function_name, m.message) for m in serious]
    back = read_pool_nwb(path)
    assert sum(s.size for s in r.spikes_ms) > 2
    assert all(np.allclose(a, b, rtol=0, atol=1e-9) for a, b in zip(r.spikes_ms, back.spikes_ms))


def test_the_file_reads_back_to_the_result(result, nwb_file):
    back = read_pool_nwb(nwb_file)
    assert back.n_units == 3 and [u["type"] for u in back.units] == [u["type"] for u in result.units]
    assert sum(s.size for s in result.spikes_ms) > 5
    for a, b in zip(result.spikes_ms, back.spikes_ms):
        assert np.allclose(a, b, rtol=0, atol=1e-9)                     # ms -> s -> ms
    assert np.array_equal(back.t_ms, result.t_ms)
    assert np.array_equal(back.unit_force_N, result.unit_force_N)
    assert np.array_equal(back.pool_force_N, result.pool_force_N)
    assert back.units == result.units
    assert back.provenance["mechanism_sha256"] == result.provenance["mechanism_sha256"]
    assert back.provenance["pool"] == "small" and back.drive == result.drive
    for name, rec in result.recordings.items():
        got = back.recordings[name]
        assert got.units == rec.units == [0, 2] and got.unit == rec.unit and np.array_equal(got.values, rec.values)


def test_nwb_layout_for_other_readers(result, nwb_file):
    """What a reader of NWB (not of this package) finds: spike times in s, rates in Hz, a simulated subject."""
    from pynwb import NWBHDF5IO

    with NWBHDF5IO(str(nwb_file), "r") as io:
        nwb = io.read()
        assert np.allclose(nwb.units["spike_times"][0], result.spikes_ms[0] / 1000.0)
        assert list(nwb.units["P0_N"][:]) == [u["P0_N"] for u in result.units]
        assert nwb.units.resolution == pytest.approx(0.025e-3)
        assert nwb.acquisition["pool_force"].rate == pytest.approx(2000.0)
        assert nwb.acquisition["pool_force"].unit == "N"
        assert nwb.acquisition["mn.v"].data.shape == (result.t_ms.size, 2)
        assert nwb.subject.species == "Felis catus" and "no animal" in nwb.subject.description
        assert json.loads(nwb.notes)["provenance"]["n_units"] == 3


def test_an_existing_file_is_kept_and_other_files_are_refused(result, nwb_file, tmp_path):
    before = nwb_file.read_bytes()
    with pytest.raises(InputError, match="refusing to overwrite"):
        write_pool_nwb(result, nwb_file)
    assert nwb_file.read_bytes() == before
    other = tmp_path / "other.nwb"
    result.save(tmp_path / "pool.h5")
    with pytest.raises(InputError, match="no such file"):
        read_pool_nwb(other)
    from pynwb import NWBHDF5IO, NWBFile
    import datetime

    with NWBHDF5IO(str(other), "w") as io:
        io.write(NWBFile(session_description="x", identifier="x",
                         session_start_time=datetime.datetime.now(datetime.timezone.utc)))
    with pytest.raises(InputError, match="not a pool written by neuromuscle"):
        read_pool_nwb(other)
