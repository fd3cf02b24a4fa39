"""Parameter sets: validated, immutable values with units, read from and written to JSON files.

A parameter file is ``{"name": ..., "source": ..., "parameters": {NAME: {"value": v, "unit": u}}}`` where NAME is
a qualified name (``kim_m2.C1``) or a flat Kim alias (``C1``: the shipped CT09/CT95 use these).  Units are part
of the file and are checked against the registry; there is no silent conversion.  Every value must lie inside the
parameter's physiological range.  Shipped sets: ``CT09`` and ``CT95`` (``load_parameters("CT09")``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Iterator, Mapping

from ..errors import InputError
from .specs import registry


@dataclass(frozen=True)
class ParameterSet(Mapping[str, float]):
    """An immutable, validated set of parameter values keyed by qualified name (flat Kim aliases accepted for
    lookup), in the units of the registry (``neuromuscle.parameters.SPECS``)."""

    name: str
    values: Mapping[str, float]
    source: str = ""

    def __post_init__(self) -> None:
        reg = registry()
        where = f"parameter set {self.name!r}"
        checked: dict[str, float] = {}
        for k, v in self.values.items():
            q = reg.resolve(k) if k in reg else None
            if q is None:
                raise InputError(f"{where}: unknown parameter {k!r} (known: {', '.join(reg.aliases)}, or a "
                                 "qualified name such as kim_m2.C1)")
            if q in checked:
                raise InputError(f"{where}: parameter {q} given twice (as {k!r} and its other name)")
            checked[q] = reg[q].check(v, where)
        kim = set(reg.aliases.values())
        if kim & set(checked) and not kim <= set(checked):
            missing = [reg.alias(q) for q in reg.aliases.values() if q not in checked]
            raise InputError(f"{where} lacks {', '.join(missing)} (a set of the Kim modules names all of them)")
        object.__setattr__(self, "values", checked)

    def __getitem__(self, key: str) -> float:
        reg = registry()
        q = reg.aliases.get(key, key)
        try:
            return self.values[q]
        except KeyError:
            raise KeyError(key) from None

    def __contains__(self, key: object) -> bool:
        return isinstance(key, str) and registry().aliases.get(key, key) in self.values

    def __iter__(self) -> Iterator[str]:
        return iter(self.values)

    def __len__(self) -> int:
        return len(self.values)

    def with_values(self, changes: Mapping[str, float] | None = None, /, **kw: float) -> ParameterSet:
        """A copy with some values replaced (flat or qualified names, same units); unknown names and values
        outside their range raise InputError naming them."""
        reg = registry()
        new = dict(self.values)
        for k, v in {**dict(changes or {}), **kw}.items():
            new[reg.resolve(k)] = v
        return ParameterSet(self.name, new, self.source)

    def to_json(self) -> dict:
        """The file form: values with their units, Kim parameters under their flat names."""
        reg = registry()
        return {"name": self.name, "source": self.source,
                "parameters": {reg.alias(k): {"value": v, "unit": reg[k].unit} for k, v in self.values.items()}}

    def save(self, path: str | Path) -> None:
        """Write the set as a parameter file that ``load_parameters`` and ``neuromuscle simulate`` accept."""
        Path(path).write_text(json.dumps(self.to_json(), indent=2) + "\n")


def builtin_sets() -> list[str]:
    """Names of the parameter sets shipped with the package."""
    return sorted(p.name[:-5] for p in resources.files("neuromuscle.data.params").iterdir()
                  if p.name.endswith(".json"))


def parameters_from_json(doc: object, where: str) -> ParameterSet:
    """Build a ParameterSet from the parsed JSON of a parameter file; ``where`` names it in errors."""
    if not isinstance(doc, dict) or not isinstance(doc.get("parameters"), dict):
        raise InputError(f"{where}: expected an object with a 'parameters' object")
    reg = registry()
    values: dict[str, float] = {}
    for k, entry in doc["parameters"].items():
        if not isinstance(entry, dict) or "value" not in entry or "unit" not in entry:
            raise InputError(f"{where}: parameter {k!r} must be {{'value': number, 'unit': string}}")
        if k not in reg:
            raise InputError(f"{where}: unknown parameter {k!r} (known: {', '.join(reg.aliases)}, or a qualified "
                             "name such as kim_m2.C1)")
        if entry["unit"] != reg[k].unit:
            raise InputError(f"{where}: parameter {k!r} has unit {entry['unit']!r}, the model uses "
                             f"{reg[k].unit!r} (no implicit conversion)")
        values[k] = reg[k].check(entry["value"], where)
    return ParameterSet(str(doc.get("name", where)), values, str(doc.get("source", where)))


def load_parameters(name_or_path: str | Path) -> ParameterSet:
    """Load a shipped set by name (``"CT09"``, ``"CT95"``) or a parameter file by path."""
    where = str(name_or_path)
    if str(name_or_path) in builtin_sets():
        text = resources.files("neuromuscle.data.params").joinpath(f"{name_or_path}.json").read_text()
        where = f"built-in set {name_or_path}"
    else:
        path = Path(name_or_path)
        if not path.is_file():
            raise InputError(f"parameter set {where!r}: neither a built-in set ({', '.join(builtin_sets())}) "
                             "nor a file")
        text = path.read_text()
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: not valid JSON ({exc})") from None
    return parameters_from_json(doc, where)
