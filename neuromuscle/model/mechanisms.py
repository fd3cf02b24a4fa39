"""Compile and load the NMODL mechanisms of ``mod/`` into NEURON.

The mechanisms are compiled by ``nrnivmodl`` on first use into a cache directory keyed by the SHA-256 of the
mod files' content (``$NEUROMUSCLE_CACHE`` or ``~/.cache/neuromuscle``), so an installed package needs no manual
step and an edited mod file is recompiled.  A hoc user can equally run ``nrnivmodl mod`` and
``nrn_load_dll("x86_64/libnrnmech.so")``; if the mechanisms are already present in NEURON (loaded that way, or
from an ``x86_64/`` folder NEURON found in the working directory) they are used as they are.

What each mechanism reads and exposes is declared by its component (``neuromuscle.model.kim``, ``.hatze``,
``.length``, ``.extensions``); the required set below is derived from them.  The benchmark's KimPublished is
compiled too (so ``nrnivmodl mod`` gives hoc users everything) but is not required.

Each mod file is named after the mechanism it defines (``ExtFatigue.mod`` holds ExtFatigue), except the Kim modules,
``kim_m1_calcium.mod`` (KimCa), ``kim_m2_activation.mod`` (KimAct), ``kim_m3_force.mod`` (KimForce) and
``kim_unit.mod`` (KimUnit, the three fused): NEURON advances mechanisms in the order nrnivmodl registers them, which
is the byte order of the file names. Module 1 must run before Module 2, Module 2 before Module 3 (KimAct < KimCa in
name order), and the lower-case names place the muscle after everything that drives it or reads it (extensions,
PortCombine, MuscleLength, afferents), in the same order for the fused unit as for the three. Equations used by more
than one mechanism live once, in ``.inc`` files the mod files INCLUDE.
"""

from __future__ import annotations

import fcntl
import hashlib
import importlib.util
import os
import platform
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable

from ..errors import MechanismBuildError
from . import integrator

#: Extra compiler flags for the mechanisms.  nrnivmodl compiles with -O2; -O3 runs a motoneuron pool 8 % faster
#: (200 units, 2 s: 6.76 -> 6.23 s) and every trace stays bit-identical (tests/model/test_ports_off_is_baseline.py).
#: -fno-semantic-interposition lets the compiler inline the mechanisms' own FUNCTIONs and PROCEDUREs (nocmodl
#: gives them external linkage, which in a shared library otherwise forbids it): the equations the .inc files
#: share cost no call.  nrnivmodl has no option for compiler flags: they go in through ``-incflags``, which its
#: makefile places after its own -O2 on the compile line (the last -O wins).  No -march: fused multiply-adds
#: would change the last bits of every trace.
COMPILE_FLAGS = "-O3 -fno-semantic-interposition"


def _components() -> tuple[Any, ...]:
    """Every registered component class (extensions included)."""
    from . import combine, extensions, hatze, kim, kim_unit, length

    return (*kim.COMPONENTS, *kim_unit.COMPONENTS, *hatze.COMPONENTS, length.MuscleLength, combine.PortCombine,
            *extensions.mechanism_extensions())


def required_mechanisms() -> tuple[str, ...]:
    """POINT_PROCESS names the package needs: one per registered component (extensions included)."""
    return tuple(c.suffix for c in _components())


#: Density mechanisms that only NEURON's fixed step advances: the fused motoneuron channels' fixed-step forms.
FIXED_STEP_ONLY_CHANNELS = ("mn_soma_fixed", "mn_pic_fixed")


def fixed_step_only_mechanisms() -> tuple[str, ...]:
    """POINT_PROCESS names of the components that only NEURON's fixed step advances (KimUnitFixed); the density
    mechanisms are FIXED_STEP_ONLY_CHANNELS."""
    return tuple(c.suffix for c in _components() if c.fixed_step_only)


def mod_dir() -> Path:
    """Directory holding the package's ``.mod`` files (``mod/`` in a source tree)."""
    src = Path(__file__).resolve().parents[2] / "mod"
    if src.is_dir() and any(src.glob("*.mod")):
        return src
    # an installed package: mod/ ships as the namespace package neuromuscle._mod (no __init__.py), whose
    # resources.files() is a MultiplexedPath, not a path; its search location is the folder
    spec = importlib.util.find_spec("neuromuscle._mod")
    for where in (spec.submodule_search_locations or []) if spec is not None else []:
        if any(Path(where).glob("*.mod")):
            return Path(where)
    raise MechanismBuildError("the package's .mod files are missing: neither mod/ beside the source tree nor the "
                              "installed neuromuscle._mod holds any (reinstall the package)")


def mod_files() -> list[Path]:
    """The ``.mod`` files and the ``.inc`` files they INCLUDE, sorted by name (nrnivmodl registers the mod
    files in this order)."""
    return sorted([*mod_dir().glob("*.mod"), *mod_dir().glob("*.inc")])


_HASHES: dict[tuple[tuple[str, int, int], ...], str] = {}
#: The mechanism hash of the library this process loaded (None until :func:`load_mechanisms` loads one).
_LOADED: str | None = None
#: True once this process's NEURON holds every mechanism and the integrator handler (they cannot be unloaded).
_READY = False


def mechanism_hash() -> str:
    """SHA-256 over the names and contents of all mod and include files: identifies the compiled mechanisms.
    The files are read again only when one's name, size or modification time changed (every simulation's
    provenance asks)."""
    files = mod_files()
    key = tuple((f.name, st.st_size, st.st_mtime_ns) for f in files for st in (f.stat(),))
    if key not in _HASHES:
        h = hashlib.sha256()
        for f in files:
            h.update(f.name.encode())
            h.update(b"\0")
            h.update(f.read_bytes())
            h.update(b"\0")
        _HASHES[key] = h.hexdigest()
    return _HASHES[key]


def cache_root() -> Path:
    """Root of the compiled-mechanism cache: ``$NEUROMUSCLE_CACHE``, else ``$XDG_CACHE_HOME/neuromuscle``, else
    ``~/.cache/neuromuscle``."""
    env = os.environ.get("NEUROMUSCLE_CACHE")
    if env:
        return Path(env)
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "neuromuscle"


def _neuron_version() -> str:
    import neuron

    return str(getattr(neuron, "__version__", "unknown"))


def _tool(name: str) -> str:
    """Path of one of NEURON's build tools (nrnivmodl, nrnivmodl-core): beside this Python, else on PATH."""
    exe = shutil.which(name, path=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]))
    if exe is None:
        raise MechanismBuildError(f"{name} not found: install NEURON (pip install neuron)")
    return exe


def _library_in(build: Path, name: str = "libnrnmech.so") -> Path | None:
    for lib in build.glob(f"*/{name}"):
        return lib
    for lib in build.glob(f"*/.libs/{name}"):
        return lib
    return None


def _run_with_progress(cmd: list[str], cwd: Path, every_s: float = 10.0) -> subprocess.CompletedProcess:
    """Run ``cmd`` capturing its output, printing the elapsed time on stderr every ``every_s`` seconds.  The C
    locale makes nrnivmodl list the mod files in byte order (:func:`mod_files`' order) whatever the user's
    locale: NEURON advances the mechanisms in the order they are registered."""
    import time

    start = time.monotonic()
    env = {**os.environ, "LC_ALL": "C"}
    with subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env) as p:
        while True:
            try:
                out, err = p.communicate(timeout=every_s)
                break
            except subprocess.TimeoutExpired:
                print(f"neuromuscle: ... still compiling ({time.monotonic() - start:.0f} s)", file=sys.stderr,
                      flush=True)
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)


def loaded_mechanism_hash() -> str:
    """The hash of the mechanisms this process runs: of the mod files the loaded library was compiled from (a
    library loaded once cannot change within the process, even if the files are edited afterwards), else of the
    mod files now (:func:`mechanism_hash`; e.g. mechanisms loaded by the user from their own build).  Every
    simulation's provenance asks, so it does not read the file system once a library is loaded (globbing and
    stat-ing the mod files took ~1.8 ms, 9 % of a 0.5 s twitch simulated at 0.1 ms)."""
    return _LOADED if _LOADED is not None else mechanism_hash()


def compiled_library() -> Path:
    """Path of ``libnrnmech.so`` for the current mod files, compiling it into the cache if needed."""
    return _compiled_library(mechanism_hash())


def coreneuron_library() -> Path:
    """Path of ``libcorenrnmech.so``, CoreNEURON's build of the current mod files (``nrnivmodl-core``, NMODL's
    code generator), compiling it into the cache if needed.  It sits beside NEURON's build under its own key:
    NEURON keeps running its own library, and CoreNEURON loads this one when a run hands it the model."""
    return _build(mechanism_hash(), "core", "libcorenrnmech.so", _build_coreneuron)


def _compiled_library(digest: str) -> Path:
    """:func:`compiled_library` for the mod files of hash ``digest``."""
    return _build(digest, "", "libnrnmech.so", _build_neuron)


def _build_neuron(folder: Path) -> str | None:
    """nrnivmodl in ``folder`` (the mod files copied there); None on success, else the reason."""
    proc = _run_with_progress([_tool("nrnivmodl"), "-incflags", COMPILE_FLAGS, "."], folder)
    if proc.returncode == 0 and _library_in(folder) is not None:
        return None
    return f"exit {proc.returncode}:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"


#: nrnivmodl-core's own report of a complete build.
_CORE_BUILT = "MOD files built successfully for CoreNEURON"


def _build_coreneuron(folder: Path) -> str | None:
    """nrnivmodl-core in ``folder``; None on success, else the reason.  Success is the library and
    nrnivmodl-core's own success message: the pip wheel's wrapper then looks for NEURON's ``special`` (which only
    nrnivmodl makes) and exits with an error after the CoreNEURON build is complete."""
    proc = _run_with_progress([_tool("nrnivmodl-core"), "-i", COMPILE_FLAGS, "."], folder)
    if _CORE_BUILT in proc.stdout + proc.stderr and _library_in(folder, "libcorenrnmech.so") is not None:
        return None
    return f"exit {proc.returncode}:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"


def _build(digest: str, variant: str, library: str, build: Callable[[Path], str | None]) -> Path:
    """The cached ``library`` built from the mod files of hash ``digest`` by ``build`` (which compiles in the
    folder it is given), under the key of the hash, NEURON's version, the machine, the flags and ``variant``;
    one compiler at a time (a file lock: parallel tests, MPI ranks)."""
    flags = hashlib.sha256(COMPILE_FLAGS.encode()).hexdigest()[:6]
    key = f"{digest[:16]}-nrn{_neuron_version()}-{platform.machine()}-f{flags}" + (f"-{variant}" if variant else "")
    target = cache_root() / key
    lib = _library_in(target, library)
    if lib is not None:
        return lib
    cache_root().mkdir(parents=True, exist_ok=True)
    with open(cache_root() / f"{key}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        lib = _library_in(target, library)
        if lib is not None:
            return lib
        tmp = Path(tempfile.mkdtemp(prefix=f"{key}.", dir=cache_root()))
        for f in mod_files():
            shutil.copy2(f, tmp / f.name)
        print(f"neuromuscle: compiling {len(list(tmp.glob('*.mod')))} NMODL mechanisms into {target} "
              f"({library}; first use only; a few minutes)", file=sys.stderr, flush=True)
        failure = build(tmp)
        if failure is not None:
            raise MechanismBuildError(f"building {library} failed in {tmp} ({failure}")
        os.replace(tmp, target)
        print("neuromuscle: mechanisms compiled.", file=sys.stderr, flush=True)
    lib = _library_in(target, library)
    assert lib is not None
    return lib


def load_mechanisms() -> None:
    """Make the package's mechanisms available in this process's NEURON (idempotent), and have every
    ``finitialize`` tell them which integrator runs (:mod:`neuromuscle.model.integrator`)."""
    global _LOADED, _READY
    if _READY:  # every unit calls this: once this process has them, nothing is left to check
        return
    from neuron import h

    names = required_mechanisms()
    present = [hasattr(h, name) for name in names]
    if all(present):
        integrator.install(mod_files)
        _READY = True
        return
    if any(present):
        missing = [n for n, p in zip(names, present) if not p]
        raise MechanismBuildError(
            f"NEURON already holds some neuromuscle mechanisms but not {missing}: an old compiled copy "
            "(e.g. an x86_64/ folder in the working directory) is loaded; remove it or recompile mod/")
    digest = mechanism_hash()
    lib = _compiled_library(digest)
    if not h.nrn_load_dll(str(lib)):
        raise MechanismBuildError(f"NEURON could not load {lib}")
    _LOADED = digest
    integrator.install(mod_files)
    _READY = True
