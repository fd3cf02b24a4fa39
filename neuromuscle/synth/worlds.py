"""Worlds: the kinds of preparation a user meets, as settings of the synthetic-data generator.

A diagnosis tuned on one generator is judged on its own assumptions.  A world fixes what the generator's base
model is and what the file offers, so that a method is developed on some worlds and measured on others:

* the base parameter set (CT09 or CT95 of Kim, Sandercock & Heckman 2015), each parameter moved per preparation
  by its own log-normal factor;
* whether the data carry the paper's own length dependence of activation (eq 18) and its movement terms (eqs
  19-20).  The diagnosis's baseline has neither, so a file with eq 18 carries ``length_dependent_activation``
  (``background_causes``) beside any hidden effect, and one with eqs 19-20 may show ``movement_induced_depression``
  and ``lengthening_below_optimum``;
* the protocol set and the protocols dropped from it, the sampling rate, and, for digitised data, a few uneven
  samples per trial;
* whether the file carries force-length and force-velocity points (the static calibration data of the paper);
* the range of the transducer noise (% of P0).

``WORLDS`` names the worlds of the benchmark; ``world(name)`` looks one up.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from ..errors import InputError


@dataclass(frozen=True)
class World:
    """Settings of the synthetic-data generator (module docstring).  noise_pct: (low, high) % of P0 that a
    benchmark draws from; samples_per_trial: None (the protocol's clock) or 10-200 uneven samples per trial."""

    name: str
    base: str = "CT09"
    length_dependence: bool = False
    movement_terms: bool = False
    protocols: str = "extended"
    drop: tuple[str, ...] = ()
    sample_rate_hz: float = 1000.0
    samples_per_trial: int | None = None
    static_points: bool = True
    noise_pct: tuple[float, float] = (1.0, 2.0)
    description: str = field(default="", compare=False)

    @property
    def background_causes(self) -> tuple[str, ...]:
        """Canonical causes every file of this world carries, whatever its hidden effect (eq 18 in the data)."""
        return ("length_dependent_activation",) if self.length_dependence else ()

    @property
    def allowed_causes(self) -> tuple[str, ...]:
        """Causes a diagnosis may name in this world without being wrong, beyond the background and the hidden
        ones: the movement terms' two causes when the data carry eqs 19-20."""
        return ("movement_induced_depression", "lengthening_below_optimum") if self.movement_terms else ()

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "base": self.base, "length_dependence": self.length_dependence,
                "movement_terms": self.movement_terms, "protocols": self.protocols, "drop": list(self.drop),
                "sample_rate_hz": self.sample_rate_hz, "samples_per_trial": self.samples_per_trial,
                "static_points": self.static_points, "noise_pct": list(self.noise_pct)}

    def with_settings(self, **changes: Any) -> World:
        """This world with some settings changed (a new name is the caller's to give)."""
        return replace(self, **changes)


#: The benchmark's worlds.  The first four are the measured ones (eq 18 on/off x the extended and the reduced
#: protocol set); the others vary the base set, the movement terms, the sampling and the design.
WORLDS: dict[str, World] = {w.name: w for w in (
    World("B", description="the baseline's own model family, extended protocol set, static points"),
    World("A", length_dependence=True, description="the paper's full model (eq 18 on), extended protocol set"),
    World("B-reduced", protocols="reduced", static_points=False,
          description="baseline model family, the reduced in situ design, no static points or step"),
    World("A-reduced", length_dependence=True, protocols="reduced", static_points=False,
          description="eq 18 on, the reduced in situ design, no static points or step"),
    World("CT95", base="CT95", length_dependence=True, protocols="reduced", static_points=False,
          noise_pct=(0.5, 3.0), description="CT95 base set with eq 18, reduced design, 0.5-3 % noise"),
    World("A-movement", length_dependence=True, movement_terms=True, protocols="reduced", static_points=False,
          description="eqs 18-20 on (the paper's full model under movement), reduced design"),
    World("B-5kHz-short", protocols="standard", drop=("long_train", "potentiation"), sample_rate_hz=5000.0,
          static_points=False, description="standard set without long trains and potentiation, sampled at 5 kHz"),
    World("ramps", protocols="ramps", static_points=False, samples_per_trial=25, noise_pct=(1.0, 3.0),
          description="ramps to one final length only, 25 uneven samples a trial (digitised figures)"),
)}


def world(name: str | World) -> World:
    """The world called ``name`` (``WORLDS``), or ``name`` itself when it is a World; InputError otherwise."""
    if isinstance(name, World):
        return name
    if name not in WORLDS:
        raise InputError(f"unknown world {name!r}; known: {', '.join(WORLDS)}")
    return WORLDS[name]
