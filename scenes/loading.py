"""The Mitsuba scenes of a :class:`scenes.Scene`: its laser pass and one ambient pass per band, textures included.

Textures (``*_texture``): the laser pass sees each textured surface's albedo at the laser's
wavelength; the ambient pass is loaded once per *band*: one (the filter's) for the mono camera, three
(one per channel) for the colour camera (:func:`band_weights`). ``translucency = "profile"``: both
passes hold the opaque stand-in of the material (:func:`line_spread`).
"""

from __future__ import annotations

from typing import Any, Dict

from . import colour_camera, description, objects, radiometry, subsurface, textures
from .laser import profile as laser_profile
from .params import textured
from .passes import profile_mode, sample_counts
from .rig import Rig

__all__ = ["SURFACES", "filter_kwargs", "band_weights", "albedo_maps", "line_spread", "load"]

#: (Mitsuba shape id, texture parameter) of each surface that can be textured.
SURFACES = (("backdrop", "background_texture"), ("object", "object_texture"), ("support", "support_texture"))


def filter_kwargs(params: Dict[str, Any]) -> Dict[str, float]:
    """The interference filter's keyword arguments (centre, FWHM in nm, peak) from a scene's ``params``."""
    return {"filter_center_nm": params["filter_center_nm"], "filter_fwhm_nm": params["filter_fwhm_nm"],
            "filter_peak": params["filter_peak"]}


def band_weights(params: Dict[str, Any]) -> Dict[str, Any]:
    """The (3,) basis weights of the textured surfaces' albedo (:mod:`scenes.textures`) in each pass:
    ``{"laser": w, "ambient": [w, ...]}`` (one ambient band for the mono camera, three for the colour
    camera); empty without textures.

    Examples
    --------
    >>> import scenes
    >>> band_weights(scenes.make("cone").params)
    {}
    >>> w = band_weights(scenes.make("cone", object_texture="wood", camera="rgb").params)
    >>> w["laser"].shape, len(w["ambient"])
    ((3,), 3)
    """
    p = params
    if not textured(p):
        return {}
    if p["camera"] == "rgb":
        W = colour_camera.channel_weighting(p["ambient_illuminant"], p["filter"], **filter_kwargs(p))
        ambient = [textures.band_weights(W[:, c]) for c in range(3)]
    else:
        t = radiometry.filter_transmission(radiometry.WAVELENGTHS_NM, p["filter_center_nm"], p["filter_fwhm_nm"],
                                           p["filter_peak"])
        ambient = [textures.band_weights(radiometry.illuminant_spd(p["ambient_illuminant"]) * t)]
    return {"laser": textures.band_weights(wavelength_nm=p["laser_wavelength_nm"]), "ambient": ambient}


def albedo_maps(params: Dict[str, Any], obj: objects.SceneObject, weights) -> Dict[str, dict]:
    """Shape id -> Mitsuba texture dict of each textured surface for one pass's basis ``weights`` (3,)."""
    out = {}
    for part, key in SURFACES:
        name = params[key]
        if name == "none" or part not in (obj.uv_to_cm or {}):
            continue
        rgb = textures.tile(name, params["texture_seed"], part)
        out[part] = textures.bitmap(textures.albedo_map(rgb, weights), obj.uv_to_cm[part],
                                    textures.tile_cm(name, params["texture_scale_cm"]))
    return out


def line_spread(params: Dict[str, Any]) -> "subsurface.LineSpread":
    """The material's line-spread table (:func:`scenes.subsurface.table_for`; computed once, a few seconds)."""
    return subsurface.table_for(params["material"], params["cache_dir"], use_cache=params["cache"])


def load(name: str, params: Dict[str, Any], rig: Rig, obj: objects.SceneObject, spp=None) -> tuple:
    """Load the scene's Mitsuba scenes: ``(laser, ambient, ...)``, one ambient per band.

    Parameters
    ----------
    name, params, rig
        The scene: :class:`scenes.Scene`'s ``name``, ``params`` and ``rig`` (at its image size).
    obj : scenes.objects.SceneObject
    spp : int or "auto", optional
        The render's ``spp`` (:func:`scenes.passes.sample_counts`): the laser scene's own integrator
        gets the first pass's count, the ambient scenes ``ambient_spp``.

    Returns
    -------
    tuple of scenes.backend.LoadedScene
        Posed at mirror angle 0; every render re-poses them.
    """
    from .backend import LoadedScene

    _, counts, ambient_spp = sample_counts(name, params, spp)
    spp = counts[0]
    mat = params["material"]
    laser = laser_profile(params["line_fwhm_mrad"], params["laser_fan_deg"])
    albedos = {"background_albedo": params["background_albedo"], "support_albedo": params["support_albedo"]}
    if params["support_finish"] != "matte":
        albedos["support_finish"] = params["support_finish"]
    if profile_mode(params):
        albedos["stand_in_albedo"] = line_spread(params).diffuse_reflectance
    weights = band_weights(params)
    if not weights:
        return (LoadedScene(description.laser_scene(rig, obj, mat, laser, 0.0, spp, **albedos)),
                LoadedScene(description.ambient_scene(rig, obj, mat, 0.0, ambient_spp, **albedos)))
    return (LoadedScene(description.laser_scene(rig, obj, mat, laser, 0.0, spp, **albedos,
                                                albedo_maps=albedo_maps(params, obj, weights["laser"]))),
            *[LoadedScene(description.ambient_scene(rig, obj, mat, 0.0, ambient_spp, **albedos,
                                                    albedo_maps=albedo_maps(params, obj, w)))
              for w in weights["ambient"]])
