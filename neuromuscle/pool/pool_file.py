"""A pool run described as data: the definition file of ``neuromuscle pool`` (TOML or JSON) or its flags.

    [units]                            # the pool (PoolDefinition); defaults: the human pool below
    count = 20
    params = "CT09"                    # base muscle parameter set (built-in name, or a JSON file relative to
                                       # the definition file)
    types = [0.7, 0.2, 0.1]            # S, FR, FF fractions, smallest cells S
    total_p0_N = 600.0                 # the unit P0s sum to this (N) ... or smallest_p0_N
    p0_range = 100.0                   # largest / smallest P0
    max_size = 1.0                     # the largest cell's size index (0..1; the smallest cell's is 0)
    size_spacing = 1.0                 # how sizes spread over the ranks (>= 1; PoolDefinition.size_spacing)
    axon_length_mm = 900.0
    motoneurons = "human"              # the cells' profile: "human" or "default" (motoneuron.PROFILES)
    neuromodulation = 0.6              # PIC strength (0: none; 1: the decerebrate cat's); default: the profile's
    synaptic_noise_uS = 0.0            # each cell's own synaptic noise (uS, its standard deviation at a drive
                                       # of 1 uS; the fixed step and synaptic drives only); default: the profile's
    noise_seed = 0                     # seed of that noise
    set = {g_km_S_per_cm2 = 0.0}       # reduced cells' parameters replaced in every cell, over the profile's
                                       # (motoneuron.MotoneuronParameters' fields; not the neuromodulation)
    muscle = "modules"                 # or "fused", "fused_fixed"
    channels = "fused"                 # or "fused_fixed", "separate"
    [drive]
    kind = "ramp"                      # ramp | rise | synaptic | current | poisson
    peak_uS = 0.7                      # ramp, rise: the synaptic conductance's peak (uS a cell)
    [length]
    mm = -8.0                          # isometric; or kind = "random" with seed (and centre_mm, low_mm, high_mm,
                                       # band_hz: protocols.random_length); or kind = "ramp": a ramp-and-hold
                                       # stretch from mm to to_mm at velocity_mm_s, from start_ms
                                       # (protocols.isokinetic_ramp)
    [run]
    duration_ms = 500.0
    dt_ms = 0.025
    record_dt_ms = 1.0
    method = "fixed"                   # or "cvode"
    engine = "neuron"                  # or "coreneuron"
    secondorder = 0                    # the fixed step's scheme for the membrane: 0 backward Euler, 2 Crank-Nicolson
    [record]                           # optional: Pool.record
    variables = ["mn.v", "act.A", "ca.CaSPT"]
    units = [0, 10]                    # default: every unit
    [motoneuron]                       # optional: reconstructed cells instead of the reduced ones (pool.cells)
    swc = "cell.swc"                   # relative to the definition file
    cm = 1.0                           # uF/cm2; also ra (ohm cm), max_segment_um
    [motoneuron.mechanisms.soma.mn_soma]     # {section group: {mechanism: {parameter: value}}}
    gnaf = 0.6
    [reflex]                           # optional: the stretch-reflex loop (pool.reflex.ReflexDefinition)
    n_ia = 8                           # also n_ii, n_ib, xref_mm (default: length.mm), fusimotor, ia_weight_uS
    cut_dorsal_roots = false           # (one number, or a table S/FR/FF), ia_delay_ms, ii_weight_uS, ...

Drives: ``ramp`` (the recruitment ramp: the common synaptic conductance 0 -> peak_uS over the first half of the
run, held to three quarters, back to 0: ``Drive.recruitment_ramp``), ``rise`` (0 -> peak_uS over the run),
``synaptic`` (times_ms and values_uS, linear between), ``current`` (a common current: times_ms and values_nA, or
0 -> peak_nA over the run), ``poisson`` (rate_hz, weight_uS, seed).  The defaults are the human pool of
networks/human_pool.py: 70/20/10 % S/FR/FF, a 100-fold P0 range summing to 600 N, 900 mm axons, the human
motoneuron profile (``motoneuron.PROFILES``), a recruitment ramp to 0.7 uS.  A missing field takes its default;
an unknown one is an error.  The [reflex] section is optional: without it no afferents are built; with it, each
field missing takes the ReflexDefinition default, and the spindles measure stretch from the length's starting
value unless xref_mm is set.
Units: ms, mm, N, uS, nA, Hz.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from ..errors import InputError
from ..parameters import builtin_sets, load_parameters
from ..protocols import LengthTrace, isokinetic_ramp, random_length
from ..sim import Simulator
from ..sim.simulator import ENGINES
from .cells import CellFactory, reconstructed_cells
from .definition import MUSCLE_MODELS, PoolDefinition
from .drives import Drive
from .experiments import total_force_smallest_p0_N
from .motoneuron import CHANNELS, PROFILES, TYPES, motoneuron_profile, parse_settings
from .reflex import ReflexDefinition

#: Every section of a definition file, its fields and their defaults (None: no default, optional).
FIELDS: dict[str, dict[str, Any]] = {
    "units": {"count": 20, "params": "CT09", "types": [0.7, 0.2, 0.1], "total_p0_N": 600.0, "smallest_p0_N": None,
              "p0_range": 100.0, "max_size": 1.0, "size_spacing": 1.0, "axon_length_mm": 900.0,
              "motoneurons": "human", "neuromodulation": None, "synaptic_noise_uS": None, "noise_seed": 0,
              "set": None, "muscle": "modules", "channels": "fused"},
    "drive": {"kind": "ramp", "peak_uS": 0.7, "peak_nA": 40.0, "times_ms": None, "values_uS": None,
              "values_nA": None, "rate_hz": 400.0, "weight_uS": 0.15, "seed": 0},
    "length": {"kind": "isometric", "mm": -8.0, "seed": 0, "centre_mm": -8.0, "low_mm": -16.0, "high_mm": 0.0,
               "band_hz": 5.0, "to_mm": -4.0, "velocity_mm_s": 30.0, "start_ms": 300.0},
    "run": {"duration_ms": 500.0, "dt_ms": 0.025, "record_dt_ms": 1.0, "method": "fixed", "engine": "neuron",
            "secondorder": 0},
    "record": {"variables": None, "units": None},
    "motoneuron": {"swc": None, "mechanisms": None, "cm": 1.0, "ra": 70.0, "max_segment_um": 100.0},
    "reflex": {**{k: v for k, v in ReflexDefinition().__dict__.items() if k != "ia_weight_uS"},
               "xref_mm": None, "ia_weight_uS": dict(ReflexDefinition().ia_weight_uS)},
}
#: Sections left out of a document that does not give them (their absence means: not built).
OPTIONAL_SECTIONS = ("reflex",)
#: Top-level fields besides the sections.
TOP_FIELDS = {"name": "pool"}
DRIVES = ("ramp", "rise", "synaptic", "current", "poisson")
LENGTHS = ("isometric", "random", "ramp")


@dataclass(frozen=True)
class PoolSetup:
    """Everything a pool run needs, checked: the definition, drive, length, simulator, duration (ms), record
    interval (ms), recordings ((variables, unit indices) or None) and the document it was read from."""

    definition: PoolDefinition
    drive: Drive
    length: LengthTrace | float
    simulator: Simulator
    duration_ms: float
    record_dt_ms: float
    recordings: tuple[tuple[str, ...], tuple[int, ...] | None] | None
    document: dict[str, Any] = field(default_factory=dict)
    cells: CellFactory | None = None
    reflex: ReflexDefinition | None = None


def read_document(path: str | Path) -> dict[str, Any]:
    """The mapping in a TOML (``.toml``) or JSON (``.json``) file; InputError naming the file otherwise."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such definition file")
    text = p.read_text(encoding="utf-8")
    if p.suffix.lower() == ".toml":
        try:
            import tomllib
        except ModuleNotFoundError:  # Python 3.10
            import tomli as tomllib
        try:
            doc = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{p}: not valid TOML ({exc})") from None
    elif p.suffix.lower() == ".json":
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError(f"{p}: not valid JSON ({exc})") from None
    else:
        raise InputError(f"{p}: a definition file ends in .toml or .json")
    if not isinstance(doc, dict):
        raise InputError(f"{p}: the definition must be a mapping of sections, got {type(doc).__name__}")
    return doc


def merge(base: Mapping[str, Any], over: Mapping[str, Any]) -> dict[str, Any]:
    """``base`` with the fields of ``over`` replacing its own, section by section."""
    out = {k: dict(v) if isinstance(v, Mapping) else v for k, v in base.items()}
    for k, v in over.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), dict):
            out[k].update(v)
        else:
            out[k] = v
    return out


def complete(doc: Mapping[str, Any], source: str) -> dict[str, Any]:
    """``doc`` with every missing field at its default; InputError naming ``source`` and any unknown section
    or field."""
    out: dict[str, Any] = dict(TOP_FIELDS)
    for key, value in doc.items():
        if key in TOP_FIELDS:
            out[key] = value
        elif key not in FIELDS:
            raise InputError(f"{source}: unknown section {key!r}; sections: {', '.join([*FIELDS, *TOP_FIELDS])}")
        elif not isinstance(value, Mapping):
            raise InputError(f"{source}: [{key}] must be a section (a mapping of fields), got {value!r}")
    for section, defaults in FIELDS.items():
        if section in OPTIONAL_SECTIONS and section not in doc:
            continue
        given = dict(doc.get(section, {}))
        unknown = sorted(set(given) - set(defaults))
        if unknown:
            raise InputError(f"{source}: [{section}] has no field {', '.join(map(repr, unknown))}; fields: "
                             f"{', '.join(defaults)}")
        out[section] = {**defaults, **given}
    return out


class _Fields:
    """Reads checked values out of a completed document; every error names the source and the field."""

    def __init__(self, doc: Mapping[str, Any], source: str, flagged: Mapping[str, str],
                 base_dir: Path | None = None) -> None:
        self.doc, self.source, self.flagged, self.base_dir = doc, source, flagged, base_dir

    def path(self, name: str) -> str:
        """A file name given by the field: relative to the definition file's folder when the file gave it."""
        text = self.text(name)
        if self.base_dir is None or name in self.flagged or Path(text).is_absolute():
            return text
        return str(self.base_dir / text)

    def where(self, name: str) -> str:
        """The field's name for a message: its flag when a flag set it, else the source and the field."""
        return self.flagged[name] if name in self.flagged else f"{self.source}: {name}"

    def raw(self, name: str) -> Any:
        section, _, key = name.partition(".")
        return self.doc[section][key] if key else self.doc[section]

    def number(self, name: str, check: Callable[[float], bool] = lambda x: True, rule: str = "") -> float:
        v = self.raw(name)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v != v or v in (float("inf"), float("-inf")):
            raise InputError(f"{self.where(name)} must be a finite number, got {v!r}")
        if not check(float(v)):
            raise InputError(f"{self.where(name)} must be {rule}, got {v!r}")
        return float(v)

    def positive(self, name: str) -> float:
        return self.number(name, lambda x: x > 0, "> 0")

    def integer(self, name: str, low: int) -> int:
        v = self.raw(name)
        if isinstance(v, bool) or not isinstance(v, int) or v < low:
            raise InputError(f"{self.where(name)} must be an integer >= {low}, got {v!r}")
        return v

    def choice(self, name: str, options: tuple[str, ...]) -> str:
        v = self.raw(name)
        if v not in options:
            raise InputError(f"{self.where(name)} must be one of {', '.join(options)}, got {v!r}")
        return str(v)

    def numbers(self, name: str, length: int | None = None) -> tuple[float, ...]:
        v = self.raw(name)
        if not isinstance(v, (list, tuple)) or (length is not None and len(v) != length) or \
                any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v):
            size = f"{length} " if length is not None else ""
            raise InputError(f"{self.where(name)} must be a list of {size}numbers, got {v!r}")
        return tuple(float(x) for x in v)

    def text(self, name: str) -> str:
        v = self.raw(name)
        if not isinstance(v, str) or not v:
            raise InputError(f"{self.where(name)} must be a non-empty string, got {v!r}")
        return v


def _definition(f: _Fields) -> PoolDefinition:
    n = f.integer("units.count", 1)
    p0_range = f.number("units.p0_range", lambda x: x >= 1, ">= 1")
    if f.raw("units.smallest_p0_N") is not None:
        smallest = f.positive("units.smallest_p0_N")
    else:
        smallest = total_force_smallest_p0_N(n, f.positive("units.total_p0_N"), p0_range)
    types = f.numbers("units.types", 3)
    if min(types) < 0 or abs(sum(types) - 1.0) > 1e-9:
        raise InputError(f"{f.where('units.types')} (S, FR, FF fractions) must be >= 0 and sum to 1, got "
                         f"{list(types)}")
    params = f.text("units.params")
    try:
        muscle = load_parameters(params if params in builtin_sets() else f.path("units.params"))
    except InputError as exc:
        raise InputError(f"{f.where('units.params')}: {exc}") from None
    fields = {"max_size": f.number("units.max_size", lambda x: 0.0 <= x <= 1.0, "in [0, 1] (a size index)"),
              "size_spacing": f.number("units.size_spacing", lambda x: x >= 1.0,
                                       ">= 1 (1: sizes uniform in rank)"),
              "axon_length_mm": f.positive("units.axon_length_mm"),
              **motoneuron_profile(f.choice("units.motoneurons", tuple(PROFILES))).pool_options(),
              "muscle_model": f.choice("units.muscle", MUSCLE_MODELS),
              "motoneuron_channels": f.choice("units.channels", CHANNELS), "name": f.text("name")}
    if f.raw("units.neuromodulation") is not None:
        fields["neuromodulation"] = f.number("units.neuromodulation", lambda x: x >= 0, ">= 0")
    if f.raw("units.synaptic_noise_uS") is not None:
        fields["synaptic_noise_uS"] = f.number("units.synaptic_noise_uS", lambda x: x >= 0, ">= 0")
    fields["noise_seed"] = f.integer("units.noise_seed", 0)
    if f.raw("units.set") is not None:
        fields["motoneuron_overrides"] = {**fields["motoneuron_overrides"], **_settings(f)}
    try:
        return PoolDefinition(n, muscle, smallest_p0_N=smallest, p0_range=p0_range, type_fractions=types, **fields)
    except InputError as exc:
        raise InputError(f"{f.source}: [units]: {exc}") from None


def _settings(f: _Fields) -> dict[str, float]:
    """``units.set``: a table of reduced-cell parameters and their numbers (``motoneuron.parse_settings``'
    rules: known fields, numbers, not the neuromodulation, which has its own field)."""
    table = f.raw("units.set")
    if not isinstance(table, Mapping):
        raise InputError(f"{f.where('units.set')} must be a table of motoneuron parameters and numbers, e.g. "
                         f"{{g_km_S_per_cm2 = 0.0}}, got {table!r}")
    if any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in table.values()):
        raise InputError(f"{f.where('units.set')}: every value must be a number, got {dict(table)!r}")
    try:
        return parse_settings(f"{k}={v!r}" for k, v in table.items())
    except InputError as exc:
        raise InputError(f"{f.where('units.set')}: {exc}") from None


def _drive(f: _Fields, duration_ms: float) -> Drive:
    kind = f.choice("drive.kind", DRIVES)
    if kind == "ramp":
        return Drive.recruitment_ramp(f.positive("drive.peak_uS"), duration_ms)
    if kind == "rise":
        return Drive.rise("synaptic", f.positive("drive.peak_uS"), duration_ms)
    if kind == "poisson":
        return Drive("poisson", rate_hz=f.positive("drive.rate_hz"),
                     weight_uS=f.number("drive.weight_uS", lambda x: x >= 0, ">= 0"),
                     seed=f.integer("drive.seed", 0))
    values = "drive.values_uS" if kind == "synaptic" else "drive.values_nA"
    if kind == "current" and f.raw("drive.times_ms") is None and f.raw(values) is None:
        return Drive.rise("current", f.positive("drive.peak_nA"), duration_ms)
    for name in ("drive.times_ms", values):
        if f.raw(name) is None:
            raise InputError(f"{f.where(name)}: the {kind} drive needs drive.times_ms and {values}")
    times = f.numbers("drive.times_ms")
    if times and times[-1] > duration_ms:
        raise InputError(f"{f.where('drive.times_ms')} reach {times[-1]:g} ms, beyond the run "
                         f"(run.duration_ms = {duration_ms:g})")
    try:
        return Drive(kind, times, f.numbers(values))
    except InputError as exc:
        raise InputError(f"{f.source}: [drive]: {exc}") from None


def _length(f: _Fields, duration_ms: float) -> LengthTrace | float:
    kind = f.choice("length.kind", LENGTHS)
    if kind == "isometric":
        return f.number("length.mm")
    if kind == "ramp":
        try:
            return isokinetic_ramp(f.number("length.mm"), f.number("length.to_mm"), f.positive("length.velocity_mm_s"),
                                   f.number("length.start_ms", lambda x: x >= 0, ">= 0"), duration_ms)
        except InputError as exc:
            raise InputError(f"{f.source}: [length]: {exc}") from None
    try:
        return random_length(duration_ms, seed=f.integer("length.seed", 0), centre_mm=f.number("length.centre_mm"),
                             low_mm=f.number("length.low_mm"), high_mm=f.number("length.high_mm"),
                             band_hz=f.positive("length.band_hz"))
    except InputError as exc:
        raise InputError(f"{f.source}: [length]: {exc}") from None


def _recordings(f: _Fields, n_units: int) -> tuple[tuple[str, ...], tuple[int, ...] | None] | None:
    names = f.raw("record.variables")
    if names is None:
        if f.raw("record.units") is not None:
            raise InputError(f"{f.where('record.units')} is given without record.variables")
        return None
    if not isinstance(names, (list, tuple)) or not names or not all(isinstance(x, str) and x for x in names):
        raise InputError(f"{f.where('record.variables')} must be a non-empty list of names such as 'mn.v', "
                         f"'act.A', got {names!r}")
    if len(set(names)) != len(names):
        raise InputError(f"{f.where('record.variables')} repeat: {list(names)}")
    units = f.raw("record.units")
    if units is None:
        return tuple(names), None
    if not isinstance(units, (list, tuple)) or not units or len(set(units)) != len(units) or \
            any(isinstance(u, bool) or not isinstance(u, int) or not 0 <= u < n_units for u in units):
        raise InputError(f"{f.where('record.units')} must be distinct unit indices 0..{n_units - 1}, got {units!r}")
    return tuple(names), tuple(units)


def _cells(f: _Fields) -> CellFactory | None:
    if f.raw("motoneuron.swc") is None:
        if f.raw("motoneuron.mechanisms") is not None:
            raise InputError(f"{f.where('motoneuron.mechanisms')} is given without motoneuron.swc")
        return None
    if f.raw("units.set") is not None:
        raise InputError(f"{f.where('units.set')} sets the reduced cells' parameters; reconstructed cells "
                         "(motoneuron.swc) take theirs from [motoneuron.mechanisms]")
    mechanisms = f.raw("motoneuron.mechanisms") or {}
    if not isinstance(mechanisms, Mapping) or not all(
            isinstance(m, Mapping) and all(isinstance(v, Mapping) for v in m.values()) for m in mechanisms.values()):
        raise InputError(f"{f.where('motoneuron.mechanisms')} must map section groups to {{mechanism: {{parameter: "
                         f"value}}}}, got {mechanisms!r}")
    options = {"cm": f.positive("motoneuron.cm"), "ra": f.positive("motoneuron.ra"),
               "max_segment_um": f.positive("motoneuron.max_segment_um")}
    try:
        return reconstructed_cells(f.path("motoneuron.swc"), mechanisms, **options)
    except InputError as exc:
        raise InputError(f"{f.source}: [motoneuron]: {exc}") from None


def _reflex(f: _Fields) -> ReflexDefinition | None:
    if "reflex" not in f.doc:
        return None
    fields: dict[str, Any] = {}
    for name in ("n_ia", "n_ii", "n_ib"):
        fields[name] = f.integer(f"reflex.{name}", 0)
    if f.raw("reflex.xref_mm") is None:
        fields["xref_mm"] = f.number("length.mm")
    else:
        fields["xref_mm"] = f.number("reflex.xref_mm")
    fields["fusimotor"] = f.number("reflex.fusimotor", lambda x: x >= 0, ">= 0 (% of maximal activation)")
    weights = f.raw("reflex.ia_weight_uS")
    if isinstance(weights, Mapping):
        unknown = sorted(set(weights) - set(TYPES))
        if unknown or set(weights) != set(TYPES):
            raise InputError(f"{f.where('reflex.ia_weight_uS')} needs one weight (uS) for each motoneuron type "
                             f"{', '.join(TYPES)}, got {dict(weights)!r}")
        fields["ia_weight_uS"] = {t: _weight(f, t, weights[t]) for t in TYPES}
    else:
        w = f.number("reflex.ia_weight_uS", lambda x: x >= 0, ">= 0 (uS), or a table of S, FR, FF weights")
        fields["ia_weight_uS"] = {t: w for t in TYPES}
    for name in ("ii_weight_uS", "ib_weight_uS", "interneuron_weight"):
        fields[name] = f.number(f"reflex.{name}", lambda x: x >= 0, ">= 0")
    for name in ("ia_delay_ms", "ia_tau_ms", "ii_delay_ms", "ib_delay_ms", "ib_tau_ms", "interneuron_tau_ms"):
        fields[name] = f.positive(f"reflex.{name}")
    cut = f.raw("reflex.cut_dorsal_roots")
    if not isinstance(cut, bool):
        raise InputError(f"{f.where('reflex.cut_dorsal_roots')} must be true or false, got {cut!r}")
    fields["cut_dorsal_roots"] = cut
    try:
        return ReflexDefinition(**fields)
    except InputError as exc:
        raise InputError(f"{f.source}: [reflex]: {exc}") from None


def _weight(f: _Fields, unit_type: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0 or value == float("inf"):
        raise InputError(f"{f.where('reflex.ia_weight_uS')}.{unit_type} must be a finite number >= 0 (uS), got "
                         f"{value!r}")
    return float(value)


def pool_setup(doc: Mapping[str, Any], source: str, flagged: Mapping[str, str] | None = None,
               base_dir: str | Path | None = None) -> PoolSetup:
    """Check ``doc`` (the definition file's mapping, flags merged in) and build the run's pieces; every
    InputError names ``source`` (the file, or "command line") and the field, or the flag (``flagged``: field ->
    flag) that set it.  A parameter file named by the document is read relative to ``base_dir`` (the
    definition file's folder).  Nothing is built in NEURON."""
    full = complete(doc, source)
    f = _Fields(full, source, flagged or {}, None if base_dir is None else Path(base_dir))
    duration = f.positive("run.duration_ms")
    dt = f.positive("run.dt_ms")
    record_dt = f.positive("run.record_dt_ms")
    if record_dt < dt:
        raise InputError(f"{f.where('run.record_dt_ms')} = {record_dt:g} ms is shorter than run.dt_ms = {dt:g} ms")
    method = f.choice("run.method", ("fixed", "cvode"))
    engine = f.choice("run.engine", ENGINES)
    secondorder = f.integer("run.secondorder", 0)
    if secondorder > 2 or (secondorder and method != "fixed"):
        raise InputError(f"{f.where('run.secondorder')} must be 0, 1 or 2 and 0 under CVODE (NEURON's fixed-step "
                         f"scheme), got {secondorder}")
    definition = _definition(f)
    if definition.synaptic_noise_uS > 0.0 and method != "fixed":
        raise InputError(f"{f.where('run.method')} = {method!r}: the motoneurons' synaptic noise (units."
                         f"synaptic_noise_uS = {definition.synaptic_noise_uS:g} uS) is drawn at fixed intervals of the "
                         "fixed step; set units.synaptic_noise_uS = 0 for CVODE")
    if definition.synaptic_noise_uS > 0.0 and f.raw("drive.kind") in ("current", "poisson"):
        raise InputError(f"{f.where('units.synaptic_noise_uS')} = {definition.synaptic_noise_uS:g} uS rides on the "
                         f"common synaptic drive (drive.kind ramp, rise or synaptic), not on {f.raw('drive.kind')!r}")
    try:
        definition.units()
    except InputError as exc:
        lo = definition.smallest_p0_N
        raise InputError(f"{source}: [units]: {exc} (the unit P0s run from {lo:.4g} to {lo * definition.p0_range:.4g} "
                         "N: set units.total_p0_N (--total-p0-n), units.smallest_p0_N (--smallest-p0-n) or "
                         "units.p0_range (--p0-range))") from None
    try:
        sim = Simulator(method=method, dt_ms=dt, v_init_mV=-70.0, max_wall_s=None, engine=engine,
                        secondorder=secondorder,
                        label=f"pool {definition.name!r} of {definition.n_units} units")
    except InputError as exc:
        raise InputError(f"{source}: [run]: {exc}") from None
    return PoolSetup(definition, _drive(f, duration), _length(f, duration), sim, duration, record_dt,
                     _recordings(f, definition.n_units), full, _cells(f), _reflex(f))
