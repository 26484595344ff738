"""Physically based laser-stripe scenes of the rotating-mirror rig (Mitsuba 3).

``scenes.make(name, **params).render(mirror_angle_deg)`` gives a :class:`Frame` with an
8-bit image, its laser-off background, noise-free radiances and per-row ground truth.
Importing this package is cheap: Mitsuba, drjit and colour-science load on first use.

What ``bench`` may use of this package (``tests/test_layout.py`` checks it): the names of ``__all__`` and
the modules of :data:`PUBLIC_MODULES`; every other module is the package's own.
"""

from .backend import LoadedScene
from .colour_camera import jpeg_round_trip
from .distractors import DISTRACTORS
from .frame import PARTS, Frame, Truth
from .laser import profile as laser_profile
from .materials import MATERIALS
from .objects import OBJECTS, SceneObject
from .params import DEFAULTS, MAX_SIZE, RENDER_KEYS
from .passes import render_pass
from .registry import available, make
from .rig import Rig
from .scene import Scene
from .sensor import SensorModel

__all__ = ["available", "make", "Scene", "Frame", "Truth", "Rig", "SensorModel", "MATERIALS", "DEFAULTS", "MAX_SIZE",
           "RENDER_KEYS", "PARTS", "OBJECTS", "SceneObject", "render_pass", "LoadedScene", "laser_profile",
           "jpeg_round_trip", "DISTRACTORS", "PUBLIC_MODULES"]

#: The modules bench may import besides ``__all__``: the renderer's choice (``variant``), the render cache
#: (``cache``), the sample-count tables (``sampling``), the materials, the rig's geometry (``rig``), and what
#: the studies that build their own Mitsuba scenes need (``description``, ``shapes``, ``subsurface``).
PUBLIC_MODULES = ("cache", "description", "materials", "rig", "sampling", "shapes", "subsurface", "variant")
