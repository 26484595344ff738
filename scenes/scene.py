"""``Scene``: one object x material with its parameters; renders frames.

A frame is a pure function of (parameters, mirror angle, spp, seed):

* the Mitsuba seeds of the two passes and the sensor's two noise draws come from
  ``numpy.random.SeedSequence([seed, angle bits...])`` (the angle's float64 bits,
  so every angle has independent noise and the same angle always the same);
* loaded Mitsuba scenes are kept only as a cache and re-posed completely for
  every frame;
* unit renders and truth go through the disk cache (:mod:`scenes.cache`); laser
  power, ambient, spectra and sensor are applied afterwards.

``frame.image = sensor(ambient + laser)`` and ``frame.background = sensor(ambient)``
with independent noise draws; both share the ambient render (its Monte Carlo
noise is therefore common to both, like a fixed pattern).

``translucency = "profile"`` (translucent materials): both passes render the opaque stand-in
(:func:`scenes.materials.stand_in_bsdf` of the material's total diffuse reflectance), and the laser pass is then
spread along each row by the material's line-spread kernels (:func:`scenes.subsurface.spread`, with the
surface point and normal of every pixel from one batched ray cast).

Textures and the colour camera (``*_texture``, ``camera="rgb"``): the laser pass sees each
textured surface's albedo at the laser's wavelength; the ambient pass is rendered once per
*band*: one band (the filter's, or, without textures, the one render every channel shares,
scaled per channel) or, for a textured frame of the colour camera, three (one per channel, each
with the texture's albedo averaged over illuminant x filter x that channel's sensitivity; the
three use the same Mitsuba seed). The colour camera then turns the (H, W, 3) channel radiances into
8-bit photographs (:class:`scenes.colour_camera.ColourCamera`).
"""

from __future__ import annotations

import dataclasses
import struct
import sys
from typing import Any, Dict, Iterable, Iterator, Optional, Tuple

import numpy as np

from . import (_checks, cache as _cache, colour_camera, description, materials, objects, radiometry, sampling,
               subsurface, textures)
from . import variant as _variant
from .frame import Frame, Truth
from .laser import profile as _laser_profile
from .params import RENDER_KEYS, SENSOR_KEYS, textured
from .rig import Rig
from .sensor import SensorModel
from .truth import false_stripe_mask, ground_truth

__all__ = ["Scene", "render_pass"]

_PARTS = ("backdrop", "object", "support")  # Mitsuba shape ids, in the order of frame.PARTS


def _mitsuba_versions():
    """Versions of the renderer, read from the modules themselves (works
    without package metadata, e.g. from an unpacked wheel)."""
    import drjit
    import mitsuba

    return mitsuba.__version__, drjit.__version__


def _angle_words(theta: float):
    bits = struct.unpack("<Q", struct.pack("<d", theta + 0.0))[0]  # +0.0 folds -0.0 into 0.0
    return [bits & 0xFFFFFFFF, bits >> 32]


#: :meth:`Scene.lit_pixels`: a depth step (cm) between neighbouring pixel centres that makes a silhouette.
SILHOUETTE_JUMP_CM = 1.0
#: :meth:`Scene.lit_pixels`: silhouette pixels within this many frustum half-widths of the sheet are rendered.
SILHOUETTE_MARGIN = 5.0

#: Version of the camera-path passes rendered on their pixels only (:func:`_on_pixels`; cache key).
CAMERA_PATHS_VERSION = 1


def _on_pixels(p: description.LaserPass) -> bool:
    """True when laser pass ``p`` is rendered on its pixels only (:func:`scenes.backend.camera_paths`):
    a ``path`` pass on a part of the image, or one of :data:`scenes.description.DIRECT_DEPTH`, whose
    light is only where the laser's frustum meets a visible surface (:meth:`Scene.lit_pixels`)."""
    return p.kind == "path" and (p.pixels != "all" or p.max_depth == description.DIRECT_DEPTH)


def render_pass(laser_scene, pose: Dict[str, np.ndarray], laser_pass: description.LaserPass,
                pixels: Optional[np.ndarray], spp: int, seed: int) -> np.ndarray:
    """One laser pass as :meth:`Scene.render` renders it, float64 (H, W), zero off ``pixels``.

    A camera-path pass with ``pixels`` (:meth:`Scene.pass_pixels`) is rendered on those pixels only
    (:func:`scenes.backend.camera_paths`); a light tracer's paths land anywhere, so its whole image is
    rendered and masked. The frame's laser radiance is the sum of its passes; the sampling procedure
    (``stripebench perf sampling``) and ``stripebench perf scenes`` render a pass through here too.

    Parameters
    ----------
    laser_scene : scenes.backend.LoadedScene
    pose : dict
        :func:`scenes.description.pose_updates` of the frame.
    laser_pass : scenes.description.LaserPass
    pixels : ndarray (H, W) of bool, or None
        The pass's pixels (None: the whole image).
    spp, seed : int
    """
    img = laser_scene.render(pose, spp, seed, integrator=(laser_pass.kind, laser_pass.max_depth),
                             pixels=pixels if _on_pixels(laser_pass) else None).astype(np.float64)
    return img if pixels is None else np.where(pixels, img, 0.0)


def _grow(mask: np.ndarray) -> np.ndarray:
    """``mask`` grown by one pixel (8-neighbourhood)."""
    grown = mask.copy()
    grown[1:] |= mask[:-1]
    grown[:-1] |= mask[1:]
    rows = grown.copy()
    grown[:, 1:] |= rows[:, :-1]
    grown[:, :-1] |= rows[:, 1:]
    return grown


class Scene:
    """An object in front of its background, on its support, with material, light and sensor parameters.

    Use :func:`scenes.make` to build one (it validates the parameters).

    Attributes
    ----------
    name : str
    params : dict
        All parameters, defaults filled in.
    """

    def __init__(self, name: str, params: Dict[str, Any]):
        self.name = name
        self.params = dict(params)
        self._loaded = None

    # -- pickling: drop Mitsuba objects ---------------------------------------------
    def __getstate__(self):
        state = self.__dict__.copy()
        state["_loaded"] = None
        state.pop("_visible_memo", None)
        return state

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, material={self.params['material']!r})"

    # -- derived, cheap -----------------------------------------------------------------
    @property
    def rig(self) -> Rig:
        """The rig at this scene's image size."""
        return Rig().with_size(self.params["width"], self.params["height"])

    @property
    def sensor(self) -> SensorModel:
        """The sensor model (nominal 10 µm pixels whatever the image size)."""
        full = Rig()
        return SensorModel(pixel_pitch_um=1000.0 * full.pitch_x_mm, wavelength_nm=self.params["filter_center_nm"],
                           **{k: self.params[k] for k in SENSOR_KEYS})

    @property
    def object(self) -> objects.SceneObject:
        """Geometry of the object, its background and its support (world cm)."""
        p = self.params
        return objects.build(self.name, self.rig.zeta_deg, p["background"], p["background_distance_cm"],
                             p["support"])

    def default_angles(self) -> np.ndarray:
        """``n_angles`` mirror angles (deg, ascending) sweeping the stripe over the whole object."""
        return self.object.default_angles(self.rig.zeta_deg, self.params["n_angles"])

    def laser_power_inband_w(self) -> float:
        """Laser power through the filter (W)."""
        p = self.params
        return radiometry.inband_laser_power_w(p["laser_power_mw"], p["laser_wavelength_nm"],
                                               filter_center_nm=p["filter_center_nm"],
                                               filter_fwhm_nm=p["filter_fwhm_nm"], filter_peak=p["filter_peak"])

    def sky_radiance_inband(self) -> float:
        """In-band ambient sky radiance (W m⁻² sr⁻¹)."""
        p = self.params
        return radiometry.inband_sky_radiance(p["ambient_lux"], p["ambient_illuminant"],
                                              filter_center_nm=p["filter_center_nm"],
                                              filter_fwhm_nm=p["filter_fwhm_nm"], filter_peak=p["filter_peak"])

    def channel_laser_power_w(self) -> np.ndarray:
        """``camera="rgb"``: effective laser power per colour channel (W), (3,)
        (:func:`scenes.colour_camera.channel_laser_power_w`)."""
        p = self.params
        return colour_camera.channel_laser_power_w(p["laser_power_mw"], p["laser_wavelength_nm"], p["filter"],
                                                   **self._filter_kwargs())

    def channel_sky_radiance(self) -> np.ndarray:
        """``camera="rgb"``: effective ambient sky radiance per colour channel (W m⁻² sr⁻¹), (3,)."""
        p = self.params
        return colour_camera.channel_sky_radiance(p["ambient_lux"], p["ambient_illuminant"], p["filter"],
                                                  **self._filter_kwargs())

    def _filter_kwargs(self) -> Dict[str, float]:
        p = self.params
        return {"filter_center_nm": p["filter_center_nm"], "filter_fwhm_nm": p["filter_fwhm_nm"],
                "filter_peak": p["filter_peak"]}

    @property
    def colour_camera(self) -> Optional[colour_camera.ColourCamera]:
        """The colour camera (``camera="rgb"``), else None."""
        p = self.params
        if p["camera"] != "rgb":
            return None
        return colour_camera.ColourCamera(self.sensor, p["ambient_illuminant"], p["defocus_px"], p["jpeg_quality"])

    # -- textures -------------------------------------------------------------------------
    _SURFACES = (("backdrop", "background_texture"), ("object", "object_texture"), ("support", "support_texture"))

    def band_weights(self) -> Dict[str, Any]:
        """The (3,) basis weights of the textured surfaces' albedo (:mod:`scenes.textures`) in each pass:
        ``{"laser": w, "ambient": [w, ...]}`` (one ambient band for the mono camera, three for the colour
        camera); empty without textures."""
        p = self.params
        if not textured(p):
            return {}
        if p["camera"] == "rgb":
            W = colour_camera.channel_weighting(p["ambient_illuminant"], p["filter"], **self._filter_kwargs())
            ambient = [textures.band_weights(W[:, c]) for c in range(3)]
        else:
            t = radiometry.filter_transmission(radiometry.WAVELENGTHS_NM, p["filter_center_nm"], p["filter_fwhm_nm"],
                                               p["filter_peak"])
            ambient = [textures.band_weights(radiometry.illuminant_spd(p["ambient_illuminant"]) * t)]
        return {"laser": textures.band_weights(wavelength_nm=p["laser_wavelength_nm"]), "ambient": ambient}

    def _albedo_maps(self, weights) -> Dict[str, dict]:
        """Shape id -> Mitsuba texture dict of each textured surface for one pass's basis ``weights``."""
        p, obj = self.params, self.object
        out = {}
        for part, key in self._SURFACES:
            name = p[key]
            if name == "none" or part not in (obj.uv_to_cm or {}):
                continue
            rgb = textures.tile(name, p["texture_seed"], part)
            out[part] = textures.bitmap(textures.albedo_map(rgb, weights), obj.uv_to_cm[part],
                                        textures.tile_cm(name, p["texture_scale_cm"]))
        return out

    # -- rendering ----------------------------------------------------------------------
    def _load(self, spp: Optional[int] = None):
        from .backend import LoadedScene

        if self._loaded is None:
            _, counts, ambient_spp = self.sample_counts(spp)
            spp = counts[0]
            rig, obj, mat = self.rig, self.object, self.params["material"]
            laser = _laser_profile(self.params["line_fwhm_mrad"], self.params["laser_fan_deg"])
            albedos = {"background_albedo": self.params["background_albedo"],
                       "support_albedo": self.params["support_albedo"]}
            if self.params["support_finish"] != "matte":
                albedos["support_finish"] = self.params["support_finish"]
            if self._profile_mode():
                albedos["stand_in_albedo"] = self._line_spread().diffuse_reflectance
            weights = self.band_weights()
            if not weights:
                self._loaded = (
                    LoadedScene(description.laser_scene(rig, obj, mat, laser, 0.0, spp, **albedos)),
                    LoadedScene(description.ambient_scene(rig, obj, mat, 0.0, ambient_spp, **albedos)),
                )
            else:
                self._loaded = (
                    LoadedScene(description.laser_scene(rig, obj, mat, laser, 0.0, spp, **albedos,
                                                        albedo_maps=self._albedo_maps(weights["laser"]))),
                    *[LoadedScene(description.ambient_scene(rig, obj, mat, 0.0, ambient_spp, **albedos,
                                                            albedo_maps=self._albedo_maps(w)))
                      for w in weights["ambient"]],
                )
        return self._loaded

    def _texture_fields(self) -> Dict[str, Any]:
        """Cache-key fields of the textures and the table's finish; empty for an untextured matte
        scene (its key stays what it was)."""
        p = self.params
        out = {}
        if p["support_finish"] != "matte":
            out["support_finish"] = p["support_finish"]
        weights = self.band_weights()
        if weights:
            out["textures"] = {
                "names": {part: p[key] for part, key in self._SURFACES},
                "scale_cm": p["texture_scale_cm"], "seed": p["texture_seed"], "version": textures.TEXTURE_VERSION,
                "weights": {"laser": [float(f"{v:.12g}") for v in weights["laser"]],
                            "ambient": [[float(f"{v:.12g}") for v in w] for w in weights["ambient"]]}}
        return out

    def _cache_fields(self, theta: float, spp, seed: int, variant: str) -> Dict[str, Any]:
        passes, counts, ambient_spp = self.sample_counts(spp)
        extra = {}
        if passes != (description.LaserPass("path", description.MAX_DEPTH, "all"),):
            # keys of plain path-traced materials stay as they were (warm caches survive)
            extra["laser_passes"] = [list(p) for p in passes]
        if any(_on_pixels(p) for p in passes):
            extra["camera_paths"] = CAMERA_PATHS_VERSION
        extra.update(self._texture_fields())
        return {
            **extra,
            "scene": self.name,
            **{k: self.params[k] for k in RENDER_KEYS if k not in ("spp", "seed")},
            # one count when every laser pass has it (the keys of fixed counts stay what they were)
            "spp": counts[0] if len(set(counts)) == 1 else list(counts),
            "ambient_spp": ambient_spp,
            "seed": seed,
            "mirror_angle_deg": theta,
            "rig": dataclasses.asdict(self.rig),
            "variant": variant,
            **({"llvm_target": _variant.llvm_target()} if variant.startswith("llvm") else {}),
            "mitsuba": _mitsuba_versions()[0],
            "drjit": _mitsuba_versions()[1],
            **self._optics_fields(),
        }

    def _profile_mode(self) -> bool:
        """True for a translucent material rendered with ``translucency = "profile"``."""
        return materials.is_translucent(self.params["material"]) and self.params["translucency"] == "profile"

    def _line_spread(self) -> "subsurface.LineSpread":
        """The material's line-spread table (:func:`scenes.subsurface.table_for`; computed once, a few seconds)."""
        return subsurface.table_for(self.params["material"], self.params["cache_dir"], use_cache=self.params["cache"])

    def _optics_fields(self) -> Dict[str, Any]:
        """Cache-key fields of a translucent material: its boundary, medium (coefficients) and
        integrators, so a change of any coefficient re-renders; with ``translucency = "profile"`` the
        profile's spec and the spreading's version instead. Empty for the opaque and shiny
        materials (their keys stay what they were)."""
        mat = self.params["material"]
        if not materials.is_translucent(mat):
            return {}
        if self._profile_mode():
            return {"optics": {"translucency": "profile", "profile": subsurface.spec_for(mat).key_fields(),
                               "spread_version": subsurface.SPREAD_VERSION,
                               "stand_in": "diffuse, total diffuse reflectance of the profile, on the medium's boundary",
                               "slab_thickness_cm": description.SLAB_THICKNESS_CM,
                               "laser_passes": [list(p) for p in description.laser_passes(mat, "profile")],
                               "ambient_integrator": description.ambient_integrator(mat, "profile")}}
        return {"optics": {"bsdf": materials.bsdf(mat), "medium": materials.medium(mat),
                           "laser_passes": [list(p) for p in description.laser_passes(mat)],
                           "ambient_integrator": description.ambient_integrator(mat),
                           "slab_thickness_cm": description.SLAB_THICKNESS_CM,
                           "boundary": "shapes.medium_boundary: as is, union of pieces, or slab"}}

    def _unit_passes(self, theta: float, spp: int, seed: int, seeds) -> Dict[str, np.ndarray]:
        variant = _variant.active_variant()
        use_cache = self.params["cache"]
        root = _cache.cache_root(self.params["cache_dir"])
        k = _cache.key(self._cache_fields(theta, spp, seed, variant))
        required = {"laser", "ambient", "columns", "points_cm", "on_object", "part"}
        shiny = self.params["material"] in materials.SHINY
        if shiny:
            required.add("false_mask")
        if use_cache:
            hit = _cache.load(root, k)
            if hit is not None and required <= set(hit):
                return hit
        laser_scene, *ambient_scenes = self._load(spp)
        pose = description.pose_updates(self.rig, theta)
        laser_seed = int(seeds[0].generate_state(1)[0])
        passes, counts, ambient_spp = self.sample_counts(spp)
        if len(passes) == 1 and passes == self._own_passes() and passes[0].pixels == "all":
            laser = laser_scene.render(pose, counts[0], laser_seed)  # the scene's own integrator
        else:  # the passes' sum, each on its pixels
            acc = np.zeros((self.params["height"], self.params["width"]), np.float64)
            for p, n, mask in zip(passes, counts, self.pass_pixels(theta, passes)):
                acc += render_pass(laser_scene, pose, p, mask, n, laser_seed)
            laser = acc.astype(np.float32)
        if self._profile_mode():
            laser = self._spread(laser_scene, theta, laser)
        ambient_seed = int(seeds[1].generate_state(1)[0])
        bands = [a.render(pose, ambient_spp, ambient_seed) for a in ambient_scenes]
        ambient = bands[0] if len(bands) == 1 else np.stack(bands, axis=-1)

        truth = self._truth(laser_scene, theta)
        out = {"laser": laser, "ambient": ambient, "columns": truth.columns, "points_cm": truth.points_cm,
               "on_object": truth.on_object, "part": truth.part}
        if shiny:
            out["false_mask"] = self._false_mask(laser_scene, theta)
        if use_cache:
            _cache.store(root, k, out)
        return out

    def _spread(self, laser_scene, theta: float, laser: np.ndarray) -> np.ndarray:
        """``translucency = "profile"``: the stand-in's laser pass spread by the line-spread kernels."""
        rig = self.rig
        rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float),
                                 indexing="ij")
        o, d = rig.pixel_rays(cols, rows, theta)
        t, part, nrm = laser_scene.cast_normals(o.reshape(-1, 3), d.reshape(-1, 3), _PARTS)
        shape = (rig.height, rig.width)
        with np.errstate(invalid="ignore"):
            points = o + np.where(np.isfinite(t), t, np.nan).reshape(shape)[..., None] * d
        on_object = part.reshape(shape) == _PARTS.index("object")
        table = self._line_spread()
        _, sheet_normal = rig.laser_plane(theta)
        return subsurface.spread(laser, points, nrm.reshape(shape + (3,)), on_object, sheet_normal=sheet_normal,
                                 laser_origin_cm=rig.laser_origin_cm(theta), camera_cm=rig.camera_center_cm(theta),
                                 table=table, albedo=table.diffuse_reflectance)

    def _truth(self, laser_scene, theta: float) -> Truth:
        def cast(o, d):
            return laser_scene.cast(o, d, _PARTS)

        points = self._visible(theta)[0] if laser_scene is self._load()[0] else None
        return ground_truth(self.rig, theta, cast, fan_deg=self.params["laser_fan_deg"],
                            object_part=_PARTS.index("object"), centre_points_cm=points)

    def _false_mask(self, laser_scene, theta: float) -> np.ndarray:
        return false_stripe_mask(self.rig, theta, lambda o, d: laser_scene.cast_normals(o, d, _PARTS),
                                 fan_deg=self.params["laser_fan_deg"], object_part=_PARTS.index("object"))

    def truth(self, mirror_angle_deg: float) -> Truth:
        """The ground truth of the frame at ``mirror_angle_deg`` without rendering it (ray casting only).

        The same arrays as ``render(mirror_angle_deg).truth`` (not cached; about 0.05 s at 512x480).
        """
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        laser_scene = self._load()[0]
        laser_scene.set_pose(description.pose_updates(self.rig, theta))
        truth = self._truth(laser_scene, theta)
        shape = (self.params["height"], self.params["width"])
        false_mask = (self._false_mask(laser_scene, theta) if self.params["material"] in materials.SHINY
                      else np.zeros(shape, bool))
        return dataclasses.replace(truth, false_mask=false_mask)

    def visible_points(self, mirror_angle_deg: float):
        """First surface hit through every pixel centre (not cached).

        Returns
        -------
        points_cm : ndarray (H, W, 3), float64
            NaN where the ray hits nothing.
        on_object : ndarray (H, W), bool
        """
        points, part, _ = self._visible(mirror_angle_deg)
        return points, part == _PARTS.index("object")

    def _visible(self, mirror_angle_deg: float):
        """First hits through every pixel centre: points (H, W, 3) cm and the index into ``_PARTS`` (H, W).

        The last angle's result is kept (read-only arrays): a frame asks for it up to three times
        (:meth:`split_pixels`, :meth:`lit_pixels`, the truth)."""
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        memo = self.__dict__.get("_visible_memo")
        if memo is not None and memo[0] == theta:
            return memo[1]
        rig = self.rig
        laser_scene = self._load()[0]
        laser_scene.set_pose(description.pose_updates(rig, theta))
        rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float),
                                 indexing="ij")
        o, d = rig.pixel_rays(cols, rows, theta)
        t, part = laser_scene.cast(o.reshape(-1, 3), d.reshape(-1, 3), _PARTS)
        t = t.reshape(rig.height, rig.width)
        part = part.reshape(rig.height, rig.width)
        with np.errstate(invalid="ignore"):
            points = o + np.where(np.isfinite(t), t, np.nan)[..., None] * d
        result = (points, part, t)
        for a in result:
            a.flags.writeable = False
        self._visible_memo = (theta, result)
        return result

    def lit_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels that can see a point inside the laser's frustum, (H, W) bool: a superset of those with
        direct laser light, where a pass of :data:`scenes.description.DIRECT_DEPTH` is rendered.

        With ``u = s / |z|`` at each pixel centre's first hit (``s`` the signed distance to the sheet's
        plane, ``z`` the distance along the beam; the frustum is ``|u| <= tan_half_x`` of the
        projector), a pixel is marked when

        * its own ``u`` is inside;
        * ``u`` of it and of one of its 8 neighbours straddle the frustum (the surface between the two
          centres sweeps every ``u`` between theirs: steep and grazing surfaces);
        * it is a silhouette pixel (a neighbour's centre misses, hits another part, or hits more than
          :data:`SILHOUETTE_JUMP_CM` nearer or farther) and ``|u|`` is within
          :data:`SILHOUETTE_MARGIN` frustum widths: the limb between its centre and the silhouette,
          which no centre sees, curves away fast;

        and the marks are grown by two pixels (footprints reaching a surface no centre hits).
        ``stripebench perf lit`` renders whole images and counts the direct light that falls outside
        (none on the measured frames: docs/scenes.md).
        """
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        points, part, t = self._visible(theta)
        rig = self.rig
        rel = points - rig.laser_origin_cm(theta)
        _, normal = rig.laser_plane(theta)
        tan_x = _laser_profile(self.params["line_fwhm_mrad"], self.params["laser_fan_deg"]).tan_half_x
        h, w = part.shape
        with np.errstate(invalid="ignore", divide="ignore"):
            u = (rel @ normal) / np.abs(rel @ rig.laser_direction(theta))
            lit = np.abs(u) <= tan_x
            edge = np.zeros((h, w), bool)
            for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
                a = (slice(0, h - dy), slice(max(0, -dx), w - max(0, dx)))
                b = (slice(dy, None), slice(max(0, dx), w + min(0, dx)))
                ua, ub = u[a], u[b]
                both = (np.minimum(ua, ub) <= tan_x) & (np.maximum(ua, ub) >= -tan_x)  # False with a miss
                lit[a] |= both
                lit[b] |= both
                jump = (part[a] != part[b]) | ~(np.abs(t[a] - t[b]) <= SILHOUETTE_JUMP_CM)
                edge[a] |= jump
                edge[b] |= jump
            lit |= edge & (np.abs(u) <= SILHOUETTE_MARGIN * tan_x)
        return _grow(_grow(lit))

    def laser_passes(self) -> tuple:
        """The laser pass(es) of this scene (:class:`scenes.description.LaserPass`).

        Those of the material (:func:`scenes.description.laser_passes`), except for a path-traced
        material on a ``support_finish="polished"`` table: ``path`` on the pixels that see the table
        (:meth:`support_pixels`: the stripe and the object mirrored in the coat), ``ptracer`` on the
        others (the sheet the coat reflects onto the object, which a path tracer finds only as
        fireflies through the narrow lobe). Unbiased for the same reason as the shiny materials' split.
        """
        return self.sample_counts()[0]

    def _own_passes(self) -> tuple:
        mat = self.params["material"]
        passes = description.laser_passes(mat, "profile") if self._profile_mode() else description.laser_passes(mat)
        plain = (description.LaserPass("path", description.MAX_DEPTH, "all"),)
        if passes == plain and self.params["support"] == "table" and self.params["support_finish"] == "polished":
            return (description.LaserPass("path", description.MAX_DEPTH, "support"),
                    description.LaserPass("ptracer", description.MAX_DEPTH, "rest"))
        return passes

    def sample_counts(self, spp=None) -> Tuple[tuple, Tuple[int, ...], int]:
        """The laser passes, each one's samples per pixel and the ambient pass's, of a render at ``spp``.

        Parameters
        ----------
        spp : int or "auto", optional
            :meth:`render`'s ``spp`` (default ``params['spp']``). An integer gives every laser pass
            that count; ``"auto"`` takes the material's integrator and counts from
            :mod:`scenes.sampling` (the fixed counts where its table lacks the material or the scene's
            passes are not the material's own; a shiny object's own pass at
            :func:`scenes.sampling.object_spp` where the table has this object and geometry).
            ``ambient_spp`` likewise from ``params``.

        Returns
        -------
        passes : tuple of scenes.description.LaserPass
        laser_spp : tuple of int
            One count per pass.
        ambient_spp : int

        Examples
        --------
        >>> import scenes
        >>> s = scenes.make("cone", material="skin", spp="auto", ambient_spp=4)
        >>> [tuple(p) for p in s.sample_counts()[0]], s.sample_counts()[1:]
        ([('volpath', 64, 'all')], ((16,), 4))
        >>> s.sample_counts(32)[1]
        (32,)
        """
        spp = self.params["spp"] if spp is None else spp
        material = self.params["material"]
        passes = self._own_passes()
        if spp == sampling.AUTO:
            choice = sampling.laser_choice(material)
            if choice is not None and passes == description.laser_passes(material):
                kind, counts = choice
                if kind in ("split", "split_hybrid"):
                    n = sampling.object_spp(material, sampling.case_key(self.name, self.params["background"],
                                                                         self.params["support"]))
                    counts = counts if n is None else (n,) + counts[1:]
                if kind == "hybrid":
                    passes = description.hybrid_passes()
                elif kind == "split_hybrid":
                    passes = description.split_hybrid_passes()
                elif kind != "split":
                    passes = (description.LaserPass(kind, description.MAX_DEPTH, "all"),)
            else:
                counts = (sampling.FIXED_SPP,) * len(passes)
        else:
            counts = (_checks.positive_int("spp", spp),) * len(passes)
        if len(counts) != len(passes):
            raise ValueError(f"scenes.sampling gives {len(counts)} counts for {len(passes)} laser passes "
                             f"of {material!r}: rerun `stripebench perf sampling --write`")
        amb = self.params["ambient_spp"]
        ambient_spp = sampling.ambient_spp(material) if amb == sampling.AUTO else int(amb)
        return passes, tuple(counts), ambient_spp

    def pass_pixels(self, mirror_angle_deg: float, passes: Optional[tuple] = None) -> list:
        """The pixels each laser pass contributes to at ``mirror_angle_deg``: one (H, W) bool mask per
        pass, or None for the whole image.

        A pass's ``pixels`` (:class:`scenes.description.LaserPass`: :meth:`split_pixels`,
        :meth:`support_pixels` or their complements), intersected for a pass of
        :data:`scenes.description.DIRECT_DEPTH` with :meth:`lit_pixels`. ``path`` passes with a mask
        are rendered on those pixels only (:func:`scenes.backend.camera_paths`); the light tracers'
        renders are masked.

        Parameters
        ----------
        mirror_angle_deg : float
        passes : tuple of LaserPass, optional
            Default :meth:`laser_passes`.
        """
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        passes = self.laser_passes() if passes is None else passes
        masks = {"all": None}
        if any(p.pixels in ("support", "rest") for p in passes):
            on_support = self.support_pixels(theta)
            masks.update(support=on_support, rest=~on_support)
        if any(p.pixels in ("object", "other") for p in passes):
            on_object = self.split_pixels(theta)
            masks.update(object=on_object, other=~on_object)
        out = []
        for p in passes:
            mask = masks[p.pixels]
            if p.kind == "path" and p.max_depth == description.DIRECT_DEPTH:
                lit = self.lit_pixels(theta)
                mask = lit if mask is None else mask & lit
            out.append(mask)
        return out

    def support_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels whose centre ray hits the table, grown by one pixel (8-neighbourhood), (H, W) bool."""
        _, part, _ = self._visible(mirror_angle_deg)
        return _grow(part == _PARTS.index("support"))

    def split_pixels(self, mirror_angle_deg: float) -> np.ndarray:
        """Pixels a ``"split"`` laser pass renders with ``path`` (the others with ``ptracer``).

        The pixels whose centre ray hits the object, grown by one pixel (8-neighbourhood), so that
        pixels the silhouette crosses, which see part of the object's highlight, are path traced too
        (light tracing renders a glossy highlight with fireflies).

        Returns
        -------
        ndarray (H, W), bool
        """
        _, on_object = self.visible_points(mirror_angle_deg)
        return _grow(on_object)

    def render(self, mirror_angle_deg: float, *, spp: Optional[int] = None, seed: Optional[int] = None,
               noise_draw: int = 0) -> Frame:
        """Render one frame.

        Parameters
        ----------
        mirror_angle_deg : float
            Mirror angle θ (deg); the camera and the laser sheet turn by 2θ.
        spp : int or "auto", optional
            Samples per pixel of every laser pass (default ``params['spp']``; ``"auto"``: the
            counts of :mod:`scenes.sampling`, see :meth:`sample_counts`); the ambient pass always
            uses ``params['ambient_spp']``.
        seed : int, optional
            Seed (default ``params['seed']``); with the angle it fixes every random number.
        noise_draw : int, optional
            Which independent draw of the sensor noise (shot and read noise of the image and the
            background) to take, >= 0. ``0`` (default) is the draw fixed by ``seed`` and the angle;
            ``k > 0`` takes the draw seeded by ``SeedSequence([seed, angle bits..., k])``. The
            Mitsuba renders (and their Monte Carlo noise) are the same for every draw, so every draw
            reuses the cached unit renders.

        Returns
        -------
        Frame
        """
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        spp = self.params["spp"] if spp is None else spp
        if spp != sampling.AUTO:
            spp = _checks.positive_int("spp", spp)
        seed = self.params["seed"] if seed is None else seed
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ValueError(f"`seed` must be an integer >= 0, got {seed!r}")
        if isinstance(noise_draw, bool) or not isinstance(noise_draw, (int, np.integer)) or noise_draw < 0:
            raise ValueError(f"`noise_draw` must be an integer >= 0, got {noise_draw!r}")
        seeds = np.random.SeedSequence([int(seed), *_angle_words(theta)]).spawn(4)
        unit = self._unit_passes(theta, spp, int(seed), seeds)
        if noise_draw:
            seeds = seeds[:2] + np.random.SeedSequence([int(seed), *_angle_words(theta), int(noise_draw)]).spawn(4)[2:]
        false_mask = (np.asarray(unit["false_mask"], bool) if "false_mask" in unit
                      else np.zeros(unit["laser"].shape, bool))
        truth = Truth(np.asarray(unit["columns"], float), np.asarray(unit["points_cm"], float),
                      np.asarray(unit["on_object"], bool), np.asarray(unit["part"], np.int8), false_mask)
        rng_image = np.random.Generator(np.random.PCG64(seeds[2]))
        rng_background = np.random.Generator(np.random.PCG64(seeds[3]))
        camera = self.colour_camera
        if camera is not None:
            return self._colour_frame(unit, camera, rng_image, rng_background, truth, theta)
        laser = (unit["laser"].astype(np.float64) * self.laser_power_inband_w()).astype(np.float32)
        ambient = (unit["ambient"].astype(np.float64) * self.sky_radiance_inband()).astype(np.float32)
        radiance = (ambient.astype(np.float64) + laser).astype(np.float32)
        sensor = self.sensor
        blur, q = self.params["defocus_px"], self.params["jpeg_quality"]
        seen, seen_ambient = ((radiance, ambient) if blur == 0 else
                              (colour_camera.defocus(radiance, blur), colour_camera.defocus(ambient, blur)))
        image = sensor.capture(seen, rng_image)
        background = sensor.capture(seen_ambient, rng_background)
        if q is not None:
            image, background = colour_camera.jpeg_round_trip(image, q), colour_camera.jpeg_round_trip(background, q)
        return Frame(image=image, background=background, radiance=radiance, laser_radiance=laser, truth=truth,
                     mirror_angle_deg=theta, variant=_variant.active_variant())

    def _colour_frame(self, unit, camera, rng_image, rng_background, truth, theta) -> Frame:
        """The colour camera's frame from the unit renders (one ambient band shared by the channels,
        or three)."""
        laser = (unit["laser"].astype(np.float64)[..., None] * self.channel_laser_power_w()).astype(np.float32)
        amb = unit["ambient"].astype(np.float64)
        if amb.ndim == 2:
            amb = amb[..., None]
        ambient = (amb * self.channel_sky_radiance()).astype(np.float32)
        radiance = (ambient.astype(np.float64) + laser).astype(np.float32)
        rgb = camera.capture(radiance, rng_image)
        rgb_background = camera.capture(ambient, rng_background)
        return Frame(image=colour_camera.luma(rgb), background=colour_camera.luma(rgb_background), radiance=radiance,
                     laser_radiance=laser, truth=truth, mirror_angle_deg=theta, variant=_variant.active_variant(),
                     rgb=rgb, rgb_background=rgb_background)

    def is_cached(self, mirror_angle_deg: float, *, spp: Optional[int] = None, seed: Optional[int] = None) -> bool:
        """Whether the render cache holds a file for :meth:`render`'s frame at these arguments.

        False when the cache is off. Checks only that the file exists (no loading: a damaged file
        still counts; :meth:`render` re-renders it). Imports Mitsuba (the key names its version).
        """
        if not self.params["cache"]:
            return False
        theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
        spp = self.params["spp"] if spp is None else spp
        if spp != sampling.AUTO:
            spp = _checks.positive_int("spp", spp)
        seed = int(self.params["seed"] if seed is None else seed)
        k = _cache.key(self._cache_fields(theta, spp, seed, _variant.active_variant()))
        return _cache.path(_cache.cache_root(self.params["cache_dir"]), k).exists()

    def scan(self, angles: Iterable[float], *, spp: Optional[int] = None, seed: Optional[int] = None,
             progress: bool = True) -> Iterator[Frame]:
        """Yield :meth:`render` frames for each mirror angle, with a tqdm bar on stderr."""
        from tqdm import tqdm

        angles = [float(a) for a in np.atleast_1d(np.asarray(angles, float))]
        bar = tqdm(angles, desc=f"{self.name}/{self.params['material']}", unit="frame", file=sys.stderr,
                   disable=not progress, leave=False)
        for a in bar:
            yield self.render(a, spp=spp, seed=seed)
