"""NEURON's unit checker passes on every mod file (INCLUDEd files are checked with their includer)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from neuromuscle.model import mechanisms


def _modlunit() -> str:
    exe = shutil.which("modlunit", path=str(Path(sys.executable).parent)) or shutil.which("modlunit")
    assert exe, "modlunit not found beside the interpreter (it ships with the neuron wheel)"
    return exe


@pytest.mark.parametrize("mod", [f.name for f in mechanisms.mod_files() if f.suffix == ".mod"])
def test_modlunit_passes(mod, tmp_path):
    for f in mechanisms.mod_files():
        shutil.copy2(f, tmp_path / f.name)
    out = subprocess.run([_modlunit(), mod], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    text = out.stdout + out.stderr
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith(("Checking units", "INCLUDEing"))]
    assert out.returncode == 0 and not lines, text


def test_no_verbatim_in_the_package():
    """No mechanism reaches into NEURON's internals (CoreNEURON compiles only plain NMODL): the integrator test is
    the GLOBAL parameter variable_step (neuromuscle.model.integrator), not a VERBATIM read of NEURON's flag."""
    holders = [f.name for f in mechanisms.mod_files() if "VERBATIM" in f.read_text().replace("ENDVERBATIM", "")]
    assert holders == []


def test_benchmark_mechanism_is_not_required():
    assert "KimPublished" not in mechanisms.required_mechanisms()
    assert {"KimCa", "KimAct", "KimForce", "MuscleLength", "HatzeExc", "HatzeTrend", "HatzeMTC"} <= set(
        mechanisms.required_mechanisms())
