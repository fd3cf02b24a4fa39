"""Scott, Brown & Loeb (1996), cat soleus: digitized force-length (Fig 3A) and force-velocity (Fig 4) points.

Units: lengths in L0 (optimal fascicle length), velocities in L0/s (negative = shortening), forces in F0
(maximal isometric tetanic force). Source files: github.com/mjhmilla/DigitizedMusculotendonData
(``cat_digitized_literature``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np

from ..errors import InputError
from ..measured.csv_import import parse_cell
from ..measured.schema import PathLike


@dataclass(frozen=True, eq=False)
class ForceLengthVelocityPoints:
    """Digitized cat soleus points of Scott, Brown & Loeb (1996) J Muscle Res Cell Motil 17:207.

    Lengths in L0 (optimal fascicle length), velocities in L0/s (negative = shortening), forces in F0 (maximal
    isometric tetanic force). Fig 3A: tetanic active force-length (``active_*``) and passive force-length
    (``passive_*``) per specimen ('S8'..'S12' in ``*_specimen``); Fig 4: force-velocity (``velocity_*``).
    Points are in digitizing order (not sorted); digitizing error ~1-2 % of the axis range.
    """

    active_length_L0: np.ndarray
    active_force_F0: np.ndarray
    active_specimen: np.ndarray
    passive_length_L0: np.ndarray
    passive_force_F0: np.ndarray
    passive_specimen: np.ndarray
    velocity_L0_per_s: np.ndarray
    velocity_force_F0: np.ndarray
    source: str


SCOTT_BROWN_LOEB_FILES = ("fig_ScottBrownLoeb1996_fig3.csv", "fig_ScottBrownLoeb1996_fig4.csv")


def load_scott_brown_loeb_1996(folder: PathLike) -> ForceLengthVelocityPoints:
    """Read fig_ScottBrownLoeb1996_fig3.csv (series fl08..fl12 active, fp08..fp12 passive F-L) and
    fig_ScottBrownLoeb1996_fig4.csv (series fv) from ``folder`` (cat_digitized_literature)."""
    root = Path(folder)
    fig3 = _read_blocks(root / SCOTT_BROWN_LOEB_FILES[0])
    fig4 = _read_blocks(root / SCOTT_BROWN_LOEB_FILES[1])
    active = _stack_series(fig3, "fl", root / SCOTT_BROWN_LOEB_FILES[0])
    passive = _stack_series(fig3, "fp", root / SCOTT_BROWN_LOEB_FILES[0])
    if "fv" not in fig4:
        raise InputError(f"{root / SCOTT_BROWN_LOEB_FILES[1]}: no series 'fv'")
    fv = fig4["fv"]
    return ForceLengthVelocityPoints(
        active_length_L0=active[0], active_force_F0=active[1], active_specimen=active[2],
        passive_length_L0=passive[0], passive_force_F0=passive[1], passive_specimen=passive[2],
        velocity_L0_per_s=fv[:, 0].copy(), velocity_force_F0=fv[:, 1].copy(),
        source="Scott SH, Brown IE, Loeb GE (1996) J Muscle Res Cell Motil 17:207, Figs 3A and 4, digitized by "
               "M. Millard (github.com/mjhmilla/DigitizedMusculotendonData 3ef51196), MIT licence")


def _read_blocks(path: Path) -> dict[str, np.ndarray]:
    """Blocks 'x,<series>' followed by 'x,y' rows -> {series: (n, 2) array}; errors name file and line."""
    if not path.is_file():
        raise InputError(f"{path}: file not found")
    blocks: dict[str, list[tuple[float, float]]] = {}
    name = None
    with open(path, encoding="utf-8-sig") as fh:
        for line_no, line in enumerate(fh, start=1):
            cells = [c.strip() for c in line.strip().split(",")]
            if not cells[0]:
                continue
            if len(cells) < 2:
                raise InputError(f"{path}: line {line_no}: expected two comma-separated values")
            if cells[0] == "x":
                name = cells[1]
                blocks[name] = []
                continue
            if name is None:
                raise InputError(f"{path}: line {line_no}: data before the first 'x,<series>' header")
            blocks[name].append((parse_cell(path, line_no, "x", cells[0]), parse_cell(path, line_no, "y", cells[1])))
    return {k: np.asarray(v, dtype=np.float64).reshape(-1, 2) for k, v in blocks.items()}


def _stack_series(blocks: Mapping[str, np.ndarray], prefix: str, path: Path) -> tuple[np.ndarray, np.ndarray,
                                                                                       np.ndarray]:
    """Concatenate series '<prefix>NN' into (x, y, specimen label 'SNN') arrays."""
    names = [k for k in blocks if k.startswith(prefix) and k[len(prefix):].isdigit()]
    if not names:
        raise InputError(f"{path}: no series named '{prefix}NN'")
    x = np.concatenate([blocks[k][:, 0] for k in names])
    y = np.concatenate([blocks[k][:, 1] for k in names])
    labels = np.concatenate([[f"S{int(k[len(prefix):])}"] * len(blocks[k]) for k in names]).astype(str)
    return x, y, labels
