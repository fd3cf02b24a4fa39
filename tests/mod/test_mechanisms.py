"""Compilation cache keyed by the mod files' content; the hoc-style nrnivmodl route."""

import re
import subprocess
import sys

from neuromuscle.model import mechanisms


def test_hash_changes_with_mod_content(tmp_path, monkeypatch):
    for f in mechanisms.mod_files():
        (tmp_path / f.name).write_bytes(f.read_bytes())
    monkeypatch.setattr(mechanisms, "mod_dir", lambda: tmp_path)
    h1 = mechanisms.mechanism_hash()
    (tmp_path / "kim_m2_activation.mod").write_text((tmp_path / "kim_m2_activation.mod").read_text() + "\n:x\n")
    assert mechanisms.mechanism_hash() != h1


def test_every_mod_file_has_a_header_with_units_and_declares_threadsafe_first():
    """THREADSAFE must precede POINTER in the NEURON block, or nocmodl silently makes the mechanism
    thread-unsafe ("Use of POINTER is not thread safe")."""
    for f in (f for f in mechanisms.mod_files() if f.suffix == ".mod"):
        text = f.read_text()
        header = text.split("ENDCOMMENT")[0]
        assert text.startswith("COMMENT") and re.search(r"\bunits?\b|\(mm", header, re.I), f.name
        block = re.search(r"NEURON \{(.*?)\}", text, re.S).group(1)
        assert "THREADSAFE" in block, f.name
        if "POINTER" in block:
            assert block.index("THREADSAFE") < block.index("POINTER"), f.name


def test_compiled_library_is_cached_and_loads_in_a_fresh_process(tmp_path):
    lib = mechanisms.compiled_library()
    assert lib.is_file() and lib == mechanisms.compiled_library()
    code = ("from neuromuscle import load_mechanisms; load_mechanisms(); from neuron import h; "
            "print(all(hasattr(h, n) for n in ('KimCa','KimAct','KimForce','MuscleLength','KimPublished')))")
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert out.stdout.strip().endswith("True"), out.stderr


def test_nrnivmodl_on_mod_folder_works_for_hoc_users(tmp_path, ct09):
    """`nrnivmodl mod` then NEURON in that folder: the hoc route of the README."""
    mod = tmp_path / "mod"
    mod.mkdir()
    for f in mechanisms.mod_files():
        (mod / f.name).write_bytes(f.read_bytes())
    subprocess.run([mechanisms._nrnivmodl(), "mod"], cwd=tmp_path, check=True, capture_output=True)
    hoc = ("create muscle\nobjref len, ca, act, frc\n"
           "muscle len = new MuscleLength(0.5)\nmuscle ca = new KimCa(0.5)\n"
           "muscle act = new KimAct(0.5)\nmuscle frc = new KimForce(0.5)\n"
           "setpointer ca.atil, act.atil\nsetpointer ca.xm, len.xm\nsetpointer act.caspt, ca.CaSPT\n"
           "setpointer act.T0, ca.T0\nsetpointer act.phi1, ca.phi1\nsetpointer act.phi2, ca.phi2\n"
           "setpointer act.xopt, ca.xopt\n"
           "setpointer act.xm, len.xm\nsetpointer act.vm, len.vm\nsetpointer frc.act, act.A\n"
           "setpointer frc.xm, len.xm\nobjref nc, nil\nnc = new NetCon(nil, ca)\nnc.weight = 1\n"
           "objref fih\nfih = new FInitializeHandler(\"nc.event(100)\")\n"
           "len.xm = -8\ndt = 0.025\nload_file(\"stdrun.hoc\")\ntstop = 300\nfinitialize()\n"
           "objref fv\nfv = new Vector()\nfv.record(&frc.F, 0.1)\nfinitialize()\ncontinuerun(300)\n"
           "printf(\"PEAK %g\\n\", fv.max())\n")
    (tmp_path / "run.hoc").write_text(hoc)
    code = "from neuron import h; h.load_file('run.hoc')"
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    peak = [float(l.split()[1]) for l in out.stdout.splitlines() if l.startswith("PEAK")]
    from neuromuscle import simulate

    expected = simulate(ct09, [100.0], -8.0, 300.0).force_N.max()
    assert peak and abs(peak[0] / expected - 1) < 0.002, out.stdout + out.stderr


def test_provenance_names_the_loaded_library_not_the_files_edited_since(tmp_path, monkeypatch):
    """A loaded library cannot change within a process: provenance keeps its hash when the mod files are edited
    afterwards (and reads no file to give it)."""
    from neuromuscle import simulate
    from neuromuscle.parameters import load_parameters

    r = simulate(load_parameters("CT09"), [10.0], -8.0, 30.0)
    loaded = r.provenance["mechanism_sha256"]
    assert loaded == mechanisms.loaded_mechanism_hash()
    for f in mechanisms.mod_files():
        (tmp_path / f.name).write_bytes(f.read_bytes())
    (tmp_path / "kim_m2_activation.mod").write_text((tmp_path / "kim_m2_activation.mod").read_text() + "\n:x\n")
    monkeypatch.setattr(mechanisms, "mod_dir", lambda: tmp_path)
    assert mechanisms.mechanism_hash() != loaded
    assert simulate(load_parameters("CT09"), [10.0], -8.0, 30.0).provenance["mechanism_sha256"] == loaded
