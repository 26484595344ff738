"""A frame's walk: unit renders through the disk cache, then laser power, ambient and the sensor or colour camera.

A frame is a pure function of (parameters, mirror angle, spp, seed):

* the Mitsuba seeds of the two passes and the sensor's two noise draws come from
  ``numpy.random.SeedSequence([seed, angle bits...])`` (:func:`angle_words`: the angle's float64
  bits, so every angle has independent noise and the same angle always the same);
* the unit renders (laser pass at 1 W in band, ambient pass(es) at unit sky radiance) and the truth
  go through the disk cache (:mod:`scenes.cache`, key :func:`scenes.render_key.cache_fields`);
  laser power, ambient, spectra and sensor are applied afterwards.

``frame.image = sensor(ambient + laser)`` and ``frame.background = sensor(ambient)`` with
independent noise draws; both share the ambient render (its Monte Carlo noise is therefore common to
both, like a fixed pattern). The colour camera turns the (H, W, 3) channel radiances into 8-bit
photographs (:class:`scenes.colour_camera.ColourCamera`); a textured frame of it has three ambient
bands (:func:`scenes.loading.band_weights`, rendered with the same Mitsuba seed).

The functions take a scene's pieces; two of them are callables of :class:`scenes.Scene`, which keeps
their results: ``load(spp)`` (:func:`scenes.loading.load`, once per scene) and ``visible(theta)``
(:func:`scenes.masks.visible`, the last angle's).
"""

from __future__ import annotations

import dataclasses
import struct
from typing import Any, Callable, Dict, Optional

import numpy as np

from . import _checks, cache as _cache, colour_camera, description, distractors, masks, materials, radiometry, sampling
from . import subsurface
from . import variant as _variant
from .frame import Frame, Truth
from .laser import profile as laser_profile
from .loading import filter_kwargs, line_spread
from .passes import own_passes, profile_mode, render_pass, sample_counts
from .render_key import cache_fields
from .rig import Rig
from .sensor import SensorModel
from .truth import false_stripe_mask, ground_truth

__all__ = ["angle_words", "laser_power_inband_w", "sky_radiance_inband", "channel_laser_power_w",
           "channel_sky_radiance", "unit_passes", "truth", "false_mask", "cast_truth", "render", "is_cached"]


def angle_words(theta: float) -> list:
    """The two 32-bit words of the float64 ``theta`` (deg), for ``numpy.random.SeedSequence``.

    Examples
    --------
    >>> angle_words(0.0) == angle_words(-0.0) == [0, 0]
    True
    >>> angle_words(1.0)
    [0, 1072693248]
    """
    bits = struct.unpack("<Q", struct.pack("<d", theta + 0.0))[0]  # +0.0 folds -0.0 into 0.0
    return [bits & 0xFFFFFFFF, bits >> 32]


def laser_power_inband_w(params: Dict[str, Any]) -> float:
    """Laser power through the filter (W) of a scene with ``params``."""
    return radiometry.inband_laser_power_w(params["laser_power_mw"], params["laser_wavelength_nm"],
                                           **filter_kwargs(params))


def sky_radiance_inband(params: Dict[str, Any]) -> float:
    """In-band ambient sky radiance (W m⁻² sr⁻¹) of a scene with ``params``."""
    return radiometry.inband_sky_radiance(params["ambient_lux"], params["ambient_illuminant"], **filter_kwargs(params))


def channel_laser_power_w(params: Dict[str, Any]) -> np.ndarray:
    """``camera="rgb"``: effective laser power per colour channel (W), (3,)
    (:func:`scenes.colour_camera.channel_laser_power_w`)."""
    return colour_camera.channel_laser_power_w(params["laser_power_mw"], params["laser_wavelength_nm"],
                                               params["filter"], **filter_kwargs(params))


def channel_sky_radiance(params: Dict[str, Any]) -> np.ndarray:
    """``camera="rgb"``: effective ambient sky radiance per colour channel (W m⁻² sr⁻¹), (3,)."""
    return colour_camera.channel_sky_radiance(params["ambient_lux"], params["ambient_illuminant"], params["filter"],
                                              **filter_kwargs(params))


def truth(laser_scene, rig: Rig, theta: float, fan_deg: float, centre_points_cm=None) -> Truth:
    """Ground truth of the frame at ``theta`` by ray casting ``laser_scene`` (posed for ``theta``);
    ``centre_points_cm`` (H, W, 3): :func:`scenes.masks.visible`'s points, when already cast."""
    return ground_truth(rig, theta, lambda o, d: laser_scene.cast(o, d, masks.PARTS), fan_deg=fan_deg,
                        object_part=masks.PARTS.index("object"), centre_points_cm=centre_points_cm)


def false_mask(laser_scene, rig: Rig, theta: float, fan_deg: float) -> np.ndarray:
    """A shiny frame's false-stripe mask (:func:`scenes.truth.false_stripe_mask`), (H, W) bool."""
    return false_stripe_mask(rig, theta, lambda o, d: laser_scene.cast_normals(o, d, masks.PARTS),
                             fan_deg=fan_deg, object_part=masks.PARTS.index("object"))


def cast_truth(params: Dict[str, Any], rig: Rig, theta: float, laser_scene, visible: Callable) -> Truth:
    """A frame's ground truth by ray casting only, its false-stripe mask included (:meth:`scenes.Scene.truth`):
    the same arrays as the rendered frame's."""
    laser_scene.set_pose(description.pose_updates(rig, theta))
    t = truth(laser_scene, rig, theta, params["laser_fan_deg"], visible(theta)[0])
    mask = (false_mask(laser_scene, rig, theta, params["laser_fan_deg"]) if params["material"] in materials.SHINY
            else np.zeros((params["height"], params["width"]), bool))
    return dataclasses.replace(t, false_mask=mask)


def _spread(laser_scene, rig: Rig, theta: float, laser: np.ndarray, table) -> np.ndarray:
    """``translucency = "profile"``: the stand-in's laser pass spread by the line-spread kernels."""
    rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float), indexing="ij")
    o, d = rig.pixel_rays(cols, rows, theta)
    t, part, nrm = laser_scene.cast_normals(o.reshape(-1, 3), d.reshape(-1, 3), masks.PARTS)
    shape = (rig.height, rig.width)
    with np.errstate(invalid="ignore"):
        points = o + np.where(np.isfinite(t), t, np.nan).reshape(shape)[..., None] * d
    on_object = part.reshape(shape) == masks.PARTS.index("object")
    _, sheet_normal = rig.laser_plane(theta)
    return subsurface.spread(laser, points, nrm.reshape(shape + (3,)), on_object, sheet_normal=sheet_normal,
                             laser_origin_cm=rig.laser_origin_cm(theta), camera_cm=rig.camera_center_cm(theta),
                             table=table, albedo=table.diffuse_reflectance)


def unit_passes(name: str, params: Dict[str, Any], rig: Rig, theta: float, spp, seed: int, seeds, *,
                load: Callable, visible: Callable) -> Dict[str, np.ndarray]:
    """The unit renders and truth of a frame, from the cache or rendered (and stored).

    Returns
    -------
    dict
        ``laser`` (H, W) and ``ambient`` (H, W) or (H, W, bands) float32 radiances at unit power and
        sky radiance; the truth's ``columns``, ``points_cm``, ``on_object``, ``part``; a shiny
        material's ``false_mask``.
    """
    use_cache = params["cache"]
    root = _cache.cache_root(params["cache_dir"])
    k = _cache.key(cache_fields(name, params, rig, theta, spp, seed, _variant.active_variant()))
    required = {"laser", "ambient", "columns", "points_cm", "on_object", "part"}
    shiny = params["material"] in materials.SHINY
    if shiny:
        required.add("false_mask")
    if use_cache:
        hit = _cache.load(root, k)
        if hit is not None and required <= set(hit):
            return hit
    laser_scene, *ambient_scenes = load(spp)
    pose = description.pose_updates(rig, theta)
    laser_seed = int(seeds[0].generate_state(1)[0])
    passes, counts, ambient_spp = sample_counts(name, params, spp)
    if len(passes) == 1 and passes == own_passes(params) and passes[0].pixels == "all":
        laser = laser_scene.render(pose, counts[0], laser_seed)  # the scene's own integrator
    else:  # the passes' sum, each on its pixels
        tan_x = laser_profile(params["line_fwhm_mrad"], params["laser_fan_deg"]).tan_half_x
        acc = np.zeros((params["height"], params["width"]), np.float64)
        for p, n, mask in zip(passes, counts, masks.pass_pixels(passes, lambda: visible(theta), rig, theta, tan_x)):
            acc += render_pass(laser_scene, pose, p, mask, n, laser_seed)
        laser = acc.astype(np.float32)
    if profile_mode(params):
        laser = _spread(laser_scene, rig, theta, laser, line_spread(params))
    ambient_seed = int(seeds[1].generate_state(1)[0])
    bands = [a.render(pose, ambient_spp, ambient_seed) for a in ambient_scenes]
    ambient = bands[0] if len(bands) == 1 else np.stack(bands, axis=-1)

    t = truth(laser_scene, rig, theta, params["laser_fan_deg"], visible(theta)[0])
    out = {"laser": laser, "ambient": ambient, "columns": t.columns, "points_cm": t.points_cm,
           "on_object": t.on_object, "part": t.part}
    if shiny:
        out["false_mask"] = false_mask(laser_scene, rig, theta, params["laser_fan_deg"])
    if use_cache:
        _cache.store(root, k, out)
    return out


def _arguments(params: Dict[str, Any], mirror_angle_deg, spp, seed):
    """``(theta, spp, seed)`` of a render, checked, defaults from ``params``."""
    theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
    spp = params["spp"] if spp is None else spp
    if spp != sampling.AUTO:
        spp = _checks.positive_int("spp", spp)
    seed = params["seed"] if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"`seed` must be an integer >= 0, got {seed!r}")
    return theta, spp, int(seed)


def render(name: str, params: Dict[str, Any], rig: Rig, mirror_angle_deg: float, spp, seed, noise_draw: int, *,
           sensor: SensorModel, camera: Optional[colour_camera.ColourCamera], load: Callable,
           visible: Callable) -> Frame:
    """One frame of the scene ``name`` with ``params`` (:meth:`scenes.Scene.render`).

    Parameters
    ----------
    name, params, rig
        The scene: :class:`scenes.Scene`'s ``name``, ``params`` and ``rig`` (at its image size).
    mirror_angle_deg : float
        Mirror angle θ (deg); the camera and the laser sheet turn by 2θ.
    spp : int, "auto" or None
        Samples per pixel of every laser pass (None: ``params['spp']``; ``"auto"``: the counts of
        :mod:`scenes.sampling`, see :func:`scenes.passes.sample_counts`); the ambient pass always uses
        ``params['ambient_spp']``.
    seed : int or None
        Seed (None: ``params['seed']``); with the angle it fixes every random number.
    noise_draw : int
        Which independent draw of the sensor noise (shot and read noise of the image and the
        background) to take, >= 0. ``0`` is the draw fixed by ``seed`` and the angle; ``k > 0`` takes
        the draw seeded by ``SeedSequence([seed, angle bits..., k])``. The Mitsuba renders (and their
        Monte Carlo noise) are the same for every draw, so every draw reuses the cached unit renders.
    sensor : SensorModel
        :attr:`scenes.Scene.sensor`.
    camera : ColourCamera or None
        :attr:`scenes.Scene.colour_camera`.
    load, visible : callable
        :meth:`scenes.Scene._load` and :meth:`scenes.Scene._visible` (see the module's docstring).

    Returns
    -------
    Frame
    """
    theta, spp, seed = _arguments(params, mirror_angle_deg, spp, seed)
    if isinstance(noise_draw, bool) or not isinstance(noise_draw, (int, np.integer)) or noise_draw < 0:
        raise ValueError(f"`noise_draw` must be an integer >= 0, got {noise_draw!r}")
    seeds = np.random.SeedSequence([seed, *angle_words(theta)]).spawn(4)
    unit = unit_passes(name, params, rig, theta, spp, seed, seeds, load=load, visible=visible)
    if noise_draw:
        seeds = seeds[:2] + np.random.SeedSequence([seed, *angle_words(theta), int(noise_draw)]).spawn(4)[2:]
    false = (np.asarray(unit["false_mask"], bool) if "false_mask" in unit else np.zeros(unit["laser"].shape, bool))
    t = Truth(np.asarray(unit["columns"], float), np.asarray(unit["points_cm"], float),
              np.asarray(unit["on_object"], bool), np.asarray(unit["part"], np.int8), false)
    rng_image = np.random.Generator(np.random.PCG64(seeds[2]))
    rng_background = np.random.Generator(np.random.PCG64(seeds[3]))
    extra = distractors.for_scene(params)  # None: the frame as rendered (scenes.distractors)
    t = distractors.truth_without(t, extra)
    if camera is not None:
        return _colour_frame(unit, params, camera, rng_image, rng_background, t, theta, extra)
    laser = (unit["laser"].astype(np.float64) * laser_power_inband_w(params)).astype(np.float32)
    ambient = (unit["ambient"].astype(np.float64) * sky_radiance_inband(params)).astype(np.float32)
    laser, ambient = distractors.apply(extra, laser, ambient, np.array([distractors.dn_radiance(sensor)]))
    radiance = (ambient.astype(np.float64) + laser).astype(np.float32)
    blur, q = params["defocus_px"], params["jpeg_quality"]
    seen, seen_ambient = ((radiance, ambient) if blur == 0 else
                          (colour_camera.defocus(radiance, blur), colour_camera.defocus(ambient, blur)))
    image = sensor.capture(seen, rng_image)
    background = sensor.capture(seen_ambient, rng_background)
    if q is not None:
        image, background = colour_camera.jpeg_round_trip(image, q), colour_camera.jpeg_round_trip(background, q)
    image, background = distractors.draw(extra, image), distractors.draw(extra, background)
    return Frame(image=image, background=background, radiance=radiance, laser_radiance=laser, truth=t,
                 mirror_angle_deg=theta, variant=_variant.active_variant())


def _colour_frame(unit, params, camera, rng_image, rng_background, t: Truth, theta: float,
                  extra: Optional[distractors.Distractor] = None) -> Frame:
    """The colour camera's frame from the unit renders (one ambient band shared by the channels,
    or three), with the scene's distractor ``extra`` (None: none)."""
    laser = (unit["laser"].astype(np.float64)[..., None] * channel_laser_power_w(params)).astype(np.float32)
    amb = unit["ambient"].astype(np.float64)
    if amb.ndim == 2:
        amb = amb[..., None]
    ambient = (amb * channel_sky_radiance(params)).astype(np.float32)
    if extra is not None:
        per_dn = camera.sensor.gain_e_per_dn / camera.electrons_per_radiance()
        laser, ambient = distractors.apply(extra, laser, ambient, per_dn)
    radiance = (ambient.astype(np.float64) + laser).astype(np.float32)
    rgb = distractors.draw(extra, camera.capture(radiance, rng_image))
    rgb_background = distractors.draw(extra, camera.capture(ambient, rng_background))
    return Frame(image=colour_camera.luma(rgb), background=colour_camera.luma(rgb_background), radiance=radiance,
                 laser_radiance=laser, truth=t, mirror_angle_deg=theta, variant=_variant.active_variant(),
                 rgb=rgb, rgb_background=rgb_background)


def is_cached(name: str, params: Dict[str, Any], rig: Rig, mirror_angle_deg: float, spp=None, seed=None) -> bool:
    """Whether the render cache holds the file of :func:`render`'s frame (:meth:`scenes.Scene.is_cached`)."""
    if not params["cache"]:
        return False
    theta = _checks.real("mirror_angle_deg", mirror_angle_deg)
    spp = params["spp"] if spp is None else spp
    if spp != sampling.AUTO:
        spp = _checks.positive_int("spp", spp)
    seed = int(params["seed"] if seed is None else seed)
    k = _cache.key(cache_fields(name, params, rig, theta, spp, seed, _variant.active_variant()))
    return _cache.path(_cache.cache_root(params["cache_dir"]), k).exists()
