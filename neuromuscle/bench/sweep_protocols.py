"""The parameter sweep's protocols (``neuromuscle bench sweep``): the seeds' twitch, trains up to 100 Hz, random
length and lengthening ramps, each as spike times (ms), a length (mm) and a duration (ms).

Isometric protocols sit at the draw's own optimum g1 (mm); the moving ones use fixed lengths (random length
-16..0 mm around -8 mm; ramps from -12 to -2 mm during a 40 Hz tetanus), so the draw's optimum moves under them.
``short`` gives the same protocols about half as long (for tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..protocols import LengthTrace, constant_rate, isokinetic_ramp, random_length, twitch

#: Train rates (Hz) of the isometric trains.
TRAIN_RATES_HZ = (10, 40, 100)
#: Lengthening ramp speeds (mm/s).
RAMP_SPEEDS_MM_S = (50, 200)
#: First stimulus (ms) of every protocol but the random length: the unit rests until then.
START_MS = 50.0
#: Durations (ms) of the full and the short form: twitch run, train, train run, random-length run, ramp start,
#: ramp run; and the ramp's lengths (mm).
DURATIONS_MS = {False: (400.0, 300.0, 550.0, 1200.0, 350.0, 800.0), True: (250.0, 150.0, 300.0, 700.0, 200.0, 400.0)}
RAMP_MM = {False: (-12.0, -2.0), True: (-10.0, -4.0)}


@dataclass(frozen=True)
class Protocol:
    """One protocol of a draw: ``name``, stimulus times ``spikes_ms`` (ms), ``length`` (LengthTrace or constant
    mm), ``duration_ms`` (ms) and whether eqs 19-20 (movement compensation) are on."""

    name: str
    spikes_ms: np.ndarray
    length: LengthTrace | float
    duration_ms: float
    movement_compensation: bool = False


def sweep_protocols(g1_mm: float, length_seed: int, movement_compensation: bool,
                    short: bool = False) -> list[Protocol]:
    """The protocols of one draw: a twitch and 10/40/100 Hz trains at the optimum g1_mm (mm), a 20 Hz train under
    ``random_length`` (seed ``length_seed``) and 40 Hz tetani under 50 and 200 mm/s lengthening ramps.  With
    ``movement_compensation`` the moving protocols run with eqs 19-20 on and their names end in ``_mc``."""
    twitch_ms, train_ms, iso_ms, random_ms, ramp_at_ms, ramp_run_ms = DURATIONS_MS[short]
    mc = "_mc" if movement_compensation else ""
    out = [Protocol("twitch", twitch(START_MS), g1_mm, twitch_ms)]
    out += [Protocol(f"train{r}", constant_rate(r, train_ms, start_ms=START_MS), g1_mm, iso_ms)
            for r in TRAIN_RATES_HZ]
    out.append(Protocol(f"random_length{mc}", constant_rate(20, random_ms - 200.0, start_ms=200.0),
                        random_length(random_ms, seed=length_seed), random_ms, movement_compensation))
    out += [Protocol(f"ramp{v}{mc}", constant_rate(40, ramp_run_ms - START_MS, start_ms=START_MS),
                     isokinetic_ramp(*RAMP_MM[short], v, ramp_at_ms, ramp_run_ms), ramp_run_ms, movement_compensation)
            for v in RAMP_SPEEDS_MM_S]
    return out
