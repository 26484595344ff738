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
  For ``polished`` and ``glazed`` (rough, shiny) the laser pass is *split by
  pixel* (:func:`laser_passes`): ``path`` on the pixels that see the object
  (centre ray on it, grown by one pixel: :meth:`scenes.Scene.split_pixels`),
  where it renders the highlight and the lit wall seen in the object,
  ``ptracer`` on all others (the sheet reflected onto the wall).  Each is an unbiased estimate
  of the same pixel, and the choice is fixed by geometry before rendering, so
  the sum is unbiased and counts no path twice.
* the **ambient pass**: a uniform ``constant`` sky of unit in-band radiance
  (1 W m⁻² sr⁻¹), integrator ``path`` (max depth 3).
* translucent materials (``skin``, ``marble``, ``wax``) use ``volpath`` (max depth
  :data:`scenes.materials.MEDIUM_MAX_DEPTH`) in both passes, the laser pass over all
  pixels (:func:`scenes.materials.integrator_for`); the object then carries its
  medium as ``interior`` inside :func:`scenes.shapes.medium_boundary`: an open mesh
  (the ``plane``) is closed into a slab :data:`SLAB_THICKNESS_CM` deep behind its
  front face, the overlapping parts of the ``hand`` are joined into one surface.
  With ``translucency = "profile"`` they are rendered instead as their opaque stand-in
  (``stand_in_albedo``: :func:`scenes.materials.stand_in_bsdf` on the same boundary, without the medium,
  ``path`` in both passes), whose laser stripe :mod:`scenes.subsurface` then spreads.

Both use a box reconstruction filter (a pixel value is the mean radiance over the
pixel) and the ``multijitter`` sampler; units are metres.
"""

from __future__ import annotations

from typing import Dict, NamedTuple, Optional, Tuple

import numpy as np

from . import materials, rig as _rig, shapes
from .laser import LaserProfile
from .objects import SceneObject

__all__ = ["sensor", "projector", "sky", "integrator", "mesh_shape", "laser_scene", "ambient_scene",
           "laser_passes", "LaserPass", "ambient_integrator", "DIRECT_DEPTH", "hybrid_passes", "split_hybrid_passes"]

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


def integrator(kind: str, max_depth: int = MAX_DEPTH) -> dict:
    """``path``, ``ptracer`` or ``volpath`` with ``max_depth`` (default :data:`MAX_DEPTH`)."""
    if kind not in ("path", "ptracer", "volpath"):
        raise ValueError(f"`kind` must be 'path', 'ptracer' or 'volpath', got {kind!r}")
    if isinstance(max_depth, bool) or not isinstance(max_depth, (int, np.integer)) or max_depth < 1:
        raise ValueError(f"`max_depth` must be an integer >= 1, got {max_depth!r}")
    return {"type": kind, "max_depth": int(max_depth)}


class LaserPass(NamedTuple):
    """One render of the laser scene: integrator, depth and the pixels it contributes to.

    ``kind`` is a Mitsuba integrator (``path``, ``ptracer``, ``volpath``) or ``"light_indirect"``:
    the light paths of exactly ``max_depth`` segments (at ``MAX_DEPTH``, those that bounce once between
    the projector and the camera), light traced with a splat only at the last vertex
    (:func:`scenes.backend.light_indirect`; its expectation is ``ptracer`` at ``max_depth`` minus
    ``ptracer`` at ``max_depth - 1``).

    ``pixels`` is ``"all"``, ``"object"`` (pixels that see the object, see
    :meth:`scenes.Scene.split_pixels`) or ``"other"`` (the rest); or ``"support"`` (pixels that
    see a polished table, :meth:`scenes.Scene.support_pixels`) and ``"rest"`` (the others).
    Passes that all have ``"all"`` are summed.
    """

    kind: str
    max_depth: int
    pixels: str


DIRECT_DEPTH = 2
"""``max_depth`` of a camera path that ends at its first surface (camera, surface, light)."""


def hybrid_passes() -> Tuple[LaserPass, ...]:
    """The laser passes of the ``"hybrid"`` choice (:mod:`scenes.sampling`): the stripe's direct light by
    path tracing (camera paths that end at the first surface, next-event estimation to the projector:
    only the pixel footprint is sampled) plus the interreflected light by light tracing (projector
    paths with at least one bounce before the camera, where a path tracer's bounces rarely find the
    thin sheet). Together they are every path up to :data:`MAX_DEPTH`, as one ``path`` pass.

    Examples
    --------
    >>> [tuple(p) for p in hybrid_passes()]
    [('path', 2, 'all'), ('light_indirect', 3, 'all')]
    """
    return (LaserPass("path", DIRECT_DEPTH, "all"), LaserPass("light_indirect", MAX_DEPTH, "all"))


def split_hybrid_passes() -> Tuple[LaserPass, ...]:
    """The laser passes of the ``"split_hybrid"`` choice (:mod:`scenes.sampling`) of a shiny material:
    ``path`` on the pixels that see the object (as the ``split``), and on the others the direct light
    path traced plus the light that reaches them after a bounce (the sheet the object mirrors, the
    interreflections) light traced, instead of one ``ptracer`` pass for both there.

    Examples
    --------
    >>> [tuple(p) for p in split_hybrid_passes()]
    [('path', 3, 'object'), ('path', 2, 'other'), ('light_indirect', 3, 'other')]
    """
    return (LaserPass("path", MAX_DEPTH, "object"), LaserPass("path", DIRECT_DEPTH, "other"),
            LaserPass("light_indirect", MAX_DEPTH, "other"))


def _max_depth(kind: str) -> int:
    """:data:`scenes.materials.MEDIUM_MAX_DEPTH` for ``volpath`` (only the media use it), else :data:`MAX_DEPTH`."""
    return materials.MEDIUM_MAX_DEPTH if kind == "volpath" else MAX_DEPTH


def laser_passes(material: str, translucency: str = "volpath") -> Tuple[LaserPass, ...]:
    """The laser pass(es) of ``material`` (from :func:`scenes.materials.integrator_for`).

    Examples
    --------
    >>> [tuple(p) for p in laser_passes("polished")]
    [('path', 3, 'object'), ('ptracer', 3, 'other')]
    >>> [tuple(p) for p in laser_passes("skin")], [tuple(p) for p in laser_passes("skin", "profile")]
    ([('volpath', 64, 'all')], [('path', 3, 'all')])
    """
    mode = materials.integrator_for(material, "laser", translucency)
    if mode == "split":
        return (LaserPass("path", MAX_DEPTH, "object"), LaserPass("ptracer", MAX_DEPTH, "other"))
    return (LaserPass(mode, _max_depth(mode), "all"),)


def ambient_integrator(material: str, translucency: str = "volpath") -> dict:
    """Integrator dict of the ambient pass of ``material``: ``path`` (max depth 3), or ``volpath``
    with :data:`scenes.materials.MEDIUM_MAX_DEPTH` for the translucent materials (unless
    ``translucency = "profile"``).

    Examples
    --------
    >>> ambient_integrator("polished"), ambient_integrator("wax"), ambient_integrator("wax", "profile")
    ({'type': 'path', 'max_depth': 3}, {'type': 'volpath', 'max_depth': 64}, {'type': 'path', 'max_depth': 3})
    """
    kind = materials.integrator_for(material, "ambient", translucency)
    return integrator(kind, _max_depth(kind))


def mesh_shape(mesh, bsdf: dict, interior: dict = None) -> dict:
    """A triangle mesh (cm) with a BSDF and optionally an ``interior`` medium dict; ``backend`` builds the ``mi.Mesh``."""
    d = {"type": "numpy_mesh", "mesh": mesh, "bsdf": bsdf}
    if interior is not None:
        d["interior"] = interior
    return d


def _geometry(obj: SceneObject, material: str, background_albedo: float, support_albedo: float,
              albedo_maps: Optional[Dict[str, dict]] = None, support_finish: str = "matte",
              stand_in_albedo: Optional[float] = None) -> Dict[str, dict]:
    """Shapes keyed by their ids: ``backdrop`` (if any), ``object``, ``support`` (if any).

    A translucent material's object carries its medium as ``interior`` inside
    :func:`scenes.shapes.medium_boundary`: an open mesh (the ``plane``) is first closed into a slab
    :data:`SLAB_THICKNESS_CM` deep behind its front face (the front triangles, which the ground truth
    hits, are unchanged), a mesh of overlapping closed parts (the ``hand``) is replaced by their
    union (the same outer surface, hence the same truth).

    ``albedo_maps`` (shape id -> a texture dict) replaces the albedo of those surfaces (the object's
    only for :data:`scenes.materials.TEXTURABLE` materials); ``support_finish`` is the table's
    (:data:`scenes.materials.SUPPORT_FINISHES`). ``stand_in_albedo`` (translucent materials only) makes the
    boundary the opaque stand-in of ``translucency = "profile"``, without the medium: the same surface, hence
    the same truth, as the reference (the slab's side walls included).
    """
    maps = albedo_maps or {}
    translucent = materials.is_translucent(material)
    stand_in = stand_in_albedo is not None and translucent
    medium = None if stand_in else materials.medium(material)
    mesh = shapes.medium_boundary(obj.mesh, SLAB_THICKNESS_CM) if translucent else obj.mesh
    out = {}
    if obj.backdrop is not None:
        out["backdrop"] = mesh_shape(obj.backdrop, materials.backdrop_bsdf(background_albedo, maps.get("backdrop")))
    if stand_in:
        obj_bsdf = materials.stand_in_bsdf(stand_in_albedo)
    elif "object" not in maps:
        obj_bsdf = materials.bsdf(material)
    else:
        obj_bsdf = materials.with_albedo(material, maps["object"])
    out["object"] = mesh_shape(mesh, obj_bsdf, medium)
    if obj.support is not None:
        out["support"] = mesh_shape(obj.support, materials.support_bsdf(support_albedo, maps.get("support"),
                                                                        support_finish))
    return out


def laser_scene(rig: _rig.Rig, obj: SceneObject, material: str, laser: LaserProfile, theta_deg: float,
                spp: int, *, background_albedo: float = materials.BACKDROP_ALBEDO,
                support_albedo: float = materials.SUPPORT_ALBEDO, albedo_maps: Optional[Dict[str, dict]] = None,
                support_finish: str = "matte", stand_in_albedo: Optional[float] = None) -> dict:
    """Laser-only scene (unit in-band power) at mirror angle ``theta_deg``.

    ``background_albedo`` and ``support_albedo`` are the wall's and the table's Lambertian
    albedos (used only when ``obj`` has them); ``albedo_maps`` and ``support_finish`` as in
    :func:`_geometry` (textures at the laser's wavelength). The scene's integrator is the first of
    :func:`laser_passes` (a split pass renders each of its integrators by pixel). ``stand_in_albedo``: a
    translucent material's opaque stand-in (``translucency = "profile"``, see :func:`_geometry`).
    """
    first = laser_passes(material, _translucency(stand_in_albedo))[0]
    return {"type": "scene", "integrator": integrator(first.kind, first.max_depth),
            "sensor": sensor(rig, theta_deg, spp),
            **_geometry(obj, material, background_albedo, support_albedo, albedo_maps, support_finish,
                        stand_in_albedo),
            "laser": projector(rig, theta_deg, laser)}


def ambient_scene(rig: _rig.Rig, obj: SceneObject, material: str, theta_deg: float, spp: int, *,
                  background_albedo: float = materials.BACKDROP_ALBEDO,
                  support_albedo: float = materials.SUPPORT_ALBEDO, albedo_maps: Optional[Dict[str, dict]] = None,
                  support_finish: str = "matte", stand_in_albedo: Optional[float] = None) -> dict:
    """Ambient-only scene (unit in-band sky radiance) at mirror angle ``theta_deg``.

    Without a wall the camera sees the sky itself where nothing is in front of it: radiance 1
    (unit), what a white Lambertian surface under the same sky would send (about 2 DN at 400 lux).
    The integrator is :func:`ambient_integrator`; ``albedo_maps`` and ``support_finish`` as in
    :func:`_geometry` (textures weighted by one band of the ambient, see :mod:`scenes.textures`);
    ``stand_in_albedo`` as in :func:`laser_scene`.
    """
    return {"type": "scene", "integrator": ambient_integrator(material, _translucency(stand_in_albedo)),
            "sensor": sensor(rig, theta_deg, spp),
            **_geometry(obj, material, background_albedo, support_albedo, albedo_maps, support_finish,
                        stand_in_albedo),
            "sky": sky(1.0)}


def _translucency(stand_in_albedo: Optional[float]) -> str:
    return "volpath" if stand_in_albedo is None else "profile"


def pose_updates(rig: _rig.Rig, theta_deg: float) -> Dict[str, np.ndarray]:
    """Scene-parameter updates (``mi.traverse`` keys) that move a loaded scene to ``theta_deg``."""
    return {"sensor.to_world": rig.camera_to_world_m(theta_deg),
            "laser.to_world": rig.laser_to_world_m(theta_deg)}
