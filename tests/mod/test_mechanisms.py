"""Compilation cache keyed by the mod files' content (the hoc route, plain `nrnivmodl mod`:
tests/docs/test_readme.py)."""

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
        assert re.match(r"TITLE [^\n]+\n\nCOMMENT\n", text) and re.search(r"\bunits?\b|\(mm", header, re.I), f.name
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


def test_an_installed_package_finds_its_mod_files(tmp_path):
    """Installed (not editable), mod/ ships as the namespace package neuromuscle._mod beside the code, as the wheel
    lays it out (setup.py): the mechanisms are found there and hash as in the source tree."""
    import shutil
    from pathlib import Path

    root = Path(mechanisms.__file__).resolve().parents[2]
    site = tmp_path / "site"
    shutil.copytree(root / "neuromuscle", site / "neuromuscle", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(root / "mod", site / "neuromuscle" / "_mod", ignore=shutil.ignore_patterns("x86_64", "arm64"))
    code = ("import neuromuscle.model.mechanisms as m; "
            "print(m.mod_dir()); print(len(m.mod_files())); print(m.mechanism_hash())")
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
                          env={"PYTHONPATH": str(site), "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr[-2000:]
    where, n, digest = done.stdout.split()
    assert Path(where) == site / "neuromuscle" / "_mod"
    assert int(n) == len(mechanisms.mod_files()) > 20
    assert digest == mechanisms.mechanism_hash()
