"""Parameter sets of the three-module muscle (seed 001 Table 1), with units.

A parameter file is JSON: ``{"name": ..., "source": ..., "parameters": {NAME: {"value": v, "unit": u}}}``.
Units are part of the file and are checked against the model's own (``SPECS``); there is no silent conversion.
Shipped sets: ``CT09`` and ``CT95`` (``load_parameters("CT09")``).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Iterator, Mapping

from .errors import InputError


@dataclass(frozen=True)
class ParameterSpec:
    """One model parameter: its unit, the module that uses it, and its admissible range."""

    unit: str
    module: int
    lower: float = 0.0
    lower_inclusive: bool = False
    doc: str = ""


_POS = dict(lower=0.0, lower_inclusive=False)
_NONNEG = dict(lower=0.0, lower_inclusive=True)
_ANY = dict(lower=-math.inf, lower_inclusive=True)

#: Every parameter of the model: unit, module (1-3; 0 for the length compensation shared by 1 and 2), range.
SPECS: dict[str, ParameterSpec] = {
    "K1": ParameterSpec("1/(M*ms)", 1, **_POS, doc="CaSR-calsequestrin binding rate"),
    "K2": ParameterSpec("1/ms", 1, **_POS, doc="calsequestrin unbinding rate"),
    "K3": ParameterSpec("1/(M*ms)", 1, **_POS, doc="CaSP-buffer binding rate"),
    "K4": ParameterSpec("1/ms", 1, **_POS, doc="buffer unbinding rate"),
    "K5i": ParameterSpec("1/(M*ms)", 1, **_POS, doc="CaSP-troponin binding rate"),
    "K6i": ParameterSpec("1/ms", 1, **_POS, doc="troponin unbinding rate at rest"),
    "K": ParameterSpec("1/M", 1, **_POS, doc="pump site binding constant"),
    "Rmax": ParameterSpec("1/ms", 1, **_POS, doc="maximum SR permeability"),
    "Umax": ParameterSpec("M/ms", 1, **_POS, doc="maximal pump rate"),
    "tau1": ParameterSpec("ms", 1, **_POS, doc="release rise time constant"),
    "tau2": ParameterSpec("ms", 1, **_POS, doc="release decay time constant"),
    "CS0": ParameterSpec("M", 1, **_POS, doc="total calsequestrin"),
    "B0": ParameterSpec("M", 1, **_POS, doc="total sarcoplasmic buffer"),
    "T0": ParameterSpec("M", 1, **_POS, doc="total troponin"),
    "CaSR0": ParameterSpec("M", 1, **_NONNEG, doc="initial free SR calcium"),
    "phi1": ParameterSpec("1/mm", 0, **_ANY, doc="eq 18 slope at or below the optimum"),
    "phi2": ParameterSpec("1", 0, **_ANY, doc="eq 18 intercept at or below the optimum"),
    "phi3": ParameterSpec("1/mm", 0, **_ANY, doc="eq 18 slope above the optimum"),
    "phi4": ParameterSpec("1", 0, **_ANY, doc="eq 18 intercept above the optimum"),
    "C1": ParameterSpec("1", 2, **_ANY, doc="normalised [CaSPT] at half activation"),
    "C2": ParameterSpec("1", 2, **_POS, doc="slope of the activation curve"),
    "C3": ParameterSpec("ms", 2, **_POS, doc="time-constant scale"),
    "C4": ParameterSpec("1", 2, **_ANY, doc="normalised [CaSPT] of the largest time constant"),
    "C5": ParameterSpec("1", 2, **_POS, doc="width of the time-constant bell"),
    "alpha": ParameterSpec("1", 2, **_POS, doc="exponent A = Atil^alpha"),
    "alpha1": ParameterSpec("1", 2, **_NONNEG, doc="eq 19 amplitude"),
    "alpha2": ParameterSpec("ms", 2, **_ANY, doc="eq 19 midpoint after movement onset"),
    "alpha3": ParameterSpec("ms", 2, **_POS, doc="eq 19 width"),
    "beta": ParameterSpec("1", 2, **_NONNEG, doc="eq 20 length divisor"),
    "gamma": ParameterSpec("s/mm", 2, **_NONNEG, doc="eq 20 velocity divisor"),
    "KSE": ParameterSpec("1/mm", 3, **_POS, doc="series-elastic stiffness normalised by P0"),
    "P0": ParameterSpec("N", 3, **_POS, doc="maximal isometric force at the optimum"),
    "g1": ParameterSpec("mm", 3, **_ANY, doc="optimal length"),
    "g2": ParameterSpec("mm", 3, **_POS, doc="width of the force-length Gaussian"),
    "a0": ParameterSpec("N", 3, **_POS, doc="Hill coefficient"),
    "b0": ParameterSpec("mm/s", 3, **_POS, doc="Hill coefficient"),
    "c0": ParameterSpec("N", 3, **_ANY, doc="Mashima coefficient"),
    "d0": ParameterSpec("mm/s", 3, **_POS, doc="Mashima coefficient"),
}


def _check_value(name: str, value: object, where: str) -> float:
    if name not in SPECS:
        raise InputError(f"{where}: unknown parameter {name!r} (known: {', '.join(SPECS)})")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}: parameter {name!r} must be a number, got {value!r}")
    v = float(value)
    spec = SPECS[name]
    if not math.isfinite(v):
        raise InputError(f"{where}: parameter {name!r} is not finite ({v})")
    if v < spec.lower or (v == spec.lower and not spec.lower_inclusive):
        rel = ">=" if spec.lower_inclusive else ">"
        raise InputError(f"{where}: parameter {name!r} = {v} {spec.unit} must be {rel} {spec.lower}")
    return v


@dataclass(frozen=True)
class ParameterSet(Mapping[str, float]):
    """An immutable, validated, complete set of model parameters (values in the units of ``SPECS``)."""

    name: str
    values: Mapping[str, float]
    source: str = ""

    def __post_init__(self) -> None:
        checked = {k: _check_value(k, v, f"parameter set {self.name!r}") for k, v in self.values.items()}
        missing = [k for k in SPECS if k not in checked]
        if missing:
            raise InputError(f"parameter set {self.name!r} lacks {', '.join(missing)}")
        object.__setattr__(self, "values", dict(checked))

    def __getitem__(self, key: str) -> float:
        return self.values[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.values)

    def __len__(self) -> int:
        return len(self.values)

    def with_values(self, **changes: float) -> "ParameterSet":
        """A copy with some values replaced (same units); unknown names and bad values raise InputError."""
        for k, v in changes.items():
            _check_value(k, v, f"override of {self.name!r}")
        return ParameterSet(self.name, {**self.values, **changes}, self.source)

    def to_json(self) -> dict:
        """The file form: values with their units."""
        return {"name": self.name, "source": self.source,
                "parameters": {k: {"value": v, "unit": SPECS[k].unit} for k, v in self.values.items()}}

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
    values: dict[str, float] = {}
    for k, entry in doc["parameters"].items():
        if not isinstance(entry, dict) or "value" not in entry or "unit" not in entry:
            raise InputError(f"{where}: parameter {k!r} must be {{'value': number, 'unit': string}}")
        if k in SPECS and entry["unit"] != SPECS[k].unit:
            raise InputError(f"{where}: parameter {k!r} has unit {entry['unit']!r}, the model uses "
                             f"{SPECS[k].unit!r} (no implicit conversion)")
        values[k] = _check_value(k, entry["value"], where)
    return ParameterSet(str(doc.get("name", where)), values, str(doc.get("source", where)))


def load_parameters(name_or_path: str | Path) -> ParameterSet:
    """Load a shipped set by name (``"CT09"``, ``"CT95"``) or a parameter file by path."""
    text: str
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
