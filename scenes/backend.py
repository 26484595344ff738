"""The only module that talks to Mitsuba: load descriptions, render passes, cast rays.

Mitsuba is imported lazily through :func:`scenes.variant.mitsuba`.  A
:class:`LoadedScene` keeps a loaded Mitsuba scene and its ``mi.traverse``
parameters; :meth:`LoadedScene.render` sets *every* per-frame parameter (camera
and laser pose) before rendering, so the result depends only on its arguments
and never on the frames rendered before (loading is only a cache).

Reproducibility: ``path`` renders are bit-identical run to run on LLVM, and across
x86-64 machines with AVX2 since :mod:`scenes.variant` fixes the LLVM target; the
``ptracer`` renders (the fixed-count passes of ``specular``, ``polished`` and
``glazed``) run on one LLVM thread because their
atomic splatting order otherwise changes the last float bits.  On CUDA the
``ptracer`` pass is reproducible only to float32 rounding (the disk cache makes
reruns identical).  :func:`light_indirect` (the ``auto`` passes' interreflected light)
splats on the host instead, so it is reproducible on any number of threads.
:func:`bounce_mis` with ``light_indirect(..., mis=...)`` is the one-bounce light by multiple
importance sampling of camera and light paths (a study, ``stripebench perf mis``; no frame uses it yet).
"""

from __future__ import annotations

import contextlib
from typing import Dict, Optional, Tuple

import numpy as np

from . import variant as _variant
from .rig import CM_TO_M

__all__ = ["materialise", "LoadedScene", "interrupted", "light_indirect", "camera_paths", "bounce_mis"]


def interrupted(exc: BaseException) -> bool:
    """True when ``exc`` is, or was caused by, a :class:`KeyboardInterrupt` (its ``__cause__`` /
    ``__context__`` chain).

    Examples
    --------
    >>> try:
    ...     try:
    ...         raise KeyboardInterrupt
    ...     except KeyboardInterrupt as k:
    ...         raise RuntimeError("wrapped") from k
    ... except RuntimeError as e:
    ...     interrupted(e), interrupted(RuntimeError("plain"))
    (True, False)
    """
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


@contextlib.contextmanager
def _ctrl_c():
    """Ctrl-C always a :class:`KeyboardInterrupt`: Dr.Jit wraps one that arrives inside some kernels
    (e.g. the light-traced pass) in a ``RuntimeError``, which the CLI would otherwise report as a
    crash instead of an interruption; other errors pass unchanged."""
    try:
        yield
    except RuntimeError as exc:
        if interrupted(exc):
            raise KeyboardInterrupt from exc
        raise


def _wavefront_sampler(sensor, spp: int, seed: int, lanes: int):
    """The sensor's sampler, cloned and seeded for a wavefront of ``lanes`` samples at ``spp`` per
    pixel, as Mitsuba's own renders seed it; returns ``(sampler, spp)`` with the sampler's own count
    (``multijitter`` rounds it to a grid). ``lanes`` is a function of that count."""
    _check_spp(spp)
    sampler = sensor.sampler().clone()
    sampler.set_sample_count(int(spp))
    spp = sampler.sample_count()
    sampler.set_samples_per_wavefront(spp)
    sampler.seed(int(seed), int(lanes(spp)))
    return sampler, spp


def _check_spp(spp) -> None:
    if int(spp) < 1:
        raise ValueError(f"`spp` must be >= 1, got {spp!r}")


def _first_channel(value):
    """A spectrum's first channel (as the renders are read back); a plain array as is."""
    return value.x if hasattr(value, "x") else value


def _splat(value, pixel: np.ndarray, width: int, height: int) -> np.ndarray:
    """Per-pixel float64 sums (H, W) of one value per lane (a one-channel Dr.Jit array, evaluated with
    everything else the kernel computes) at flat pixel indices ``pixel`` (lanes outside the image:
    -1, dropped), in lane order: the same bytes on any number of threads."""
    v = np.array(value, dtype=np.float64).reshape(-1)
    keep = (v != 0) & (pixel >= 0) & (pixel < width * height)
    return np.bincount(pixel[keep], weights=v[keep], minlength=width * height).reshape(height, width)


def _adjoint_shading(mi, dr, si, d_world, d_local, wi_geo):
    """Veach's adjoint correction for shading normals (light travelling along ``si.wi`` -> ``d``) and
    the light-leak test, as ``ptracer`` does: 0 where the geometric and shading normals disagree about
    the side of either direction."""
    wo_geo = dr.dot(si.n, d_world)
    cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(d_local)
    valid = (wi_geo * cos_i > 0) & (wo_geo * cos_o > 0)
    return dr.select(valid, dr.abs((cos_i * wo_geo) / (cos_o * wi_geo)), 0.0)


def _pixel_rays(mi, dr, sensor, pixels: np.ndarray, spp: int, seed: int):
    """``spp`` camera rays through uniformly random points of the footprint of each pixel of ``pixels``
    ((H, W) bool, the film's shape), differentials scaled by ``1 / sqrt(spp)``: ``(sampler, spp, lanes,
    ray, weight)``, ``lanes`` the pixel index of each ray; None when ``pixels`` is empty."""
    width, height = (int(v) for v in sensor.film().size())
    pixels = np.asarray(pixels, bool)
    if pixels.shape != (height, width):
        raise ValueError(f"`pixels` must have the film's shape {(height, width)}, got {pixels.shape}")
    index = np.flatnonzero(pixels).astype(np.uint32)
    if len(index) == 0:
        _check_spp(spp)
        return None
    sampler, spp = _wavefront_sampler(sensor, spp, seed, lambda n: len(index) * n)
    lanes = np.repeat(index, spp)
    pixel = mi.UInt32(lanes)
    position = mi.Point2f(mi.Float(pixel % width), mi.Float(pixel // width)) + sampler.next_2d()
    ray, weight = sensor.sample_ray_differential(mi.Float(0.0), mi.Float(0.0),
                                                 position / mi.ScalarVector2f(width, height), mi.Point2f(0.5))
    ray.scale_differential(dr.rsqrt(spp))
    return sampler, spp, lanes, ray, weight


class _BounceDensities:
    """The sample densities of a one-bounce laser path (projector, ``x2``, ``x1``, camera) under its two
    unidirectional strategies, for their multiple importance sampling (:func:`bounce_mis`).

    * camera paths (``spp`` per pixel): ``x1`` through the pixel footprint, ``x2`` by sampling
      ``x1``'s BSDF, the projector connected to ``x2``; in area measure, per sample,
      ``Npix / (A_c cos^3 t_c) |cos t_1c| / d_c1^2 * pdf_1(w_12) * |cos t_2| / d_12^2``;
    * light paths (``light_spp`` per pixel, ``W H light_spp`` in all): ``x2`` by sampling the
      projector's texture (``Texture.pdf_position`` on its image plane of area ``A_p`` at z = 1),
      ``x1`` by sampling ``x2``'s BSDF, ``x1`` connected to the camera:
      ``pdf_uv / (A_p cos^3 t_p) |cos t_2p| / d_p2^2 * pdf_2(w_21) * |cos t_1| / d_12^2``.

    ``A_c``, ``A_p``: the image planes' areas at unit distance (``(2 tan(fov_x / 2))^2 H / W``);
    ``t_c``, ``t_p``: the angle of the ray to each pinhole's axis. The common ``1 / d_12^2`` is left out
    of both (:meth:`camera` and :meth:`light` return the rest), as is ``|cos t_2|`` / ``|cos t_1|``
    where the caller multiplies them in.
    """

    def __init__(self, mi, dr, scene, projector_fov_x_deg: float):
        import math

        self.mi, self.dr = mi, dr
        sensor, emitter = scene.sensors()[0], scene.emitters()[0]
        width, height = (int(v) for v in sensor.film().size())
        self.n_pixels = width * height
        cam = sensor.world_transform()
        self.cam_o, self.cam_z = cam @ mi.Point3f(0.0, 0.0, 0.0), dr.normalize(cam @ mi.Vector3f(0.0, 0.0, 1.0))
        tx = math.tan(math.radians(float(dr.slice(mi.traverse(sensor)["x_fov"], 0))) / 2.0)
        self.a_cam = (2.0 * tx) ** 2 * height / width
        data = np.array(mi.traverse(emitter)["irradiance.data"], dtype=np.float32)
        th, tw = data.shape[:2]
        self.texture = mi.load_dict({"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(data)), "raw": True})
        tp = math.tan(math.radians(float(projector_fov_x_deg)) / 2.0)
        self.a_proj = (2.0 * tp) ** 2 * th / tw
        proj = emitter.world_transform()
        self.proj_o, self.proj_z = proj @ mi.Point3f(0.0, 0.0, 0.0), dr.normalize(proj @ mi.Vector3f(0.0, 0.0, 1.0))
        self.proj_inv = proj.inverse()
        self.to_sample = mi.perspective_projection(mi.ScalarVector2i(tw, th), mi.ScalarVector2i(tw, th),
                                                   mi.ScalarVector2i(0, 0), float(projector_fov_x_deg), 1e-4, 1e4)

    def camera(self, x1, n1):
        """Per camera sample per pixel: ``Npix / (A_c cos^3 t_c) |cos t_1c| / d_c1^2`` at ``x1``."""
        dr = self.dr
        d = self.cam_o - x1
        dist2 = dr.squared_norm(d)
        dn = d * dr.rsqrt(dist2)
        cos_c = dr.maximum(dr.abs(dr.dot(dn, self.cam_z)), 1e-6)
        return self.n_pixels / (self.a_cam * cos_c ** 3) * dr.abs(dr.dot(n1, dn)) / dist2

    def light(self, x2, n2):
        """Per light path: ``pdf_uv / (A_p cos^3 t_p) |cos t_2p| / d_p2^2`` at ``x2`` (0 outside the texture)."""
        mi, dr = self.mi, self.dr
        d = self.proj_o - x2
        dist2 = dr.squared_norm(d)
        dn = d * dr.rsqrt(dist2)
        cos_p = dr.maximum(dr.abs(dr.dot(dn, self.proj_z)), 1e-6)
        local = self.proj_inv @ x2
        uvw = self.to_sample @ local
        uv = mi.Point2f(uvw.x, uvw.y)
        inside = (uv.x >= 0) & (uv.x <= 1) & (uv.y >= 0) & (uv.y <= 1) & (local.z > 0)
        pdf_uv = self.texture.pdf_position(uv, inside)
        return dr.select(inside, pdf_uv / (self.a_proj * cos_p ** 3) * dr.abs(dr.dot(n2, dn)) / dist2, 0.0)


def bounce_mis(mi, scene, pixels: np.ndarray, spp: int, seed: int, light_spp: int,
               projector_fov_x_deg: float) -> np.ndarray:
    """The one-bounce laser light (projector, two surface vertices, camera) on ``pixels`` by camera paths,
    each weighted for multiple importance sampling against :func:`light_indirect` at ``light_spp``
    (balance heuristic: :class:`_BounceDensities`): float32 (H, W) radiance, 0 outside ``pixels``.

    Each pixel of ``pixels`` gets ``spp`` camera rays through random points of its footprint; at the
    first surface ``x1`` the BSDF is sampled, at the hit ``x2`` the projector is connected (next-event
    estimation), and the path's value is multiplied by ``c / (c + l)``, ``c`` and ``l`` the path's
    densities under this strategy and under the light tracer. ``light_indirect(..., mis=(pixels, spp,
    fov))`` weights its splats on ``pixels`` by ``l / (c + l)``, so the two sum to the one-bounce light
    with the noise of whichever strategy samples a path better: a glossy ``x1`` (its lobe sampled from
    the camera) or a glossy ``x2`` (its lobe sampled from the projector), where each alone has
    fireflies. The direct light (camera, ``x1``, projector) is not included.

    Parameters
    ----------
    mi : module
        ``mitsuba`` with a JIT variant set.
    scene : mitsuba.Scene
        A loaded, posed laser scene (its first sensor and its projector).
    pixels : ndarray (H, W), bool
    spp : int
        Camera samples per pixel (>= 1).
    seed : int
    light_spp : int
        Light paths per pixel of the :func:`light_indirect` pass it is combined with (>= 1).
    projector_fov_x_deg : float
        The projector's horizontal field of view (``fov`` with ``fov_axis = 'x'``).
    """
    import drjit as dr

    sensor = scene.sensors()[0]
    width, height = (int(v) for v in sensor.film().size())
    if isinstance(light_spp, bool) or not isinstance(light_spp, (int, np.integer)) or light_spp < 1:
        raise ValueError(f"`light_spp` must be an integer >= 1, got {light_spp!r}")
    rays = _pixel_rays(mi, dr, sensor, pixels, spp, seed)
    if rays is None:
        return np.zeros((height, width), np.float32)
    sampler, spp, lanes, ray, ray_weight = rays
    dens = _BounceDensities(mi, dr, scene, projector_fov_x_deg)
    ctx = mi.BSDFContext()
    si = scene.ray_intersect(ray, mi.RayFlags.All, coherent=True)
    active = si.is_valid()
    bsdf = si.bsdf(ray)
    bs, bsdf_weight = bsdf.sample(ctx, si, sampler.next_1d(active), sampler.next_2d(active), active)
    d12 = si.to_world(bs.wo)
    ray2 = si.spawn_ray(d12)
    active &= dr.max(bsdf_weight) != 0
    si2 = scene.ray_intersect(ray2, active)
    active &= si2.is_valid()
    bsdf2 = si2.bsdf(ray2)
    ds, emitted = scene.sample_emitter_direction(si2, sampler.next_2d(active), True, active)
    active &= ds.pdf != 0
    value = _first_channel(bsdf_weight * emitted * bsdf2.eval(ctx, si2, si2.to_local(ds.d), active))
    camera = spp * dens.camera(si.p, si.n) * bs.pdf * dr.abs(dr.dot(si2.n, d12))
    at_x2 = mi.SurfaceInteraction3f(si2)
    at_x2.wi = si2.to_local(ds.d)  # the light path arrives from the projector
    pdf2 = bsdf2.pdf(mi.BSDFContext(mi.TransportMode.Importance), at_x2, si2.to_local(-d12), active)
    light = int(light_spp) * dens.n_pixels * dens.light(si2.p, si2.n) * pdf2 * dr.abs(dr.dot(si.n, d12))
    weight = dr.select(camera + light > 0, camera / (camera + light), 1.0)
    value = dr.select(active, value * weight, 0.0) * _first_channel(ray_weight)
    dr.eval(value)
    return (_splat(value, lanes.astype(np.int64), width, height) / spp).astype(np.float32)


def light_indirect(mi, scene, spp: int, seed: int, depth: int, mis: Optional[tuple] = None) -> np.ndarray:
    """The light paths of exactly ``depth`` segments (projector, ``depth - 1`` surface vertices,
    camera), light traced: float32 (H, W) radiance.

    Each of the ``spp x W x H`` light paths starts at the projector
    (``Scene.sample_emitter_ray``), is extended by BSDF sampling in importance transport
    ``depth - 2`` times and splats only at its last vertex, connected to the camera
    (``Sensor.sample_direction``, a shadow ray, the BSDF towards the camera). This is term for
    term Mitsuba's ``ptracer`` (its shading-normal correction and leak test, the weight
    ``1 / spp``, the box filter's one pixel per splat) restricted to the splat at that vertex, so
    its expectation is ``ptracer`` at ``depth`` minus ``ptracer`` at ``depth - 1``: the interreflected
    light alone, at the cost of one connection per path instead of ``2 depth - 3``
    (``tests/scenes/test_backend.py`` checks the expectation against both integrators).

    Reproducible on any number of threads: every path is one independent lane of the kernel (no
    atomic splats, whose order ``ptracer`` leaves to the scheduler), and the splats are summed by
    pixel in float64 on the host (``numpy.bincount``, in lane order).

    Parameters
    ----------
    mi : module
        ``mitsuba`` with a JIT variant set (``llvm_*`` or ``cuda_*``).
    scene : mitsuba.Scene
        A loaded, posed scene: the first sensor's film (box filter) and sampler are used.
    spp : int
        Light paths per pixel (>= 1).
    seed : int
        Seed of the sampler.
    depth : int
        Segments of the paths (>= 2; 2 is the direct light, 3 one bounce).
    mis : (pixels, camera_spp, projector_fov_x_deg), optional
        At ``depth = 3`` only: weight the splats on ``pixels`` ((H, W) bool) for multiple importance
        sampling against :func:`bounce_mis` at ``camera_spp`` there (the other pixels' splats are
        unchanged, bit for bit).
    """
    import drjit as dr

    if int(depth) < 2:
        raise ValueError(f"`depth` must be >= 2 (projector, a surface, the camera), got {depth!r}")
    if mis is not None and int(depth) != 3:
        raise ValueError(f"`mis` needs `depth` = 3 (one bounce), got {depth!r}")
    sensor = scene.sensors()[0]
    width, height = (int(v) for v in sensor.film().size())
    sampler, spp = _wavefront_sampler(sensor, spp, seed, lambda n: width * height * n)
    ctx = mi.BSDFContext(mi.TransportMode.Importance)
    ray, throughput, _ = scene.sample_emitter_ray(mi.Float(0.0), sampler.next_1d(), sampler.next_2d(),
                                                  sampler.next_2d(), mi.Bool(True))
    active = dr.max(throughput) != 0
    si = scene.ray_intersect(ray, active)
    active &= si.is_valid()
    for _ in range(int(depth) - 2):  # the bounces before the last vertex
        bs, value = si.bsdf(ray).sample(ctx, si, sampler.next_1d(active), sampler.next_2d(active), active)
        d_world = si.to_world(bs.wo)
        throughput *= value * _adjoint_shading(mi, dr, si, d_world, bs.wo, dr.dot(si.n, -ray.d))
        active &= dr.max(throughput) != 0
        previous, pdf_previous, d_previous = si, bs.pdf, d_world
        ray = si.spawn_ray(d_world)
        si = scene.ray_intersect(ray, active)
        active &= si.is_valid()
    # the last vertex, connected to the camera
    ds, sensor_weight = sensor.sample_direction(si, sampler.next_2d(), active)
    active &= ds.pdf > 0
    to_camera = si.spawn_ray_to(ds.p)
    active &= ~scene.ray_test(to_camera, active)
    local = si.to_local(to_camera.d)
    wi_geo = dr.dot(si.n, si.to_world(si.wi))
    bsdf = si.bsdf(ray)
    value = (throughput * sensor_weight * _adjoint_shading(mi, dr, si, to_camera.d, local, wi_geo)
             * bsdf.eval(ctx, si, local, active) / spp)
    value = _first_channel(dr.select(active, value, 0.0))
    x = mi.Int32(dr.floor(ds.uv.x))
    y = mi.Int32(dr.floor(ds.uv.y))
    if mis is not None:
        mis_pixels, camera_spp, fov = mis
        mis_pixels = np.asarray(mis_pixels, bool)
        if mis_pixels.shape != (height, width):
            raise ValueError(f"`mis` pixels must have shape {(height, width)}, got {mis_pixels.shape}")
        dens = _BounceDensities(mi, dr, scene, fov)
        inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
        on_mis = inside & dr.gather(mi.Bool, mi.Bool(mis_pixels.reshape(-1)),
                                    mi.UInt32(dr.select(inside, y * width + x, 0)), inside)
        at_x1 = mi.SurfaceInteraction3f(si)
        at_x1.wi = local  # the camera path arrives from the camera
        pdf1 = bsdf.pdf(mi.BSDFContext(), at_x1, si.to_local(-d_previous), on_mis)
        camera = int(camera_spp) * dens.camera(si.p, si.n) * pdf1 * dr.abs(dr.dot(previous.n, d_previous))
        light = (spp * dens.n_pixels * dens.light(previous.p, previous.n) * pdf_previous
                 * dr.abs(dr.dot(si.n, d_previous)))
        value = dr.select(on_mis & (camera + light > 0), value * light / (camera + light), value)
    dr.eval(value, x, y)  # one kernel for all three
    x, y = np.array(x).reshape(-1).astype(np.int64), np.array(y).reshape(-1).astype(np.int64)
    pixel = np.where((x >= 0) & (x < width) & (y >= 0) & (y < height), y * width + x, -1)
    return _splat(value, pixel, width, height).astype(np.float32)


def camera_paths(mi, scene, integrator, pixels: np.ndarray, spp: int, seed: int) -> np.ndarray:
    """A camera-path integrator (``path``, ``volpath``) on some pixels only: float32 (H, W) radiance, 0
    outside ``pixels``.

    Each pixel of ``pixels`` gets ``spp`` camera rays through uniformly random points of its
    footprint (``Sensor.sample_ray_differential``, differentials scaled by ``1 / sqrt(spp)``), each
    estimated by the integrator's own ``sample`` and weighted by the ray's weight; the pixel is their
    mean. That is what ``mi.render`` computes for a pixel with the box filter, so the result has the
    same expectation (and noise) per pixel as the whole-image render masked to ``pixels``, at the
    cost of those pixels only. Reproducible on any number of threads (independent lanes, the mean
    taken on the host in lane order).

    Parameters
    ----------
    mi : module
        ``mitsuba`` with a JIT variant set.
    scene : mitsuba.Scene
        A loaded, posed scene (first sensor: film with a box filter, and its sampler).
    integrator : mitsuba.SamplingIntegrator
    pixels : ndarray (H, W), bool
        The pixels to render (the film's size).
    spp : int
        Samples per pixel (>= 1; the sampler may round it, e.g. ``multijitter`` to a grid).
    seed : int
    """
    import drjit as dr

    sensor = scene.sensors()[0]
    width, height = (int(v) for v in sensor.film().size())
    rays = _pixel_rays(mi, dr, sensor, pixels, spp, seed)
    if rays is None:
        return np.zeros((height, width), np.float32)
    sampler, spp, lanes, ray, weight = rays
    radiance, _, _ = integrator.sample(scene, sampler, ray, None, mi.Bool(True))
    value = _first_channel(radiance * weight)
    dr.eval(value)
    return (_splat(value, lanes.astype(np.int64), width, height) / spp).astype(np.float32)


def _mesh(mi, name: str, mesh, bsdf, interior=None):
    props = mi.Properties()
    props["bsdf"] = bsdf
    if interior is not None:
        props["interior"] = interior
    m = mi.Mesh(name, len(mesh.vertices_cm), len(mesh.faces), props=props,
                has_vertex_normals=True, has_vertex_texcoords=True)
    params = mi.traverse(m)

    def put(key, arr, dtype):
        params[key] = type(params[key])(np.ascontiguousarray(arr, dtype=dtype).ravel())

    put("vertex_positions", mesh.vertices_cm * CM_TO_M, np.float32)
    put("vertex_normals", mesh.normals, np.float32)
    put("vertex_texcoords", mesh.uv, np.float32)
    put("faces", mesh.faces, np.uint32)
    params.update()
    return m


def materialise(d, mi, *, mono: bool, name: str = "shape"):
    """Turn a :mod:`scenes.description` dict into what ``mi.load_dict`` accepts.

    4x4 ``to_world`` (and a texture's ``to_uv``) arrays become ``ScalarTransform4f``, ``bitmap`` arrays ``mi.Bitmap``,
    ``numpy_mesh`` entries ``mi.Mesh`` objects with their BSDF (and ``interior`` medium); RGB variants get an
    ``rgb`` film.
    """
    if isinstance(d, dict):
        if d.get("type") == "numpy_mesh":
            bsdf = mi.load_dict(materialise(d["bsdf"], mi, mono=mono))
            interior = mi.load_dict(materialise(d["interior"], mi, mono=mono)) if "interior" in d else None
            return _mesh(mi, name, d["mesh"], bsdf, interior)
        out = {}
        for k, v in d.items():
            if k in ("to_world", "to_uv") and isinstance(v, np.ndarray):
                out[k] = mi.ScalarTransform4f(v.tolist())
            elif k == "bitmap" and isinstance(v, np.ndarray):
                out[k] = mi.Bitmap(np.array(v, dtype=np.float32, order="C", copy=True))
            elif k == "pixel_format" and not mono:
                out[k] = "rgb"
            else:
                out[k] = materialise(v, mi, mono=mono, name=k)
        return out
    return d


class LoadedScene:
    """A loaded Mitsuba scene that can be re-posed, rendered and ray cast.

    Parameters
    ----------
    scene_dict : dict
        A :mod:`scenes.description` scene dict.
    """

    def __init__(self, scene_dict: dict):
        self._mi = _variant.mitsuba()
        self.variant = self._mi.variant()
        self._mono = _variant.is_mono(self.variant)
        self._scene = self._mi.load_dict(materialise(scene_dict, self._mi, mono=self._mono), optimize=False)
        self._params = self._mi.traverse(self._scene)
        self._shape_ids: Optional[Dict[str, object]] = None
        self._integrators: Dict[Tuple[str, int], object] = {}
        # ptracer splats with atomic adds: their order (hence the float sum) varies between
        # threads; one LLVM thread makes it bit-reproducible (about 2x slower on 2 cores).
        self._scene_kind = scene_dict.get("integrator", {}).get("type")
        self._projector_fov = scene_dict.get("laser", {}).get("fov")  # a laser scene's projector

    def set_pose(self, updates: Dict[str, np.ndarray]) -> None:
        """Apply ``{traverse key: 4x4 matrix}`` updates (keys the scene lacks are skipped)."""
        changed = False
        for key, m in updates.items():
            if key in self._params:
                self._params[key] = self._mi.ScalarTransform4f(np.asarray(m, float).tolist())
                changed = True
        if changed:
            self._params.update()

    def render(self, updates: Dict[str, np.ndarray], spp: int, seed: int,
               integrator: Optional[Tuple[str, int]] = None, pixels: Optional[np.ndarray] = None) -> np.ndarray:
        """Pose, then render; returns float32 (H, W) radiance (one channel).

        ``integrator`` ``(kind, max_depth)`` (e.g. ``("ptracer", 2)``) renders with that integrator
        instead of the scene's own; ``("light_indirect", d)`` renders the light paths of exactly ``d``
        segments (:func:`light_indirect`, see :class:`scenes.description.LaserPass`).

        ``pixels`` (H, W) bool renders only those pixels (zero elsewhere) with a camera-path integrator
        (``path``, ``volpath``): :func:`camera_paths` on JIT variants, the whole image masked on
        ``scalar_*``. The light tracers ignore it (their paths land anywhere).
        """
        if integrator is not None and integrator[0] == "light_indirect":
            return self._light_indirect(updates, spp, seed, int(integrator[1]))
        self.set_pose(updates)
        kwargs = {}
        kind = self._scene_kind
        if integrator is not None:
            kind = integrator[0]
            if integrator not in self._integrators:
                self._integrators[integrator] = self._mi.load_dict(
                    {"type": integrator[0], "max_depth": int(integrator[1])})
            kwargs["integrator"] = self._integrators[integrator]
        if pixels is not None and kind in ("path", "volpath"):
            pixels = np.asarray(pixels, bool)
            if self.variant.startswith("scalar"):
                return np.where(pixels, self.render(updates, spp, seed, integrator), 0.0).astype(np.float32)
            with _ctrl_c():
                return camera_paths(self._mi, self._scene, kwargs.get("integrator", self._scene.integrator()),
                                    pixels, spp, seed)
        if kind == "ptracer" and self.variant.startswith("llvm"):
            dr = __import__("drjit")
            threads = dr.thread_count()
            dr.set_thread_count(1)
            try:
                img = np.array(self._render(spp, seed, kwargs), dtype=np.float32)
            finally:
                dr.set_thread_count(threads)
        else:
            img = np.array(self._render(spp, seed, kwargs), dtype=np.float32)
        if img.ndim == 3:
            img = img[..., 0]
        return np.ascontiguousarray(img)

    def _light_indirect(self, updates, spp: int, seed: int, depth: int) -> np.ndarray:
        """``("light_indirect", depth)``: :func:`light_indirect` on JIT variants; on ``scalar_*`` (one
        sample at a time in Python would crawl) the same light as ``ptracer`` at ``depth`` minus
        ``ptracer`` at ``depth - 1`` with the same seed, which draw the same random numbers for the
        vertices they share."""
        if self.variant.startswith("scalar"):
            longer = self.render(updates, spp, seed, integrator=("ptracer", depth))
            shorter = self.render(updates, spp, seed, integrator=("ptracer", depth - 1))
            return (longer.astype(np.float64) - shorter).astype(np.float32)
        self.set_pose(updates)
        with _ctrl_c():
            return light_indirect(self._mi, self._scene, spp, seed, depth)

    def bounce_mis(self, updates: Dict[str, np.ndarray], pixels: np.ndarray, camera_spp: int, light_spp: int,
                   seed: int) -> np.ndarray:
        """The one-bounce laser light on ``pixels`` by camera paths and light paths weighted by the balance
        heuristic (:func:`bounce_mis` at ``camera_spp`` with seed ``seed``, :func:`light_indirect` with
        ``mis`` at ``light_spp`` with seed ``seed + 1``): float32 (H, W) radiance, 0 off ``pixels``. JIT
        variants of a laser scene (its projector) only.
        """
        if self._projector_fov is None or self.variant.startswith("scalar"):
            raise ValueError(f"bounce_mis needs a laser scene on a JIT variant, this is {self.variant}")
        self.set_pose(updates)
        with _ctrl_c():
            camera = bounce_mis(self._mi, self._scene, pixels, camera_spp, seed, light_spp, self._projector_fov)
            light = light_indirect(self._mi, self._scene, light_spp, seed + 1, 3,
                                   mis=(pixels, camera_spp, self._projector_fov))
        return camera + np.where(np.asarray(pixels, bool), light, 0.0).astype(np.float32)

    def _render(self, spp: int, seed: int, kwargs: dict):
        """``mi.render``, with Ctrl-C always a :class:`KeyboardInterrupt` (:func:`_ctrl_c`)."""
        with _ctrl_c():
            return self._mi.render(self._scene, spp=int(spp), seed=int(seed), **kwargs)

    # -- ray casting --------------------------------------------------------------
    def _ids(self):
        if self._shape_ids is None:
            dr = __import__("drjit")
            ids = {}
            for shape in self._scene.shapes():
                if self.variant.startswith("scalar"):
                    ids[shape.id()] = shape.id()
                else:
                    ptr = self._mi.ShapePtr(shape)
                    ids[shape.id()] = int(np.array(dr.reinterpret_array(self._mi.UInt32, ptr))[0])
            self._shape_ids = ids
        return self._shape_ids

    def cast(self, origins_cm: np.ndarray, dirs: np.ndarray, names: Tuple[str, ...]) -> Tuple[np.ndarray, np.ndarray]:
        """First hits of rays.

        Parameters
        ----------
        origins_cm, dirs : ndarray, shape (N, 3)
            Ray origins (cm) and unit directions.
        names : tuple of str
            Shape ids; the returned index is the position of the hit shape in ``names``.

        Returns
        -------
        t_cm : ndarray (N,), float64
            Hit distance (inf for a miss).
        part : ndarray (N,), int64
            Index into ``names`` of the hit shape, -1 for a miss or an unlisted shape.
        """
        t, part, _ = self._cast(origins_cm, dirs, names, normals=False)
        return t, part

    def cast_normals(self, origins_cm: np.ndarray, dirs: np.ndarray,
                     names: Tuple[str, ...]) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Like :meth:`cast`, plus the unit shading normal (N, 3) at each hit (NaN on a miss).

        The shading normal is the interpolated vertex normal the BSDFs use, i.e. the normal of
        the smooth surface the mesh approximates (not the facet's).
        """
        return self._cast(origins_cm, dirs, names, normals=True)

    def _cast(self, origins_cm, dirs, names, normals: bool):
        mi = self._mi
        o = np.asarray(origins_cm, float).reshape(-1, 3) * CM_TO_M
        d = np.asarray(dirs, float).reshape(-1, 3)
        n = len(o)
        t = np.full(n, np.inf)
        part = np.full(n, -1, np.int64)
        nrm = np.full((n, 3), np.nan)
        if n == 0:
            return t, part, nrm
        ids = self._ids()
        if self.variant.startswith("scalar"):
            for i in range(n):
                si = self._scene.ray_intersect(mi.Ray3f(mi.Point3f(*o[i]), mi.Vector3f(*d[i])))
                if si.is_valid():
                    t[i] = float(si.t) / CM_TO_M
                    sid = si.shape.id()
                    part[i] = names.index(sid) if sid in names else -1
                    if normals:
                        nrm[i] = [float(si.sh_frame.n[k]) for k in range(3)]
            return t, part, nrm
        dr = __import__("drjit")
        o32, d32 = o.astype(np.float32), d.astype(np.float32)
        ray = mi.Ray3f(mi.Point3f(o32[:, 0], o32[:, 1], o32[:, 2]), mi.Vector3f(d32[:, 0], d32[:, 1], d32[:, 2]))
        # one kernel for every field read back (each separate read would re-run the intersection);
        # the preliminary record has the hit distance and shape, the normals need the interaction
        pi = self._scene.ray_intersect_preliminary(ray)
        fields = [pi.is_valid(), pi.t, dr.reinterpret_array(mi.UInt32, pi.shape)]
        if normals:
            n_sh = pi.compute_surface_interaction(ray).sh_frame.n
            fields += [n_sh.x, n_sh.y, n_sh.z]
        dr.eval(*fields)
        valid = np.array(fields[0], dtype=bool)
        tt = np.array(fields[1], dtype=np.float64)
        sid = np.array(fields[2], dtype=np.int64)
        t[valid] = tt[valid] / CM_TO_M
        for k, name in enumerate(names):
            if name in ids:
                part[valid & (sid == ids[name])] = k
        if normals:
            sn = np.stack([np.array(f, dtype=np.float64) for f in fields[3:]], axis=-1)
            nrm[valid] = sn[valid] / np.linalg.norm(sn[valid], axis=1, keepdims=True)
        return t, part, nrm
