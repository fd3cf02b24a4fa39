"""Published muscle data sets, each loaded by its own module (not part of the measured-data layer)."""

from .herzog_leonard_2002 import load_herzog_leonard_2002
from .scott_brown_loeb_1996 import ForceLengthVelocityPoints, load_scott_brown_loeb_1996

__all__ = ["ForceLengthVelocityPoints", "load_herzog_leonard_2002", "load_scott_brown_loeb_1996"]
