"""Tell the mechanisms which integrator NEURON runs: their GLOBAL ``variable_step``.

Several mechanisms (KimCa, KimAct, KimForce, KimUnit, HatzeExc, HatzeMTC, mn_soma, mn_pic) advance by a step of
their own under NEURON's fixed step and give CVODE the exact right-hand side of the same equations.  NMODL has no
portable way to ask which integrator is running (CoreNEURON, which has only the fixed step, has no such flag), so
each of them reads a GLOBAL parameter ``variable_step`` (hoc: ``variable_step_<name>``): 1 under CVODE, 0 under
the fixed step.  :func:`install` registers an ``FInitializeHandler`` that sets every one of them from
``CVode.active()`` at the start of each ``finitialize``, so Python users (the Simulator, or a run of their own)
never set it; a hoc user who runs CVODE sets ``variable_step_KimCa = 1`` and so on (see the mod files).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Callable

#: NMODL's declaration of the flag in a mechanism's NEURON block.
_DECLARATION = re.compile(r"^\s*GLOBAL\s+variable_step\s*$", re.M)
_NAME = re.compile(r"^\s*(?:SUFFIX|POINT_PROCESS|ARTIFICIAL_CELL)\s+(\w+)", re.M)

#: The handler registered in this process (one for all runs; NEURON keeps it while a reference exists).
_HANDLER: list[Any] = []


def flag_names(mod_files: list[Path]) -> list[str]:
    """hoc names (``variable_step_<mechanism>``) of the flags declared by the given mod files."""
    names = []
    for f in mod_files:
        text = f.read_text()
        m = _NAME.search(text)
        if m and _DECLARATION.search(text):
            names.append(f"variable_step_{m.group(1)}")
    return names


def set_variable_step(on: bool, names: list[str]) -> None:
    """Set every flag in ``names`` to 1 (CVODE) or 0 (fixed step)."""
    from neuron import h

    value = 1.0 if on else 0.0
    for name in names:
        setattr(h, name, value)


def install(mod_files: Callable[[], list[Path]]) -> None:
    """Register (once per process) the FInitializeHandler that sets the flags declared by ``mod_files()`` from
    ``CVode.active()`` at the start of every ``finitialize``, before any INITIAL block runs."""
    if _HANDLER:
        return
    from neuron import h

    names = flag_names(mod_files())

    cvode = h.CVode()

    def _sync() -> None:
        set_variable_step(bool(cvode.active()), names)

    _HANDLER.append(h.FInitializeHandler(3, _sync))
    _HANDLER.append(_sync)
