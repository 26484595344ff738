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
"""

from __future__ import annotations

import contextlib
from typing import Dict, Optional, Tuple

import numpy as np

from . import variant as _variant
from .rig import CM_TO_M

__all__ = ["materialise", "LoadedScene", "interrupted", "light_indirect", "camera_paths"]


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


def light_indirect(mi, scene, spp: int, seed: int, depth: int) -> np.ndarray:
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
    """
    import drjit as dr

    if int(depth) < 2:
        raise ValueError(f"`depth` must be >= 2 (projector, a surface, the camera), got {depth!r}")
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
    value = (throughput * sensor_weight * _adjoint_shading(mi, dr, si, to_camera.d, local, wi_geo)
             * si.bsdf(ray).eval(ctx, si, local, active) / spp)
    value = _first_channel(dr.select(active, value, 0.0))
    x = mi.Int32(dr.floor(ds.uv.x))
    y = mi.Int32(dr.floor(ds.uv.y))
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
    pixels = np.asarray(pixels, bool)
    if pixels.shape != (height, width):
        raise ValueError(f"`pixels` must have the film's shape {(height, width)}, got {pixels.shape}")
    index = np.flatnonzero(pixels).astype(np.uint32)
    if len(index) == 0:
        _check_spp(spp)
        return np.zeros((height, width), np.float32)
    sampler, spp = _wavefront_sampler(sensor, spp, seed, lambda n: len(index) * n)
    lanes = np.repeat(index, spp)
    pixel = mi.UInt32(lanes)
    position = mi.Point2f(mi.Float(pixel % width), mi.Float(pixel // width)) + sampler.next_2d()
    ray, weight = sensor.sample_ray_differential(mi.Float(0.0), mi.Float(0.0),
                                                 position / mi.ScalarVector2f(width, height), mi.Point2f(0.5))
    ray.scale_differential(dr.rsqrt(spp))
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
