"""What a pool records of one unit: its muscle unit's variables by the single unit's names ("ca.CaSPT",
"act.A", "force.F": ``MuscleUnit.recordables``) and its motoneuron's as "mn.<name>" ("mn.v", "mn.v_dend",
"mn.i_pic", "mn.cai": ``motoneuron.RECORDABLES``), through the single unit's Recorder.

    pool.record(["mn.v", "act.A", "ca.CaSPT"], units=[0, 5])     # before pool.run
    result.recordings["act.A"].values                             # (recorded units, samples)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from ..errors import InputError

#: Prefix of a motoneuron variable in a pool's recorded names.
MOTONEURON_SLOT = "mn"


@dataclass
class Recording:
    """One variable recorded in several units: ``values[k]`` is unit ``units[k]``'s trace, sampled at the
    result's ``t_ms``, in ``unit`` (mV, mM, N, 1...)."""

    variable: str
    unit: str
    units: list[int]
    values: np.ndarray


class PoolUnit:
    """A pool's unit as the Recorder sees it: the muscle unit's variables and, when built, the motoneuron's."""

    def __init__(self, muscle: Any, cell: Any | None, name: str) -> None:
        self.muscle = muscle
        self.cell = cell
        self.name = name

    def recordables(self) -> dict[str, str]:
        """Every recordable name with its unit."""
        out = dict(self.muscle.recordables())
        if self.cell is not None:
            out.update({f"{MOTONEURON_SLOT}.{k}": u for k, u in self.cell.recordables().items()})
        return out

    def _cell_variable(self, name: str) -> str | None:
        slot, _, var = name.partition(".")
        if slot != MOTONEURON_SLOT:
            return None
        if self.cell is None:
            raise InputError(f"{self.name}: {name!r} needs a motoneuron; this pool was built without them")
        return var

    def ref(self, name: str) -> Any:
        """NEURON reference to ``name``."""
        var = self._cell_variable(name)
        return self.muscle.ref(name) if var is None else self.cell.ref(var)

    def owner(self, name: str) -> Any:
        """The muscle unit's point process, or the motoneuron's section, holding ``name``."""
        var = self._cell_variable(name)
        return self.muscle.owner(name) if var is None else self.cell.section_of(var)


def gather_recordings(names: Sequence[str], units: Sequence[int],
                      traced: Mapping[int, tuple[Mapping[str, np.ndarray], Mapping[str, str]]]
                      ) -> dict[str, Recording]:
    """Every variable of ``names`` over ``units`` (indices, ascending) from the per-unit traces gathered from
    the ranks (``traced[unit] = (traces by name, units of measure by name)``)."""
    missing = [u for u in units if u not in traced]
    if missing:
        raise InputError(f"recordings of units {missing} are missing from the gathered traces")
    return {x: Recording(x, traced[units[0]][1][x], list(units), np.array([traced[u][0][x] for u in units]))
            for x in names}
