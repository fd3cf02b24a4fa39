"""MPI for pools: find the MPI library of the ``mpi`` extra, start NEURON's MPI, build ``mpiexec`` command lines.

NEURON's pip wheel loads MPI at run time (``h.nrnmpi_init()``) and looks for ``libmpi.so`` on the loader's path;
the ``mpich`` wheel (``pip install 'neuromuscle[mpi]'``) puts it in the environment's ``lib/``, which is not on
that path, so NEURON would silently run every rank alone.  :func:`init_mpi` points ``MPI_LIB_NRN_PATH`` at the
wheel's library when it is unset, starts MPI, and refuses to go on when NEURON sees fewer ranks than the launcher
started (each rank would otherwise simulate and write the whole pool).

    rank, nhost = init_mpi()          # first thing in a script run by ``mpiexec -n 2 python script.py``
"""

from __future__ import annotations

import os
import shutil
import sys
from importlib import metadata
from pathlib import Path
from typing import NoReturn

from ..errors import InputError, NeuromuscleError

#: Environment variables by which MPI launchers tell a process how many ranks they started (MPICH's Hydra,
#: Open MPI, PMIx).
LAUNCHER_SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "PMIX_SIZE")


class MPIError(NeuromuscleError):
    """MPI is missing or NEURON did not join the ranks the launcher started."""


def mpi_library() -> Path | None:
    """The MPI shared library NEURON should load: ``$MPI_LIB_NRN_PATH`` if set, else ``libmpi.so`` of the
    installed ``mpich`` wheel, else None (NEURON then searches the loader's path itself)."""
    env = os.environ.get("MPI_LIB_NRN_PATH")
    if env:
        return Path(env)
    try:
        files = metadata.files("mpich") or []
        dist = metadata.distribution("mpich")
    except metadata.PackageNotFoundError:
        return None
    for name in ("libmpi.so.12", "libmpi.so"):
        for f in files:
            if Path(str(f)).name == name:
                path = Path(str(dist.locate_file(f))).resolve()
                if path.exists():
                    return path
    return None


def mpiexec() -> str | None:
    """Path of ``mpiexec``: the one beside this Python (the mpich wheel's), else the first on PATH, else None."""
    here = Path(sys.executable).parent / "mpiexec"
    if here.exists():
        return str(here)
    return shutil.which("mpiexec")


def mpi_available() -> bool:
    """True when pools can run on several ranks here: mpiexec and an MPI library NEURON can load."""
    return mpiexec() is not None and mpi_library() is not None


def mpiexec_command(n_ranks: int, args: list[str]) -> list[str]:
    """``mpiexec -n n_ranks <this python> args...`` (args start with e.g. ``-m``); raises MPIError without MPI."""
    if isinstance(n_ranks, bool) or not isinstance(n_ranks, int) or n_ranks < 1:
        raise InputError(f"number of MPI ranks must be an integer >= 1, got {n_ranks!r}")
    exe = mpiexec()
    if exe is None or mpi_library() is None:
        raise MPIError("no MPI here: install the extra (pip install -e '.[mpi]': mpich and mpi4py) to run on "
                       "several ranks")
    return [exe, "-n", str(n_ranks), sys.executable, *args]


def launcher_size() -> int | None:
    """Number of ranks the MPI launcher started (from its environment), or None when not under a launcher."""
    for name in LAUNCHER_SIZE_VARIABLES:
        value = os.environ.get(name)
        if value and value.isdigit():
            return int(value)
    return None


def init_mpi() -> tuple[int, int]:
    """Start NEURON's MPI (call before any other use of NEURON in the process); returns (rank, number of ranks).

    Not under a launcher (or without an MPI library) this is one rank.  Raises MPIError when the launcher
    started more ranks than NEURON joined (no MPI library found): nothing must then run twice."""
    expected = launcher_size()
    lib = mpi_library()
    if lib is not None:
        os.environ.setdefault("MPI_LIB_NRN_PATH", str(lib))
    from neuron import h

    if lib is not None or (expected or 1) > 1:
        h.nrnmpi_init()
    pc = h.ParallelContext()
    rank, nhost = int(pc.id()), int(pc.nhost())
    if expected is not None and nhost != expected:
        raise MPIError(f"the MPI launcher started {expected} ranks but NEURON joined {nhost} (no MPI library "
                       f"found: MPI_LIB_NRN_PATH={os.environ.get('MPI_LIB_NRN_PATH')!r}); install the extra "
                       "(pip install -e '.[mpi]') or set MPI_LIB_NRN_PATH to libmpi.so")
    return rank, nhost


def finish_mpi(code: int) -> NoReturn:
    """Leave MPI cleanly on every rank (a barrier, then NEURON's ``pc.done()``) and exit the process with
    ``code`` (NEURON's MPI does not end through the interpreter's normal exit)."""
    from neuron import h

    sys.stdout.flush()
    sys.stderr.flush()
    pc = h.ParallelContext()
    pc.barrier()
    pc.done()
    os._exit(code)
