"""The muscle length input (mod/MuscleLength.mod) as a component: xm (mm) and vm (mm/s), played or set."""

from __future__ import annotations

from .component import Component


class MuscleLength(Component):
    """MuscleLength: the length Xm (mm, relative to the physiological maximum) and velocity Vm (mm/s, positive =
    lengthening) that the muscle mechanisms read.  Under MPI each rank holds its own (a POINTER cannot cross
    ranks); a pool shares one per rank."""

    suffix = "MuscleLength"
    namespace = "length"
    exposes = {"xm": "mm", "vm": "mm/s"}
