"""The object catalogue: what stands where, in front of what, on what.

Each object is centred on the laser's direction at mirror angle 0 (azimuth
``phi = -ζ``), so angle 0 puts the stripe across its middle, at the distance
``R`` from the mirror axis given below.

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

Background and support (scene parameters, see :mod:`scenes.params`):

* ``background="wall"``: a grey wall facing the mirror axis, perpendicular to the
  laser's direction at angle 0, ``background_distance_cm`` from the axis (default
  :data:`BACKDROP_DISTANCE_CM` = 55 cm, *inside* the imaged range, so its stripe is in
  every frame); 90 x 40 cm at 55 cm, scaled with the distance so it fills the same
  part of the view.  :func:`out_of_range_distance_cm` gives a distance the rig cannot
  image (about 75.9 cm).  ``background="none"``: nothing behind the object.
* ``support="table"``: a horizontal rectangle whose top is at the object's lowest
  point, running from the mirror axis's line to the wall (or, with no wall, to
  :func:`out_of_range_distance_cm`), wide enough to fill the camera's view below the
  object over any scan of up to ±20° of mirror angle.  The laser sheet lights it, so
  the stripe runs on from the object's foot down to the bottom of the image.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Optional, Tuple

import numpy as np

from . import rig as _rig
from . import shapes

__all__ = ["OBJECTS", "BACKGROUNDS", "SUPPORTS", "SceneObject", "build", "BACKDROP_DISTANCE_CM",
           "OUT_OF_RANGE_MARGIN_CM", "out_of_range_distance_cm"]

OBJECTS = ("cone", "hand", "plane", "sphere")
BACKGROUNDS = ("wall", "none")
SUPPORTS = ("none", "table")
BACKDROP_DISTANCE_CM = 55.0
BACKDROP_SIZE_CM = (90.0, 40.0)  # at BACKDROP_DISTANCE_CM; scaled with the distance
OUT_OF_RANGE_MARGIN_CM = 10.0
TABLE_MAX_MIRROR_ANGLE_DEG = 20.0  # the table fills the view for |mirror angle| up to this
_ANGLE_MARGIN_DEG = 0.5  # mirror-angle margin beyond the object's edges


def out_of_range_distance_cm(rig: Optional[_rig.Rig] = None, margin_cm: float = OUT_OF_RANGE_MARGIN_CM) -> float:
    """A distance from the mirror axis (cm) that the rig cannot image: ``R_max`` + ``margin_cm``.

    ``R_max`` is eq. (3) of the paper at the image's outer edge (column -0.5, see
    :meth:`scenes.Rig.imaged_range_cm`); a wall facing the axis at this distance is at least
    this far along every azimuth, so its stripe lies left of the image at every mirror angle.
    The default 10 cm margin keeps the stripe about 40 columns (at 512 px) clear of the edge,
    far more than its width.  Derived from the rig's f, d_m, δ_0 and ζ only.

    Parameters
    ----------
    rig : Rig, optional
        Default: ``Rig()`` (f = 25 mm, d_m = 15 cm, δ_0 = 8 cm, ζ = 14.12°); the pixel count does
        not matter (the field of view is fixed).
    margin_cm : float
        Added to ``R_max``, >= 0.

    Returns
    -------
    float
        cm.

    Examples
    --------
    >>> round(out_of_range_distance_cm(), 1)
    75.9
    """
    if not (isinstance(margin_cm, (int, float)) and math.isfinite(margin_cm) and margin_cm >= 0):
        raise ValueError(f"`margin_cm` must be a finite number >= 0, got {margin_cm!r}")
    rig = _rig.Rig() if rig is None else rig
    return rig.imaged_range_cm(edges=True)[1] + float(margin_cm)


@dataclasses.dataclass(frozen=True)
class SceneObject:
    """An object, its background and its support in world coordinates (cm).

    Attributes
    ----------
    name : str
    mesh : shapes.Mesh
        The object, with planar texture coordinates.
    backdrop : shapes.Mesh or None
        The wall behind it (None: no background).
    phi_range_deg : tuple of float
        Azimuth range (clockwise from +Y) the object covers, seen from the mirror axis.
    support : shapes.Mesh or None
        The table it stands on (None: it floats).
    uv_to_cm : dict, optional
        Shape id (``"backdrop"``, ``"object"``, ``"support"``) -> (3, 3) affine map from homogeneous
        texture coordinates ``(u, v, 1)`` to cm along the surface, for textures of a given size in
        cm: the wall's and the table's own sides; the ``plane`` board's own coordinates (its planar
        projection undone); for the curved objects the planar projection's extent (the texture is
        front-projected, like a slide).
    """

    name: str
    mesh: shapes.Mesh
    backdrop: Optional[shapes.Mesh]
    phi_range_deg: Tuple[float, float]
    support: Optional[shapes.Mesh] = None
    uv_to_cm: Optional[dict] = None

    def default_angles(self, zeta_deg: float, n_angles: int) -> np.ndarray:
        """``n_angles`` mirror angles (deg) sweeping the laser over the whole object plus a margin."""
        lo, hi = self.phi_range_deg
        th_lo = 0.5 * (lo + zeta_deg) - _ANGLE_MARGIN_DEG
        th_hi = 0.5 * (hi + zeta_deg) + _ANGLE_MARGIN_DEG
        return np.linspace(th_lo, th_hi, int(n_angles))


def _uv_to_cm(name: str, local: shapes.Mesh) -> np.ndarray:
    """(3, 3) map from the object's planar texture coordinates (:func:`shapes.planar_uv` of ``local``)
    to cm: the board's own (x, -z) for the ``plane``, else the projection's extent."""
    uv = shapes.planar_uv(local).uv
    if name == "plane":
        board = shapes.rectangle(*_PLANE_SIZE_CM).vertices_cm  # same vertex order, before the tilt
        target = np.stack([board[:, 0], -board[:, 2]], axis=1)
        A = np.c_[uv, np.ones(len(uv))]
        sol, *_ = np.linalg.lstsq(A, target, rcond=None)  # exact: the projection of a plane is affine
        m = np.eye(3)
        m[:2, :] = sol.T
        return m
    v = local.vertices_cm
    span = v.max(axis=0) - v.min(axis=0)
    return np.diag([span[0], span[2], 1.0])


def _size_map(width_cm: float, height_cm: float) -> np.ndarray:
    return np.diag([float(width_cm), float(height_cm), 1.0])


_PLANE_SIZE_CM = (14.0, 12.0)


def _local(name: str) -> Tuple[shapes.Mesh, float]:
    """Object-local mesh and its distance from the mirror axis (cm)."""
    if name == "cone":
        return shapes.cone(4.0, 8.6), 38.0
    if name == "hand":
        return shapes.hand(), 36.0
    if name == "plane":
        m = shapes.rectangle(*_PLANE_SIZE_CM).transformed(_rig.rotation_z(25.0) @ _rig.rotation_x(-20.0))
        return m, 36.0
    if name == "sphere":
        return shapes.uv_sphere(4.3), 38.0
    raise KeyError(f"unknown scene {name!r}; valid: {', '.join(OBJECTS)}")


def _placement(distance_cm: float, zeta_deg: float) -> np.ndarray:
    """Object-local -> world: local +Y along the laser direction at mirror angle 0."""
    return (_rig.translation(_rig.cylindrical_to_cartesian(distance_cm, -zeta_deg, 0.0))
            @ _rig.rotation_z(-zeta_deg))


def _wall_size_cm(distance_cm: float) -> Tuple[float, float]:
    scale = distance_cm / BACKDROP_DISTANCE_CM
    return (BACKDROP_SIZE_CM[0] * scale, BACKDROP_SIZE_CM[1] * scale)


def _wall(distance_cm: float, zeta_deg: float) -> shapes.Mesh:
    return shapes.rectangle(*_wall_size_cm(distance_cm)).transformed(_placement(distance_cm, zeta_deg))


def _table_half_width_cm(far_cm: float) -> float:
    return 1.5 * far_cm + 20.0


def _table(top_z_cm: float, far_cm: float, zeta_deg: float) -> shapes.Mesh:
    """Horizontal rectangle facing up at height ``top_z_cm``, from the axis's line to ``far_cm``.

    In the frame of the laser at angle 0 (local +Y along it).  The half-width ``1.5 far_cm + 20`` cm
    covers every view direction up to ``ζ + 2 θ + fov/2`` ≈ 56° off that frame's +Y for mirror angles
    up to :data:`TABLE_MAX_MIRROR_ANGLE_DEG` (``tests/scenes/test_objects.py`` checks that the bottom
    rows see only the table).
    """
    half_width = _table_half_width_cm(far_cm)
    m = shapes.rectangle(2.0 * half_width, far_cm)  # local XZ plane, facing -Y
    to_floor = _rig.translation([0.0, 0.5 * far_cm, top_z_cm]) @ _rig.rotation_x(-90.0)  # facing +Z
    return m.transformed(_placement(0.0, zeta_deg) @ to_floor)


@functools.lru_cache(maxsize=64)
def build(name: str, zeta_deg: float, background: str = "wall",
          background_distance_cm: float = BACKDROP_DISTANCE_CM, support: str = "none") -> SceneObject:
    """The object ``name`` with its background and support, placed for a rig with laser angle ``zeta_deg``.

    Parameters
    ----------
    name : str
        One of :data:`OBJECTS`.
    zeta_deg : float
        The rig's laser angle ζ.
    background : str
        One of :data:`BACKGROUNDS`.
    background_distance_cm : float
        The wall's distance from the mirror axis; the whole object must be in front of it.
    support : str
        One of :data:`SUPPORTS`.

    Raises
    ------
    KeyError
        Unknown ``name``.
    ValueError
        Unknown ``background`` or ``support``; a wall through or in front of the object.
    """
    if background not in BACKGROUNDS:
        raise ValueError(f"`background` must be one of {', '.join(map(repr, BACKGROUNDS))}, got {background!r}")
    if support not in SUPPORTS:
        raise ValueError(f"`support` must be one of {', '.join(map(repr, SUPPORTS))}, got {support!r}")
    local, distance = _local(name)
    uv_to_cm = {"object": _uv_to_cm(name, local)}
    local = shapes.planar_uv(local)
    mesh = local.transformed(_placement(distance, zeta_deg))
    v = mesh.vertices_cm
    e0 = _rig.Rig(zeta_deg=zeta_deg).laser_direction(0.0)
    backdrop = None
    if background == "wall":
        depth = float((v @ e0).max())
        if not background_distance_cm > depth:
            raise ValueError(f"`background_distance_cm` must put the wall behind the {name} (farther than "
                             f"{depth:.2f} cm from the mirror axis), got {background_distance_cm!r}")
        backdrop = _wall(float(background_distance_cm), zeta_deg)
        uv_to_cm["backdrop"] = _size_map(*_wall_size_cm(float(background_distance_cm)))
    table = None
    if support == "table":
        far = (float(background_distance_cm) if background == "wall"
               else out_of_range_distance_cm(_rig.Rig(zeta_deg=zeta_deg)))
        table = _table(float(v[:, 2].min()), far, zeta_deg)
        uv_to_cm["support"] = _size_map(2.0 * _table_half_width_cm(far), far)
    for m in uv_to_cm.values():
        m.setflags(write=False)
    phi = np.degrees(np.arctan2(v[:, 0], v[:, 1]))
    return SceneObject(name, mesh, backdrop, (float(phi.min()), float(phi.max())), table, uv_to_cm)
