"""A pool's definition: N motor units in recruitment order, each a motoneuron (size index, type) and its muscle
unit (P0, twitch speed, extensions).  Pure data, checked on construction; nothing is built in NEURON here."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..errors import InputError
from ..parameters import ParameterSet
from ..validate import finite_number, nonnegative_number, positive_number
from .motoneuron import (CHANNELS, FUSED_CHANNELS, HUMAN_NEUROMODULATION, TYPES, MotoneuronParameters,
                         motoneuron_parameters, unit_type_of)
from .units import TWITCH_SPEED, p0_spread_N, unit_muscle_parameters


def size_index(rank: float, spacing: float) -> float:
    """The size index (0..1) of the unit at ``rank`` (0..1) in the pool.  ``spacing`` 1: uniform in rank, so the
    size-scaled properties (rheobase among them) grow geometrically with rank (the exponential spread of
    Fuglevand, Winter & Patla 1993); ``spacing`` K > 1: log(1 + (K - 1) rank) / log K, so a property that grows
    K-fold over the size range grows linearly with rank (fewer units crowd the low end)."""
    if spacing == 1.0:
        return rank
    return float(np.log1p((spacing - 1.0) * rank) / np.log(spacing))


#: Muscle models a pool can build: the three Kim mechanisms, or Modules 1-3 fused in one (KimUnit).
#: How each unit's muscle is modelled: the three Kim mechanisms, KimUnit, or KimUnitFixed (the fixed step only).
MUSCLE_MODELS = ("modules", "fused", "fused_fixed")

#: The muscle models with one mechanism per unit (they take muscle_substeps).
FUSED_MUSCLE_MODELS = ("fused", "fused_fixed")


@dataclass(frozen=True)
class UnitSpec:
    """One motor unit: index (= gid), type, its motoneuron's and its muscle unit's parameters, extensions."""

    index: int
    unit_type: str
    motoneuron: MotoneuronParameters
    muscle: ParameterSet
    speed: float = 1.0
    extensions: Mapping[str, Mapping[str, float]] = field(default_factory=dict)

    def row(self) -> dict[str, Any]:
        """The unit's summary (for tables and HDF5)."""
        return {"index": self.index, "type": self.unit_type, "size": self.motoneuron.size,
                "P0_N": self.muscle["P0"], "axon_delay_ms": self.motoneuron.axon_delay_ms,
                "twitch_speed": self.speed}


@dataclass(frozen=True)
class PoolDefinition:
    """N units in recruitment order (size index from 0 to ``max_size``), types by ``type_fractions`` (S, FR, FF),
    P0 from ``smallest_p0_N`` over ``p0_range`` (largest / smallest), twitch speed by type (``twitch_speed``),
    axon length ``axon_length_mm`` (mm), PIC strength ``neuromodulation`` (0: none, as under anaesthesia; 1: the
    decerebrate cat's; see ``motoneuron``).  ``extensions``: {unit index: {extension: {param: value}}} or one
    mapping for every unit (key "all").  ``motoneuron_overrides``: fields replaced in every motoneuron;
    ``motoneuron_scales``: factors on its size-dependent parameters (``motoneuron_parameters``).
    ``muscle_model``: "modules" (KimCa, KimAct, KimForce), "fused" (KimUnit: the same numbers, faster) or
    "fused_fixed" (KimUnitFixed: KimUnit's numbers, faster still, NEURON's fixed step and CoreNEURON only; all
    take extensions); ``muscle_substeps`` k (fused models only): the muscle advances every k membrane steps;
    ``pic_substeps`` k (fused channels only): the dendritic PIC's gate (time constant 60 ms) advances every k
    membrane steps, its current still every step.
    ``size_spacing``: how sizes spread over the ranks (``size_index``).  ``p0_N``: every unit's P0 (N, recruitment
    order) instead of the exponential spread.
    ``synaptic_noise_uS``: each motoneuron's own synaptic input, a conductance (reversal 0 mV) fluctuating
    around the common synaptic drive g with standard deviation ``synaptic_noise_uS`` sqrt(g / 1 uS) (uS; 0: none)
    and correlation time ``synaptic_noise_tau_ms`` (ms), independent between cells, drawn from ``noise_seed``
    (mod/MnNoise.mod; the fixed step and the synaptic drive only): what makes discharges irregular as recorded ones
    are.
    ``motoneuron_channels``: "fused" (mn_soma + mn_pic, tabulated rates), "fused_fixed" (mn_soma_fixed +
    mn_pic_fixed: the same, cheaper, the fixed step only) or "separate" (one mechanism per channel, the reference);
    see ``motoneuron.CHANNELS``."""

    n_units: int
    muscle: ParameterSet
    smallest_p0_N: float = 0.05
    p0_range: float = 100.0
    type_fractions: tuple[float, float, float] = (0.25, 0.25, 0.5)
    twitch_speed: Mapping[str, float] = field(default_factory=lambda: dict(TWITCH_SPEED))
    max_size: float = 1.0
    axon_length_mm: float = 600.0
    extensions: Mapping[Any, Mapping[str, Mapping[str, float]]] = field(default_factory=dict)
    motoneuron_overrides: Mapping[str, Any] = field(default_factory=dict)
    name: str = "pool"
    muscle_model: str = "modules"
    muscle_substeps: int = 1
    motoneuron_channels: str = "fused"
    pic_substeps: int = 1
    neuromodulation: float = HUMAN_NEUROMODULATION
    size_spacing: float = 1.0
    p0_N: tuple[float, ...] | None = None
    motoneuron_scales: Mapping[str, float] = field(default_factory=dict)
    synaptic_noise_uS: float = 0.0
    synaptic_noise_tau_ms: float = 5.0
    noise_seed: int = 0

    def __post_init__(self) -> None:
        where = f"pool {self.name!r}"
        if isinstance(self.n_units, bool) or not isinstance(self.n_units, (int, np.integer)) or self.n_units < 1:
            raise InputError(f"{where}: n_units must be an integer >= 1, got {self.n_units!r}")
        if not isinstance(self.muscle, ParameterSet):
            raise InputError(f"{where}: muscle must be a ParameterSet (load_parameters), got {type(self.muscle)}")
        size = finite_number(f"{where}: max_size", self.max_size)
        if not 0.0 <= size <= 1.0:
            raise InputError(f"{where}: max_size must lie in [0, 1], got {size}")
        positive_number(f"{where}: axon_length_mm", self.axon_length_mm)
        nonnegative_number(f"{where}: neuromodulation", self.neuromodulation)
        nonnegative_number(f"{where}: synaptic_noise_uS", self.synaptic_noise_uS)
        positive_number(f"{where}: synaptic_noise_tau_ms", self.synaptic_noise_tau_ms)
        seed = self.noise_seed
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**32:
            raise InputError(f"{where}: noise_seed must be an integer in [0, 2**32) (a Random123 id), got {seed!r}")
        object.__setattr__(self, "noise_seed", int(seed))
        if positive_number(f"{where}: size_spacing", self.size_spacing) < 1.0:
            raise InputError(f"{where}: size_spacing must be >= 1 (1: sizes uniform in rank), got {self.size_spacing}")
        if set(self.twitch_speed) != set(TYPES):
            raise InputError(f"{where}: twitch_speed must give {', '.join(TYPES)}, got {sorted(self.twitch_speed)}")
        for t, k in self.twitch_speed.items():
            positive_number(f"{where}: twitch_speed[{t}]", k)
        bad = [k for k in self.extensions if k != "all" and not (isinstance(k, (int, np.integer))
                                                                and 0 <= k < self.n_units)]
        if bad:
            raise InputError(f"{where}: extensions keys must be unit indices 0..{self.n_units - 1} or 'all', got {bad}")
        if self.muscle_model not in MUSCLE_MODELS:
            raise InputError(f"{where}: muscle_model must be one of {', '.join(MUSCLE_MODELS)}, got "
                             f"{self.muscle_model!r}")
        if self.motoneuron_channels not in CHANNELS:
            raise InputError(f"{where}: motoneuron_channels must be one of {', '.join(CHANNELS)}, got "
                             f"{self.motoneuron_channels!r}")
        for name, k, fused, needs in (
                ("muscle_substeps", self.muscle_substeps, self.muscle_model in FUSED_MUSCLE_MODELS,
                 "muscle_model='fused' or 'fused_fixed' (the three mechanisms advance every step)"),
                ("pic_substeps", self.pic_substeps, self.motoneuron_channels in FUSED_CHANNELS,
                 "motoneuron_channels='fused' or 'fused_fixed' (mn_cal advances every step)")):
            if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
                raise InputError(f"{where}: {name} must be an integer >= 1, got {k!r}")
            if k > 1 and not fused:
                raise InputError(f"{where}: {name} = {k} needs {needs}")
        unit_type_of(0.0, tuple(self.type_fractions))  # checks the fractions
        p0_spread_N(int(self.n_units), self.smallest_p0_N, self.p0_range)
        motoneuron_parameters(0.0, scales=dict(self.motoneuron_scales))  # checks the scales
        if self.p0_N is not None:
            p0 = tuple(positive_number(f"{where}: p0_N[{i}]", x) for i, x in enumerate(self.p0_N))
            if len(p0) != self.n_units:
                raise InputError(f"{where}: p0_N gives {len(p0)} forces for {self.n_units} units")
            object.__setattr__(self, "p0_N", p0)
        object.__setattr__(self, "_units", None)

    def units(self) -> list[UnitSpec]:
        """Every unit's specification, in recruitment order (cached)."""
        if self._units is None:  # type: ignore[has-type]
            n = int(self.n_units)
            p0 = (np.asarray(self.p0_N) if self.p0_N is not None
                  else p0_spread_N(n, self.smallest_p0_N, self.p0_range))
            out = []
            for i in range(n):
                x = self.max_size * size_index(i / (n - 1) if n > 1 else 0.0, self.size_spacing)
                t = unit_type_of(i / n if n > 1 else 0.0, tuple(self.type_fractions))
                fields = {"axon_length_mm": self.axon_length_mm, "neuromodulation": self.neuromodulation,
                          **dict(self.motoneuron_overrides)}
                mn = motoneuron_parameters(x, unit_type=t, scales=dict(self.motoneuron_scales), **fields)
                muscle = unit_muscle_parameters(self.muscle, float(p0[i]), self.twitch_speed[t],
                                                name=f"{self.muscle.name}:{self.name}[{i}]")
                ext = dict(self.extensions.get("all", {}))
                ext.update(self.extensions.get(i, {}))
                out.append(UnitSpec(i, t, mn, muscle, self.twitch_speed[t], ext))
            object.__setattr__(self, "_units", out)
        return list(self._units)  # type: ignore[arg-type]
