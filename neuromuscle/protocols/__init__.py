"""Protocols of the seeds: stimulus trains (spike times, ms) and length inputs (LengthTrace, mm)."""

from .lengths import (MOVEMENT_SPEED_MM_S, LengthTrace, as_length_trace, isokinetic_ramp, isometric,
                      random_length, step_shortening)
from .trains import MIN_INTERVAL_MS, constant_rate, random_interval, twitch

__all__ = ["MIN_INTERVAL_MS", "MOVEMENT_SPEED_MM_S", "LengthTrace", "as_length_trace", "constant_rate",
           "isokinetic_ramp", "isometric", "random_interval", "random_length", "step_shortening", "twitch"]
