"""Readable Mitsuba scene dicts, built by small functions.

The dicts are *descriptions*: plain Python with numpy values (4x4 matrices in
metres, mesh objects in cm, bitmap arrays) that :mod:`scenes.backend` turns into
Mitsuba objects.  They never import Mitsuba.

Two scenes share the geometry of one frame:

* the **laser pass**: projector only, unit in-band power (1 W), integrator
  ``path`` (max depth 3: direct light plus one interreflection) or, for the
  ``specular`` material, ``ptracer`` (max depth 3) because ``path`` cannot find
  laser -> perfect mirror -> diffuse paths from a delta light.  ``ptracer``
  misses camera -> mirror -> lit diffuse paths instead (the lit backdrop seen
  *in* the mirror); the physically more important false stripe is the one
  thrown onto the backdrop, which it renders.
* the **ambient pass**: a uniform ``constant`` sky of unit in-band radiance
  (1 W m⁻² sr⁻¹), integrator ``path`` (max depth 3).
* translucent materials (``skin``, ``marble``, ``wax``) use ``volpath`` in both
  passes (:func:`scenes.materials.integrator_for`); the object then carries its
  medium as ``interior`` and an open mesh (the ``plane``) is closed into a
  slab :data:`SLAB_THICKNESS_CM` deep behind its front face.

Both use a box reconstruction filter (a pixel value is the mean radiance over the
pixel) and the ``multijitter`` sampler; units are metres.
"""

from __future__ import annotations

from typing import Dict

import numpy as np

from . import materials, rig as _rig, shapes
from .laser import LaserProfile
from .objects import SceneObject

__all__ = ["sensor", "projector", "sky", "integrator", "mesh_shape", "laser_scene", "ambient_scene"]

MAX_DEPTH = 3
#: Depth of the slab that closes an open object (the ``plane``) around a medium, cm.
SLAB_THICKNESS_CM = 2.0


def sensor(rig: _rig.Rig, theta_deg: float, spp: int) -> dict:
    """Pinhole camera at the virtual pose for ``theta_deg``; principal point at the image centre."""
    return {
        "type": "perspective",
        "fov": rig.fov_x_deg,
        "fov_axis": "x",
        "near_clip": 0.01,
        "far_clip": 100.0,
        "to_world": rig.camera_to_world_m(theta_deg),
        "film": {"type": "hdrfilm", "width": rig.width, "height": rig.height,
                 "rfilter": {"type": "box"}, "pixel_format": "luminance"},
        "sampler": {"type": "multijitter", "sample_count": int(spp)},
    }


def projector(rig: _rig.Rig, theta_deg: float, laser: LaserProfile, power_w: float = 1.0) -> dict:
    """The line laser: a projector at ``-d_laser e_L`` aimed along ``e_L``, fan vertical."""
    return {
        "type": "projector",
        "irradiance": {"type": "bitmap", "bitmap": laser.texture, "raw": True},
        "fov": laser.fov_x_deg,
        "fov_axis": "x",
        "scale": laser.scale_for_power(power_w),
        "to_world": rig.laser_to_world_m(theta_deg),
    }


def sky(radiance: float = 1.0) -> dict:
    """A uniform sky of in-band radiance ``radiance`` (W m⁻² sr⁻¹)."""
    return {"type": "constant", "radiance": float(radiance)}


def integrator(kind: str) -> dict:
    """``path`` or ``ptracer`` with :data:`MAX_DEPTH`."""
    if kind not in ("path", "ptracer"):
        raise ValueError(f"`kind` must be 'path' or 'ptracer', got {kind!r}")
    return {"type": kind, "max_depth": MAX_DEPTH}


def mesh_shape(mesh, bsdf: dict, interior: dict = None) -> dict:
    """A triangle mesh (cm) with a BSDF and optionally an ``interior`` medium dict; ``backend`` builds the ``mi.Mesh``."""
    d = {"type": "numpy_mesh", "mesh": mesh, "bsdf": bsdf}
    if interior is not None:
        d["interior"] = interior
    return d


def _geometry(obj: SceneObject, material: str) -> Dict[str, dict]:
    medium = materials.medium(material)
    mesh = obj.mesh if medium is None else shapes.solidify(obj.mesh, SLAB_THICKNESS_CM)
    return {"backdrop": mesh_shape(obj.backdrop, materials.backdrop_bsdf()),
            "object": mesh_shape(mesh, materials.bsdf(material), medium)}


def _integrator(material: str, light: str) -> dict:
    d = materials.integrator_for(material, light)
    return integrator(d["type"]) if d["type"] in ("path", "ptracer") else d


def laser_scene(rig: _rig.Rig, obj: SceneObject, material: str, laser: LaserProfile, theta_deg: float,
                spp: int) -> dict:
    """Laser-only scene (unit in-band power) at mirror angle ``theta_deg``."""
    return {"type": "scene", "integrator": _integrator(material, "laser"), "sensor": sensor(rig, theta_deg, spp),
            **_geometry(obj, material), "laser": projector(rig, theta_deg, laser)}


def ambient_scene(rig: _rig.Rig, obj: SceneObject, material: str, theta_deg: float, spp: int) -> dict:
    """Ambient-only scene (unit in-band sky radiance) at mirror angle ``theta_deg``."""
    return {"type": "scene", "integrator": _integrator(material, "ambient"), "sensor": sensor(rig, theta_deg, spp),
            **_geometry(obj, material), "sky": sky(1.0)}


def pose_updates(rig: _rig.Rig, theta_deg: float) -> Dict[str, np.ndarray]:
    """Scene-parameter updates (``mi.traverse`` keys) that move a loaded scene to ``theta_deg``."""
    return {"sensor.to_world": rig.camera_to_world_m(theta_deg),
            "laser.to_world": rig.laser_to_world_m(theta_deg)}
