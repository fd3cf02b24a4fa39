"""Two extensions on one modulation port: the PortCombine mechanism (mod/PortCombine.mod) that multiplies two gains
or adds two offsets, so that several causes act in one unit."""

from __future__ import annotations

from typing import Any, Mapping

from .component import Component, Port


class PortCombine(Component):
    """out = a * b (mode 0, gains) or a + b (mode 1, offsets); a and b are wired by the unit."""

    suffix = "PortCombine"
    namespace = "port_combine"
    reads = (Port("a", "1"), Port("b", "1"))
    exposes = {"out": "1"}

    def __init__(self, unit: str) -> None:
        super().__init__()
        self.mode = 1.0 if unit == "N" else 0.0

    def configure(self, params: Mapping[str, float] | None) -> None:
        self.obj.mode = self.mode

    def switches(self) -> dict[str, Any]:
        return {"mode": "product" if self.mode == 0.0 else "sum"}
