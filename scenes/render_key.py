"""Render-cache key fields of a frame: everything its unit renders depend on (:func:`scenes.cache.key`).

Laser power, ambient level, spectra and the sensor are applied after the cache, so they are not in
the key. Fields added over time are left out where they take their old value, so the keys of
existing renders stay what they were (warm caches survive).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Dict

from . import description, materials, subsurface, textures
from . import variant as _variant
from .loading import SURFACES, band_weights
from .params import RENDER_KEYS
from .passes import CAMERA_PATHS_VERSION, on_pixels, profile_mode, sample_counts
from .rig import Rig

__all__ = ["mitsuba_versions", "texture_fields", "optics_fields", "cache_fields"]


def mitsuba_versions():
    """Versions of the renderer, read from the modules themselves (works
    without package metadata, e.g. from an unpacked wheel)."""
    import drjit
    import mitsuba

    return mitsuba.__version__, drjit.__version__


def texture_fields(params: Dict[str, Any]) -> Dict[str, Any]:
    """Cache-key fields of the textures and the table's finish; empty for an untextured matte
    scene (its key stays what it was).

    Examples
    --------
    >>> import scenes
    >>> texture_fields(scenes.make("cone").params)
    {}
    >>> texture_fields(scenes.make("cone", support="table", support_finish="polished").params)
    {'support_finish': 'polished'}
    """
    p = params
    out = {}
    if p["support_finish"] != "matte":
        out["support_finish"] = p["support_finish"]
    weights = band_weights(p)
    if weights:
        out["textures"] = {
            "names": {part: p[key] for part, key in SURFACES},
            "scale_cm": p["texture_scale_cm"], "seed": p["texture_seed"], "version": textures.TEXTURE_VERSION,
            "weights": {"laser": [float(f"{v:.12g}") for v in weights["laser"]],
                        "ambient": [[float(f"{v:.12g}") for v in w] for w in weights["ambient"]]}}
    return out


def optics_fields(params: Dict[str, Any]) -> Dict[str, Any]:
    """Cache-key fields of a translucent material: its boundary, medium (coefficients) and
    integrators, so a change of any coefficient re-renders; with ``translucency = "profile"`` the
    profile's spec and the spreading's version instead. Empty for the opaque and shiny
    materials (their keys stay what they were)."""
    mat = params["material"]
    if not materials.is_translucent(mat):
        return {}
    if profile_mode(params):
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


def cache_fields(name: str, params: Dict[str, Any], rig: Rig, theta: float, spp, seed: int,
                 variant: str) -> Dict[str, Any]:
    """The key fields of the unit renders of a frame (imports Mitsuba: the key names its version).

    Parameters
    ----------
    name, params, rig
        The scene: :class:`scenes.Scene`'s ``name``, ``params`` and ``rig`` (at its image size).
    theta : float
        Mirror angle (deg).
    spp : int or "auto"
    seed : int
    variant : str
        The Mitsuba variant that renders.

    Returns
    -------
    dict
        For :func:`scenes.cache.key`.
    """
    passes, counts, ambient_spp = sample_counts(name, params, spp)
    extra = {}
    if passes != (description.LaserPass("path", description.MAX_DEPTH, "all"),):
        # keys of plain path-traced materials stay as they were (warm caches survive)
        extra["laser_passes"] = [list(p) for p in passes]
    if any(on_pixels(p) for p in passes):
        extra["camera_paths"] = CAMERA_PATHS_VERSION
    extra.update(texture_fields(params))
    return {
        **extra,
        "scene": name,
        **{k: params[k] for k in RENDER_KEYS if k not in ("spp", "seed")},
        # one count when every laser pass has it (the keys of fixed counts stay what they were)
        "spp": counts[0] if len(set(counts)) == 1 else list(counts),
        "ambient_spp": ambient_spp,
        "seed": seed,
        "mirror_angle_deg": theta,
        "rig": dataclasses.asdict(rig),
        "variant": variant,
        **({"llvm_target": _variant.llvm_target()} if variant.startswith("llvm") else {}),
        "mitsuba": mitsuba_versions()[0],
        "drjit": mitsuba_versions()[1],
        **optics_fields(params),
    }
