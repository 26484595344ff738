"""Physically based laser-stripe scenes of the rotating-mirror rig (Mitsuba 3).

``scenes.make(name, **params).render(mirror_angle_deg)`` gives a :class:`Frame` with an
8-bit image, its laser-off background, noise-free radiances and per-row ground truth.
Importing this package is cheap: Mitsuba, drjit and colour-science load on first use.
"""

from .frame import Frame, Truth
from .materials import MATERIALS
from .params import DEFAULTS
from .registry import available, make
from .rig import Rig
from .scene import Scene
from .sensor import SensorModel

__all__ = ["available", "make", "Scene", "Frame", "Truth", "Rig", "SensorModel", "MATERIALS", "DEFAULTS"]
