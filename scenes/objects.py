"""The object catalogue: what stands where in front of the backdrop.

Each object is centred on the laser's direction at mirror angle 0 (azimuth
``phi = -ζ``), so angle 0 puts the stripe across its middle, at the distance
``R`` from the mirror axis given below; a grey wall 55 cm from the axis, facing
it, is the backdrop (it stays within 20-60 cm over every default scan).

=========  ===============================================================  ======
name       shape                                                            R (cm)
=========  ===============================================================  ======
cone       right circular cone, base radius 4 cm, height 8.6 cm, apex up    38
hand       palm + four fingers + thumb, ~16 x 8.6 cm, fingers to the right  36
plane      flat 14 x 12 cm board, turned 25° about Z, leaning back 20°      36
sphere     sphere of radius 4.3 cm                                          38
=========  ===============================================================  ======

Heights stay within ±4.3 cm (the camera's vertical field at 45-50 cm is about
±4.5 cm), except the plane, which overfills it on purpose (a stripe over the
full image height).  Object-local frames are those of :mod:`scenes.shapes`.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Tuple

import numpy as np

from . import rig as _rig
from . import shapes

__all__ = ["OBJECTS", "SceneObject", "build", "BACKDROP_DISTANCE_CM"]

OBJECTS = ("cone", "hand", "plane", "sphere")
BACKDROP_DISTANCE_CM = 55.0
BACKDROP_SIZE_CM = (90.0, 40.0)
_ANGLE_MARGIN_DEG = 0.5  # mirror-angle margin beyond the object's edges


@dataclasses.dataclass(frozen=True)
class SceneObject:
    """An object and its backdrop in world coordinates (cm).

    Attributes
    ----------
    name : str
    mesh : shapes.Mesh
        The object, with planar texture coordinates.
    backdrop : shapes.Mesh
        The wall behind it.
    phi_range_deg : tuple of float
        Azimuth range (clockwise from +Y) the object covers, seen from the mirror axis.
    """

    name: str
    mesh: shapes.Mesh
    backdrop: shapes.Mesh
    phi_range_deg: Tuple[float, float]

    def default_angles(self, zeta_deg: float, n_angles: int) -> np.ndarray:
        """``n_angles`` mirror angles (deg) sweeping the laser over the whole object plus a margin."""
        lo, hi = self.phi_range_deg
        th_lo = 0.5 * (lo + zeta_deg) - _ANGLE_MARGIN_DEG
        th_hi = 0.5 * (hi + zeta_deg) + _ANGLE_MARGIN_DEG
        return np.linspace(th_lo, th_hi, int(n_angles))


def _local(name: str) -> Tuple[shapes.Mesh, float]:
    """Object-local mesh and its distance from the mirror axis (cm)."""
    if name == "cone":
        return shapes.cone(4.0, 8.6), 38.0
    if name == "hand":
        return shapes.hand(), 36.0
    if name == "plane":
        m = shapes.rectangle(14.0, 12.0).transformed(_rig.rotation_z(25.0) @ _rig.rotation_x(-20.0))
        return m, 36.0
    if name == "sphere":
        return shapes.uv_sphere(4.3), 38.0
    raise KeyError(f"unknown scene {name!r}; valid: {', '.join(OBJECTS)}")


def _placement(distance_cm: float, zeta_deg: float) -> np.ndarray:
    """Object-local -> world: local +Y along the laser direction at mirror angle 0."""
    return (_rig.translation(_rig.cylindrical_to_cartesian(distance_cm, -zeta_deg, 0.0))
            @ _rig.rotation_z(-zeta_deg))


@functools.lru_cache(maxsize=32)
def build(name: str, zeta_deg: float) -> SceneObject:
    """The object ``name`` and its backdrop, placed for a rig with laser angle ``zeta_deg``."""
    local, distance = _local(name)
    local = shapes.planar_uv(local)
    mesh = local.transformed(_placement(distance, zeta_deg))
    backdrop = shapes.rectangle(*BACKDROP_SIZE_CM).transformed(_placement(BACKDROP_DISTANCE_CM, zeta_deg))
    v = mesh.vertices_cm
    phi = np.degrees(np.arctan2(v[:, 0], v[:, 1]))
    return SceneObject(name, mesh, backdrop, (float(phi.min()), float(phi.max())))
