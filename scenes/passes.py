"""Laser passes of a scene: which passes, how many samples each, and how one pass is rendered on its pixels.

A frame's laser radiance is the sum of its passes (:class:`scenes.description.LaserPass`), each
rendered on its pixels (:func:`scenes.masks.pass_pixels`). The functions here take a scene's name
and parameters (``Scene.params``); :class:`scenes.Scene` calls them.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _checks, description, materials, sampling

__all__ = ["CAMERA_PATHS_VERSION", "profile_mode", "own_passes", "sample_counts", "on_pixels", "render_pass"]

#: Version of the camera-path passes rendered on their pixels only (:func:`on_pixels`; cache key).
CAMERA_PATHS_VERSION = 1


def profile_mode(params: Dict[str, Any]) -> bool:
    """True for a translucent material rendered with ``translucency = "profile"``."""
    return materials.is_translucent(params["material"]) and params["translucency"] == "profile"


def own_passes(params: Dict[str, Any]) -> tuple:
    """The laser pass(es) of a scene with ``params`` at fixed sample counts (:meth:`scenes.Scene.laser_passes`).

    Those of the material (:func:`scenes.description.laser_passes`), except for a path-traced
    material on a ``support_finish="polished"`` table: ``path`` on the pixels that see the table
    (:func:`scenes.masks.support_pixels`: the stripe and the object mirrored in the coat), ``ptracer``
    on the others (the sheet the coat reflects onto the object, which a path tracer finds only as
    fireflies through the narrow lobe). Unbiased for the same reason as the shiny materials' split.

    Returns
    -------
    tuple of scenes.description.LaserPass
    """
    mat = params["material"]
    passes = description.laser_passes(mat, "profile") if profile_mode(params) else description.laser_passes(mat)
    plain = (description.LaserPass("path", description.MAX_DEPTH, "all"),)
    if passes == plain and params["support"] == "table" and params["support_finish"] == "polished":
        return (description.LaserPass("path", description.MAX_DEPTH, "support"),
                description.LaserPass("ptracer", description.MAX_DEPTH, "rest"))
    return passes


def sample_counts(name: str, params: Dict[str, Any], spp=None) -> Tuple[tuple, Tuple[int, ...], int]:
    """The laser passes, each one's samples per pixel and the ambient pass's, of a render at ``spp``.

    Parameters
    ----------
    name : str
        The scene's object (:func:`scenes.available`).
    params : dict
        The scene's parameters (``Scene.params``).
    spp : int or "auto", optional
        :meth:`scenes.Scene.render`'s ``spp`` (default ``params['spp']``). An integer gives every laser
        pass that count; ``"auto"`` takes the material's integrator and counts from
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
    >>> p = scenes.make("cone", material="skin", spp="auto", ambient_spp=4).params
    >>> [tuple(q) for q in sample_counts("cone", p)[0]], sample_counts("cone", p)[1:]
    ([('volpath', 64, 'all')], ((16,), 4))
    >>> sample_counts("cone", p, 32)[1]
    (32,)
    """
    spp = params["spp"] if spp is None else spp
    material = params["material"]
    passes = own_passes(params)
    if spp == sampling.AUTO:
        choice = sampling.laser_choice(material)
        if choice is not None and passes == description.laser_passes(material):
            kind, counts = choice
            if kind in ("split", "split_hybrid"):
                n = sampling.object_spp(material, sampling.case_key(name, params["background"], params["support"]))
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
    amb = params["ambient_spp"]
    ambient_spp = sampling.ambient_spp(material) if amb == sampling.AUTO else int(amb)
    return passes, tuple(counts), ambient_spp


def on_pixels(p: description.LaserPass) -> bool:
    """True when laser pass ``p`` is rendered on its pixels only (:func:`scenes.backend.camera_paths`):
    a ``path`` pass on a part of the image, or one of :data:`scenes.description.DIRECT_DEPTH`, whose
    light is only where the laser's frustum meets a visible surface (:func:`scenes.masks.lit_pixels`)."""
    return p.kind == "path" and (p.pixels != "all" or p.max_depth == description.DIRECT_DEPTH)


def render_pass(laser_scene, pose: Dict[str, np.ndarray], laser_pass: description.LaserPass,
                pixels: Optional[np.ndarray], spp: int, seed: int) -> np.ndarray:
    """One laser pass as :meth:`scenes.Scene.render` renders it, float64 (H, W), zero off ``pixels``.

    A camera-path pass with ``pixels`` (:meth:`scenes.Scene.pass_pixels`) is rendered on those pixels
    only (:func:`scenes.backend.camera_paths`); a light tracer's paths land anywhere, so its whole image
    is rendered and masked. The frame's laser radiance is the sum of its passes; the sampling procedure
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
                             pixels=pixels if on_pixels(laser_pass) else None).astype(np.float64)
    return img if pixels is None else np.where(pixels, img, 0.0)
