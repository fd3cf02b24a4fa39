"""Compile and load the NMODL mechanisms of ``mod/`` into NEURON.

The mechanisms are compiled by ``nrnivmodl`` on first use into a cache directory keyed by the SHA-256 of the
mod files' content (``$NEUROMUSCLE_CACHE`` or ``~/.cache/neuromuscle``), so an installed package needs no manual
step and an edited mod file is recompiled.  A hoc user can equally run ``nrnivmodl mod`` and
``nrn_load_dll("x86_64/libnrnmech.so")``; if the mechanisms are already present in NEURON (loaded that way, or
from an ``x86_64/`` folder NEURON found in the working directory) they are used as they are.

Coupling interface between the mechanisms (all point processes; see each mod file's header):

==============  ==========================  ===============================================
mechanism       reads (POINTER)             exposes (RANGE)
==============  ==========================  ===============================================
MuscleLength    -                           xm (mm), vm (mm/s)
KimCa (M1)      atil <- KimAct.atil,        CaSR, CaSRCS, CaSP, CaSPB, CaSPT (M), R, U (M/ms)
                xm <- MuscleLength.xm
KimAct (M2)     caspt <- KimCa.CaSPT,       atil (Atil), A (activation)
                xm, vm <- MuscleLength
KimForce (M3)   act <- <excitation>.A,      xce (mm), F, Fc (N), vce (mm/s), nasym
                xm <- MuscleLength.xm
HatzeExc        -                           b, vb, g, vg (seed 000 eqs 6-7), A = q (eq 9)
HatzeTrend      -                           g (eq 10 trend, nu played as rate/100 Hz), A = q
HatzeMTC        act <- <excitation>.A       phi_ce (rad), M (N m), omega_ce (rad/s); input
                                            phi_mtc_offset (rad, RANGE: set or Vector.play)
KimPublished    xm <- MuscleLength.xm       A (Modules 1-2 the authors' way; benchmark only)
==============  ==========================  ===============================================

Swapping excitation models: any mechanism that takes spikes by NET_RECEIVE and exposes RANGE A in [0, 1] can be
set in front of Module 3 with ``setpointer force.act, exc.A`` (``MuscleUnit(excitation="hatze")`` does this).

Spikes arrive at KimCa (or another excitation mechanism) through NET_RECEIVE, so any NetCon source works.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import platform
import shutil
import subprocess
import sys
import tempfile
from importlib import resources
from pathlib import Path

from .errors import MechanismBuildError

#: Mechanisms the package needs; all come from ``mod/``.
MECHANISMS = ("KimCa", "KimAct", "KimForce", "MuscleLength", "HatzeExc", "HatzeTrend", "HatzeMTC", "KimPublished")


def mod_dir() -> Path:
    """Directory holding the package's ``.mod`` files (``mod/`` in a source tree)."""
    src = Path(__file__).resolve().parent.parent / "mod"
    if src.is_dir() and any(src.glob("*.mod")):
        return src
    return Path(str(resources.files("neuromuscle._mod")))


def mod_files() -> list[Path]:
    """The ``.mod`` files, sorted by name (the order nrnivmodl registers them in)."""
    return sorted(mod_dir().glob("*.mod"))


def mechanism_hash() -> str:
    """SHA-256 over the names and contents of all mod files: identifies the compiled mechanisms."""
    h = hashlib.sha256()
    for f in mod_files():
        h.update(f.name.encode())
        h.update(b"\0")
        h.update(f.read_bytes())
        h.update(b"\0")
    return h.hexdigest()


def cache_root() -> Path:
    """Root of the compiled-mechanism cache (``$NEUROMUSCLE_CACHE`` or ``~/.cache/neuromuscle``)."""
    env = os.environ.get("NEUROMUSCLE_CACHE")
    if env:
        return Path(env)
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "neuromuscle"


def _neuron_version() -> str:
    import neuron

    return str(getattr(neuron, "__version__", "unknown"))


def _nrnivmodl() -> str:
    exe = shutil.which("nrnivmodl", path=os.pathsep.join([str(Path(sys.executable).parent),
                                                          os.environ.get("PATH", "")]))
    if exe is None:
        raise MechanismBuildError("nrnivmodl not found: install NEURON (pip install neuron)")
    return exe


def _library_in(build: Path) -> Path | None:
    for lib in build.glob("*/libnrnmech.so"):
        return lib
    for lib in build.glob("*/.libs/libnrnmech.so"):
        return lib
    return None


def compiled_library() -> Path:
    """Path of ``libnrnmech.so`` for the current mod files, compiling it into the cache if needed."""
    key = f"{mechanism_hash()[:16]}-nrn{_neuron_version()}-{platform.machine()}"
    target = cache_root() / key
    lib = _library_in(target)
    if lib is not None:
        return lib
    cache_root().mkdir(parents=True, exist_ok=True)
    with open(cache_root() / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one compiler at a time (parallel tests, MPI ranks)
        lib = _library_in(target)
        if lib is not None:
            return lib
        tmp = Path(tempfile.mkdtemp(prefix=f"{key}.", dir=cache_root()))
        for f in mod_files():
            shutil.copy2(f, tmp / f.name)
        proc = subprocess.run([_nrnivmodl(), "."], cwd=tmp, capture_output=True, text=True)
        if proc.returncode != 0 or _library_in(tmp) is None:
            raise MechanismBuildError(
                f"nrnivmodl failed in {tmp} (exit {proc.returncode}):\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}")
        os.replace(tmp, target)
    lib = _library_in(target)
    assert lib is not None
    return lib


def load_mechanisms() -> None:
    """Make the package's mechanisms available in this process's NEURON (idempotent)."""
    from neuron import h

    present = [hasattr(h, name) for name in MECHANISMS]
    if all(present):
        return
    if any(present):
        missing = [n for n, p in zip(MECHANISMS, present) if not p]
        raise MechanismBuildError(
            f"NEURON already holds some neuromuscle mechanisms but not {missing}: an old compiled copy "
            "(e.g. an x86_64/ folder in the working directory) is loaded; remove it or recompile mod/")
    lib = compiled_library()
    if not h.nrn_load_dll(str(lib)):
        raise MechanismBuildError(f"NEURON could not load {lib}")
