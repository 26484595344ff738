"""Pixel masks of a frame from the first hits through its pixel centres: lit, support, split and pass pixels.

Every mask is (H, W) bool and derives from :func:`visible` (one batched ray cast of the frame's
loaded laser scene): the surface point, the part (an index into :data:`PARTS`) and the distance of
the first hit through each pixel centre. :class:`scenes.Scene` keeps the last angle's hits and calls
these functions.
"""

from __future__ import annotations

from typing import Callable, Tuple

import numpy as np

from . import description
from .rig import Rig

__all__ = ["PARTS", "SILHOUETTE_JUMP_CM", "SILHOUETTE_MARGIN", "grow", "visible", "lit_pixels", "support_pixels",
           "split_pixels", "pass_pixels"]

#: Mitsuba shape ids, in the order of :data:`scenes.frame.PARTS` (the part index of a hit).
PARTS = ("backdrop", "object", "support")
#: :func:`lit_pixels`: a depth step (cm) between neighbouring pixel centres that makes a silhouette.
SILHOUETTE_JUMP_CM = 1.0
#: :func:`lit_pixels`: silhouette pixels within this many frustum half-widths of the sheet are rendered.
SILHOUETTE_MARGIN = 5.0

#: First hits of one frame: points (H, W, 3) cm (NaN on a miss), part index (H, W), distance (H, W) cm.
Hits = Tuple[np.ndarray, np.ndarray, np.ndarray]


def grow(mask: np.ndarray) -> np.ndarray:
    """``mask`` grown by one pixel (8-neighbourhood).

    Examples
    --------
    >>> m = np.zeros((3, 4), bool)
    >>> m[1, 1] = True
    >>> grow(m).astype(int)
    array([[1, 1, 1, 0],
           [1, 1, 1, 0],
           [1, 1, 1, 0]])
    """
    grown = mask.copy()
    grown[1:] |= mask[:-1]
    grown[:-1] |= mask[1:]
    rows = grown.copy()
    grown[:, 1:] |= rows[:, :-1]
    grown[:, :-1] |= rows[:, 1:]
    return grown


def visible(laser_scene, rig: Rig, theta: float) -> Hits:
    """First hits through every pixel centre at mirror angle ``theta`` (deg); poses ``laser_scene``.

    Parameters
    ----------
    laser_scene : scenes.backend.LoadedScene
        The scene's loaded laser scene (posed here for ``theta``).
    rig : Rig
    theta : float

    Returns
    -------
    points_cm : ndarray (H, W, 3), float64
        NaN where the ray hits nothing.
    part : ndarray (H, W)
        Index into :data:`PARTS` (-1 on a miss).
    t : ndarray (H, W), float
        Distance along the ray, cm (inf on a miss).

    All three are read-only.
    """
    laser_scene.set_pose(description.pose_updates(rig, theta))
    rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float), indexing="ij")
    o, d = rig.pixel_rays(cols, rows, theta)
    t, part = laser_scene.cast(o.reshape(-1, 3), d.reshape(-1, 3), PARTS)
    t = t.reshape(rig.height, rig.width)
    part = part.reshape(rig.height, rig.width)
    with np.errstate(invalid="ignore"):
        points = o + np.where(np.isfinite(t), t, np.nan)[..., None] * d
    result = (points, part, t)
    for a in result:
        a.flags.writeable = False
    return result


def lit_pixels(hits: Hits, rig: Rig, theta: float, tan_half_x: float) -> np.ndarray:
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

    Parameters
    ----------
    hits : tuple
        :func:`visible` at ``theta``.
    rig : Rig
    theta : float
        Mirror angle (deg).
    tan_half_x : float
        The projector's frustum half-width (:func:`scenes.laser.profile`).
    """
    points, part, t = hits
    rel = points - rig.laser_origin_cm(theta)
    _, normal = rig.laser_plane(theta)
    h, w = part.shape
    with np.errstate(invalid="ignore", divide="ignore"):
        u = (rel @ normal) / np.abs(rel @ rig.laser_direction(theta))
        lit = np.abs(u) <= tan_half_x
        edge = np.zeros((h, w), bool)
        for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
            a = (slice(0, h - dy), slice(max(0, -dx), w - max(0, dx)))
            b = (slice(dy, None), slice(max(0, dx), w + min(0, dx)))
            ua, ub = u[a], u[b]
            both = (np.minimum(ua, ub) <= tan_half_x) & (np.maximum(ua, ub) >= -tan_half_x)  # False with a miss
            lit[a] |= both
            lit[b] |= both
            jump = (part[a] != part[b]) | ~(np.abs(t[a] - t[b]) <= SILHOUETTE_JUMP_CM)
            edge[a] |= jump
            edge[b] |= jump
        lit |= edge & (np.abs(u) <= SILHOUETTE_MARGIN * tan_half_x)
    return grow(grow(lit))


def support_pixels(part: np.ndarray) -> np.ndarray:
    """Pixels whose centre ray hits the table (``part``: :func:`visible`'s), grown by one pixel
    (8-neighbourhood), (H, W) bool."""
    return grow(part == PARTS.index("support"))


def split_pixels(part: np.ndarray) -> np.ndarray:
    """Pixels a ``"split"`` laser pass renders with ``path`` (the others with ``ptracer``), (H, W) bool.

    The pixels whose centre ray hits the object (``part``: :func:`visible`'s), grown by one pixel
    (8-neighbourhood), so that pixels the silhouette crosses, which see part of the object's
    highlight, are path traced too (light tracing renders a glossy highlight with fireflies).
    """
    return grow(part == PARTS.index("object"))


def pass_pixels(passes: tuple, hits: Callable[[], Hits], rig: Rig, theta: float, tan_half_x: float) -> list:
    """The pixels each laser pass contributes to at ``theta``: one (H, W) bool mask per pass, or None for
    the whole image.

    A pass's ``pixels`` (:class:`scenes.description.LaserPass`: :func:`split_pixels`,
    :func:`support_pixels` or their complements), intersected for a pass of
    :data:`scenes.description.DIRECT_DEPTH` with :func:`lit_pixels`. ``path`` passes with a mask
    are rendered on those pixels only (:func:`scenes.backend.camera_paths`); the light tracers'
    renders are masked.

    Parameters
    ----------
    passes : tuple of scenes.description.LaserPass
    hits : callable
        Returns :func:`visible` at ``theta``; called only when a pass needs a mask.
    rig : Rig
    theta : float
        Mirror angle (deg).
    tan_half_x : float
        The projector's frustum half-width (:func:`lit_pixels`).
    """
    masks = {"all": None}
    if any(p.pixels in ("support", "rest") for p in passes):
        on_support = support_pixels(hits()[1])
        masks.update(support=on_support, rest=~on_support)
    if any(p.pixels in ("object", "other") for p in passes):
        on_object = split_pixels(hits()[1])
        masks.update(object=on_object, other=~on_object)
    out = []
    for p in passes:
        mask = masks[p.pixels]
        if p.kind == "path" and p.max_depth == description.DIRECT_DEPTH:
            lit = lit_pixels(hits(), rig, theta, tan_half_x)
            mask = lit if mask is None else mask & lit
        out.append(mask)
    return out
