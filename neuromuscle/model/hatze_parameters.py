"""Parameters of the Hatze excitation / triceps surae model of van Zandwijk et al. 1998 (Tables 1-4),
with units.

The tables ship as JSON files in ``neuromuscle/data/hatze/`` (``{"value": v, "unit": u}`` per quantity, plus
``"lower"``/``"upper"`` for the 95 % confidence intervals of Tables 2 and 3). Loading checks every entry: an
unknown name, a unit other than the expected one, a non-finite or a non-positive value raises ``InputError``
naming the file and the quantity. All values are SI with angles in rad:

* Table 1 (``Subject``): k_see N m/rad^2, phi_ce_opt rad, m_max N m, a_rel (1), b_rel Hz, and w (1).
* Table 2 (``ExcitationTheta``): theta1 1/s, theta2 1/s^2, theta3 1/s, theta4 1/s^2, theta5 1/s^4.
  With alpha dimensionless, beta is in s^2 and gamma in s^4, so theta5*gamma is dimensionless.
* Table 3 (``TrendParameters``): m 1/s and c in the paper's concentration convention (mol/L).
* Table 4 (``ActiveStateConstants``): q0, rho2, xi_check, s (all dimensionless).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields, replace
from importlib import resources
from pathlib import Path
from typing import Mapping

import numpy as np

from ..errors import InputError

_PACKAGE = "neuromuscle.data.hatze"
_TABLE1 = "table1_contraction.json"
_TABLE2 = "table2_excitation.json"
_TABLE3 = "table3_trend.json"
_TABLE4 = "table4_active_state.json"

#: Names of the five excitation parameters, in order.
THETA_NAMES: tuple[str, ...] = ("theta1", "theta2", "theta3", "theta4", "theta5")
#: Units of the five excitation parameters (time in s).
THETA_UNITS: dict[str, str] = {"theta1": "1/s", "theta2": "1/s^2", "theta3": "1/s", "theta4": "1/s^2",
                               "theta5": "1/s^4"}
_SUBJECT_UNITS: dict[str, str] = {"k_see": "N*m/rad^2", "phi_ce_opt": "rad", "m_max": "N*m", "a_rel": "1",
                                  "b_rel": "Hz"}
_SHARED_UNITS: dict[str, str] = {"w": "1"}
_TREND_UNITS: dict[str, str] = {"m": "1/s", "c": "mol/L"}
_ACTIVE_UNITS: dict[str, str] = {"q0": "1", "rho2": "1", "xi_check": "1", "s": "1"}


def check_positive(name: str, value: object, where: str = "", allow_zero: bool = False) -> float:
    """Return ``value`` as a float if it is a finite number > 0 (>= 0 with ``allow_zero``), else InputError."""
    prefix = f"{where}: " if where else ""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{prefix}{name} must be a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise InputError(f"{prefix}{name} is not finite ({v})")
    if v < 0.0 or (v == 0.0 and not allow_zero):
        rel = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{prefix}{name} = {v} must be {rel}")
    return v


def _check_fields(obj: object, where: str, allow_zero: tuple[str, ...] = ()) -> None:
    for f in fields(obj):  # type: ignore[arg-type]
        if f.type in ("str", str):
            continue
        value = getattr(obj, f.name)
        object.__setattr__(obj, f.name, check_positive(f.name, value, where, f.name in allow_zero))


@dataclass(frozen=True)
class Subject:
    """Contraction dynamics of one subject (Table 1) in angular coordinates.

    Attributes: ``k_see`` SEE stiffness (N m/rad^2); ``phi_ce_opt`` CE optimum angle (rad); ``m_max`` maximal
    isometric CE moment at the optimum (N m); ``a_rel`` Hill constant (1); ``b_rel`` Hill constant (Hz,
    ``b = b_rel * phi_ce_opt`` rad/s); ``w`` width of the moment-angle parabola (1); ``k_pee`` PEE stiffness
    (N m/rad^2, 0 in all the paper's experiments); ``phi_pee0_rel`` PEE slack angle / phi_ce_opt (1).
    """

    name: str
    k_see: float
    phi_ce_opt: float
    m_max: float
    a_rel: float
    b_rel: float
    w: float = 0.56
    k_pee: float = 0.0
    phi_pee0_rel: float = 1.0

    def __post_init__(self) -> None:
        _check_fields(self, f"subject {self.name!r}", allow_zero=("k_pee",))

    @property
    def b(self) -> float:
        """Hill constant b = b_rel * phi_ce_opt (rad/s)."""
        return self.b_rel * self.phi_ce_opt

    @property
    def v_max(self) -> float:
        """Maximal CE shortening velocity at the optimum under q = 1: b / a_rel (rad/s)."""
        return self.b / self.a_rel

    def with_values(self, **changes: float) -> Subject:
        """A copy with some values replaced (same units); bad values raise InputError."""
        unknown = [k for k in changes if k not in {f.name for f in fields(self)}]
        if unknown:
            raise InputError(f"subject {self.name!r}: unknown parameter(s) {', '.join(unknown)}")
        return replace(self, **changes)


@dataclass(frozen=True)
class ExcitationTheta:
    """The five excitation parameters of eqs 6-9 (time in s).

    ``theta1`` (1/s) and ``theta2`` (1/s^2): beta'' + theta1 beta' + theta2 beta = alpha (eq 6);
    ``theta3`` (1/s) and ``theta4`` (1/s^2): gamma'' + theta3 gamma' + theta4 gamma = beta (eq 7);
    ``theta5`` (1/s^4): scale of gamma in the active state q (eq 9).
    """

    theta1: float
    theta2: float
    theta3: float
    theta4: float
    theta5: float

    def __post_init__(self) -> None:
        _check_fields(self, "theta")

    def as_array(self) -> np.ndarray:
        """[theta1 .. theta5] in 1/s, 1/s^2, 1/s, 1/s^2, 1/s^4."""
        return np.array([self.theta1, self.theta2, self.theta3, self.theta4, self.theta5])

    @classmethod
    def from_array(cls, values: object) -> ExcitationTheta:
        """Build from five numbers in the order and units of ``THETA_NAMES``."""
        try:
            arr = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"theta must be five numbers (theta1..theta5), got {values!r}") from None
        if arr.size != 5:
            raise InputError(f"theta must have 5 values (theta1..theta5), got {arr.size}")
        return cls(*(float(v) for v in arr))


@dataclass(frozen=True)
class ActiveStateConstants:
    """Constants of the active state-calcium relationship, eq 9 (Table 4), all dimensionless.

    ``q0`` resting active state (0 < q0 < 1); ``rho2`` > 1 (real roots m1, m2); ``xi_check`` > 1 the relative CE
    length at which rho* diverges; ``s`` the exponent of rho*.
    """

    q0: float = 0.005
    rho2: float = 1.05
    xi_check: float = 2.90
    s: float = 1.0

    def __post_init__(self) -> None:
        _check_fields(self, "active-state constants")
        if not self.q0 < 1.0:
            raise InputError(f"active-state constants: q0 = {self.q0} must be < 1")
        if not self.rho2 > 1.0:
            raise InputError(f"active-state constants: rho2 = {self.rho2} must be > 1 (real m1 != m2)")
        if not self.xi_check > 1.0:
            raise InputError(f"active-state constants: xi_check = {self.xi_check} must be > 1")

    @property
    def m1(self) -> float:
        """m1 = -rho2 + sqrt(rho2^2 - 1)."""
        return -self.rho2 + math.sqrt(self.rho2 ** 2 - 1.0)

    @property
    def m2(self) -> float:
        """m2 = -rho2 - sqrt(rho2^2 - 1)."""
        return -self.rho2 - math.sqrt(self.rho2 ** 2 - 1.0)


@dataclass(frozen=True)
class Interval:
    """A published estimate with its 95 % confidence interval (same unit for all three)."""

    value: float
    lower: float
    upper: float
    unit: str

    def contains(self, x: float) -> bool:
        """True if lower <= x <= upper."""
        return self.lower <= x <= self.upper


@dataclass(frozen=True)
class TrendParameters:
    """First-order trend function eq 10, dgamma/dt = m (c nu - gamma): ``m`` (1/s) and ``c``.

    ``c`` carries whatever convention its producer states: Table 3 gives it in mol/L; ``fit_trend`` returns it on
    the raw scale of gamma in eqs 6-7 (s^4).
    """

    m: float
    c: float

    def __post_init__(self) -> None:
        _check_fields(self, "trend parameters")


# ------------------------------------------------------------------------------------------- file parsing

def _read_doc(filename: str) -> tuple[dict, str]:
    where = f"neuromuscle/data/hatze/{filename}"
    text = resources.files(_PACKAGE).joinpath(filename).read_text()
    try:
        return json.loads(text), where
    except json.JSONDecodeError as exc:  # pragma: no cover - shipped files are valid
        raise InputError(f"{where}: not valid JSON ({exc})") from None


def _read_file(path: str | Path) -> tuple[dict, str]:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"parameter file {str(path)!r} does not exist")
    try:
        return json.loads(p.read_text()), str(path)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON ({exc})") from None


def _quantities(block: object, units: Mapping[str, str], where: str, with_interval: bool = False,
                required: bool = True) -> dict[str, object]:
    """Validate a ``{name: {"value", "unit"[, "lower", "upper"]}}`` block; return floats or Intervals."""
    if not isinstance(block, dict):
        raise InputError(f"{where}: expected an object of quantities, got {type(block).__name__}")
    out: dict[str, object] = {}
    for name, entry in block.items():
        if name not in units:
            raise InputError(f"{where}: unknown quantity {name!r} (known: {', '.join(units)})")
        keys = ("value", "unit", "lower", "upper") if with_interval else ("value", "unit")
        if not isinstance(entry, dict) or any(k not in entry for k in keys):
            raise InputError(f"{where}: quantity {name!r} must be an object with keys {', '.join(keys)}")
        if entry["unit"] != units[name]:
            raise InputError(f"{where}: quantity {name!r} has unit {entry['unit']!r}, expected {units[name]!r} "
                             "(no implicit conversion)")
        value = check_positive(name, entry["value"], where)
        if with_interval:
            lo = check_positive(f"{name}.lower", entry["lower"], where)
            hi = check_positive(f"{name}.upper", entry["upper"], where)
            if not lo <= value <= hi:
                raise InputError(f"{where}: quantity {name!r}: interval [{lo}, {hi}] does not contain {value}")
            out[name] = Interval(value, lo, hi, units[name])
        else:
            out[name] = value
    missing = [k for k in units if k not in out]
    if required and missing:
        raise InputError(f"{where}: missing quantity/ies {', '.join(missing)}")
    return out


def subjects_from_json(doc: object, where: str) -> dict[str, Subject]:
    """Table 1 from parsed JSON: ``{"shared": {"w": ...}, "subjects": {name: {k_see, ...}}}``."""
    if not isinstance(doc, dict) or not isinstance(doc.get("subjects"), dict) or not doc["subjects"]:
        raise InputError(f"{where}: expected an object with a non-empty 'subjects' object")
    shared = _quantities(doc.get("shared", {}), _SHARED_UNITS, f"{where} [shared]", required=False)
    return {str(name): Subject(str(name), **_quantities(block, _SUBJECT_UNITS, f"{where} [subject {name}]"),
                               **shared)  # type: ignore[arg-type]
            for name, block in doc["subjects"].items()}


def theta_intervals_from_json(doc: object, where: str) -> dict[str, Interval]:
    """Table 2 from parsed JSON: ``{"parameters": {theta1: {value, lower, upper, unit}, ...}}``."""
    if not isinstance(doc, dict):
        raise InputError(f"{where}: expected an object with a 'parameters' object")
    return _quantities(doc.get("parameters"), THETA_UNITS, where, with_interval=True)  # type: ignore[return-value]


def trend_table_from_json(doc: object, where: str) -> dict[str, dict[str, Interval]]:
    """Table 3 from parsed JSON: ``{"subjects": {name: {"m": {...}, "c": {...}}}}``."""
    if not isinstance(doc, dict) or not isinstance(doc.get("subjects"), dict) or not doc["subjects"]:
        raise InputError(f"{where}: expected an object with a non-empty 'subjects' object")
    return {str(name): _quantities(block, _TREND_UNITS, f"{where} [subject {name}]",  # type: ignore[misc]
                                   with_interval=True)
            for name, block in doc["subjects"].items()}


def active_state_from_json(doc: object, where: str) -> ActiveStateConstants:
    """Table 4 from parsed JSON: ``{"parameters": {q0, rho2, xi_check, s}}``."""
    if not isinstance(doc, dict):
        raise InputError(f"{where}: expected an object with a 'parameters' object")
    return ActiveStateConstants(**_quantities(doc.get("parameters"), _ACTIVE_UNITS, where))  # type: ignore[arg-type]


# ------------------------------------------------------------------------------------------- loaders

def load_subjects(path: str | Path | None = None) -> dict[str, Subject]:
    """Table 1: subjects "1".."4" (or those of the file at ``path``)."""
    doc, where = _read_doc(_TABLE1) if path is None else _read_file(path)
    return subjects_from_json(doc, where)


def load_subject(name: str | int) -> Subject:
    """One subject of Table 1 by its number (1-4)."""
    subjects = load_subjects()
    key = str(name)
    if key not in subjects:
        raise InputError(f"subject {name!r} is not in Table 1 (known: {', '.join(subjects)})")
    return subjects[key]


def load_theta_intervals(path: str | Path | None = None) -> dict[str, Interval]:
    """Table 2: theta1..theta5 of subject 3 with their 95 % confidence intervals."""
    doc, where = _read_doc(_TABLE2) if path is None else _read_file(path)
    return theta_intervals_from_json(doc, where)


def load_theta(path: str | Path | None = None) -> ExcitationTheta:
    """Table 2 point estimates as an ``ExcitationTheta``."""
    table = load_theta_intervals(path)
    return ExcitationTheta(*(table[n].value for n in THETA_NAMES))


def load_trend_table(path: str | Path | None = None) -> dict[str, dict[str, Interval]]:
    """Table 3: per subject, ``{"m": Interval (1/s), "c": Interval (mol/L)}``."""
    doc, where = _read_doc(_TABLE3) if path is None else _read_file(path)
    return trend_table_from_json(doc, where)


def load_active_state_constants(path: str | Path | None = None) -> ActiveStateConstants:
    """Table 4: q0, rho2, xi_check, s."""
    doc, where = _read_doc(_TABLE4) if path is None else _read_file(path)
    return active_state_from_json(doc, where)
