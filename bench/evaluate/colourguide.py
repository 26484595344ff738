"""Which of a colour photograph's candidate stripes looks like the laser: laser evidence and the arbiter of two guides.

A colour photograph has two guides to its stripe (:func:`bench.run.predict_frames.colour_guide`): one found on the
pure laser-colour excess (white light has none) and the tracker's frame's own. :func:`laser_evidence` scores each
pixel by the lesser of its brightness in the laser's channel and its laser colour; :func:`arbitrate` keeps, where the
two guides part, the one with the more evidence near it, and neither where neither has ``evidence_share`` of the
typical evidence. A pixel whose laser channel is clipped with another shows no hue (:func:`hue_hidden`). The tuned
values are fields of :class:`bench.evaluate.predict_settings.PredictSettings`. Pure functions.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.evaluate.stripe import clipped_at, window_lift

__all__ = ["hue_hidden", "laser_evidence", "arbitrate", "evidence_near"]


def hue_hidden(image, laser: str, noise_dn=None, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """Pixels whose hue is not seen, shape (H, W) bool: the laser's channel and at least one other stand within
    ``clip_noise_k`` of that channel's noise units (:func:`bench.evaluate.stripe.channel_noise`, at least 1 DN) of the top of an integer
    image's range, as the transplant reads clipping. There the laser-colour excess reads a glare clipped in green and
    blue (cyan-white) as green; light of the laser's colour keeps the others under it. All False on a float or grey
    image.

    Parameters
    ----------
    image : array_like, shape (H, W, 3) or (H, W)
        The photograph (DN).
    laser : {'red', 'green', 'blue'}
        The laser's colour.
    noise_dn : array_like, shape (3,), optional
        Each channel's noise (DN); :func:`bench.evaluate.stripe.channel_noise` when None.

    Examples
    --------
    A green stripe clipped in green alone, a cyan glare clipped in green and blue, and a white core clipped in all:

    >>> rgb = np.full((4, 8, 3), 40, np.uint8)
    >>> rgb[:, 1] = [120, 255, 90]; rgb[:, 2] = [200, 255, 255]; rgb[:, 3] = [255, 255, 255]
    >>> hue_hidden(rgb, "green")[0, :5].tolist()
    [False, False, True, True, False]
    """
    from bench.evaluate.pixels import LASER_INDEX

    a = np.asarray(image)
    if a.ndim != 3 or not np.issubdtype(a.dtype, np.integer):
        return np.zeros(a.shape[:2], bool)
    clipped = a >= clipped_at(a, noise_dn, settings=settings)[None, None, :]
    li = LASER_INDEX[laser]
    return clipped[..., li] & np.delete(clipped, li, axis=2).any(axis=2)


def laser_evidence(laser_channel, excess, laser_background=None, excess_background=None, *,
                   over: str = "row", settings: PredictSettings = DEFAULT) -> np.ndarray:
    """How much each pixel looks like the laser, shape (H, W), DN: the lesser of two lifts over their row's median (or,
    ``over="window"``, over the reference window around each pixel), each clipped at 0: the laser's own channel
    (bright), and the laser-colour excess (:func:`bench.evaluate.pixels.select_channel` ``excess``) at its most within
    ``guide_half_px`` px along the row (coloured: a stripe's core clipped white in every channel takes its
    fringe's colour). White light (a lamp, a window) is bright without colour; a surface of the laser's hue is
    coloured without being brighter than its row; the stripe is both. The lesser, not a mean: a white bar far
    brighter than the stripe, with a few DN of colour at its edge, must not outweigh the stripe.

    Parameters
    ----------
    laser_channel, excess : array_like, shape (H, W)
        The photograph's laser channel and its laser-colour excess (DN).
    laser_background, excess_background : array_like, shape (H, W), optional
        The same of its laser-off frame, subtracted first.
    over : {'row', 'window'}
        What each lift stands over: its row's median (``row``), or the median of the reference window around it
        (``window``, :func:`window_lift`; the colour's lift taken before it is widened). A glare or lit patch wider
        than the window stands over its row only; a bar's coloured edge beside a bright patch over its window only.
        :func:`bench.run.predict_frames.colour_guide` reads the frame's own guide on the lesser of the two.

    Examples
    --------
    A white lamp (column 5), an orange surface (column 30) and a stripe clipped white with a red fringe
    (columns 60-62):

    >>> red = np.full((3, 80), 100.0); excess = np.zeros((3, 80))
    >>> red[:, 5] = 255.0
    >>> excess[:, 30] = 80.0
    >>> red[:, 60:63] = [200.0, 255.0, 200.0]; excess[:, 60:63] = [40.0, 0.0, 40.0]
    >>> ev = laser_evidence(red, excess)
    >>> ev[0, 60:63].tolist(), float(ev[0, 5]), float(ev[0, 30])
    ([40.0, 40.0, 40.0], 0.0, 0.0)

    A white bar far brighter than a faint stripe, with a little colour at its edge: the stripe has the more evidence.

    >>> red = np.full((1, 60), 20.0); excess = np.zeros((1, 60))
    >>> red[0, 10] = 42.0; excess[0, 10] = 22.0
    >>> red[0, 40] = 255.0; excess[0, 43] = 3.0
    >>> ev = laser_evidence(red, excess)
    >>> float(ev[0, 10]), float(ev[0, 40])
    (22.0, 3.0)

    A greenish glare 30 px wide (columns 20-49): it stands over its row, not over the window around its middle; a
    thin green line (column 120) stands over either.

    >>> green = np.full((1, 200), 60.0); excess = np.zeros((1, 200))
    >>> green[0, 20:50] = 200.0; excess[0, 20:50] = 30.0
    >>> green[0, 120] = 120.0; excess[0, 120] = 40.0
    >>> [float(laser_evidence(green, excess, over=o)[0, 35]) for o in ("row", "window")]
    [30.0, 0.0]
    >>> [float(laser_evidence(green, excess, over=o)[0, 120]) for o in ("row", "window")]
    [40.0, 40.0]
    """
    lc = np.asarray(laser_channel, dtype=np.float64)
    ex = np.asarray(excess, dtype=np.float64)
    if lc.ndim != 2 or ex.shape != lc.shape:
        raise ValueError(f"`laser_channel` and `excess` must be 2-D of one shape, got {lc.shape} and {ex.shape}")
    for name, bg in (("laser_background", laser_background), ("excess_background", excess_background)):
        if bg is not None and np.shape(bg) != lc.shape:
            raise ValueError(f"`{name}` must have the shape of `laser_channel` {lc.shape}, got {np.shape(bg)}")
    if over not in ("row", "window"):
        raise ValueError(f"`over` must be 'row' or 'window', got {over!r}")
    if laser_background is not None:
        lc = lc - np.asarray(laser_background, dtype=np.float64)
    if excess_background is not None:
        ex = ex - np.asarray(excess_background, dtype=np.float64)
    from scipy.ndimage import maximum_filter1d

    widen = 2 * settings.guide_half_px + 1
    if over == "window":  # the colour's lift before it is widened: a widened peak is a plateau that wide
        bright = np.clip(window_lift(lc, settings=settings), 0.0, None)
        coloured = maximum_filter1d(np.clip(window_lift(ex, settings=settings), 0.0, None), widen, axis=1, mode="nearest")
        return np.minimum(bright, coloured)
    wide = maximum_filter1d(ex, widen, axis=1, mode="nearest")
    bright = np.clip(lc - np.median(lc, axis=1, keepdims=True), 0.0, None)
    coloured = np.clip(wide - np.median(wide, axis=1, keepdims=True), 0.0, None)
    return np.minimum(bright, coloured)


def arbitrate(guide, other, evidence, other_evidence=None, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """Two guides made one, shape (H,), px: ``guide``, and ``other`` where ``guide`` has no stripe; where both do
    and lie more than ``jump_px`` apart, the one with the more ``evidence`` (H, W; e.g.
    :func:`laser_evidence`) within ``arbiter_half_px`` px of it (``guide`` on a tie), unless neither has
    ``evidence_share`` of the median evidence near ``guide`` in its rows: then neither (NaN; where the stripe turns
    white, the colour's guide may wander onto something else). Where ``guide`` has no stripe, ``other`` is kept only with that share (a white lamp's or
    window's edge, which the frame's own guide may follow where the colour shows no stripe, has none); with no such
    rows, as it is. ``other_evidence`` (H, W), optional: the evidence ``other`` is read on (default ``evidence``);
    the share is always of ``guide``'s.

    Examples
    --------
    >>> ev = np.zeros((3, 20)); ev[:, 12] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, np.nan]), np.array([3.0, 12.0, 12.0]), ev).tolist()
    [3.0, 12.0, 12.0]

    Where the colour finds no stripe, the frame's own guide on something of no colour is dropped:

    >>> ev = np.zeros((3, 20)); ev[:, 3] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, np.nan]), np.array([3.0, 3.0, 12.0]), ev).tolist()
    [3.0, 3.0, nan]

    Where the two part and neither has evidence, neither is kept:

    >>> ev = np.zeros((5, 20)); ev[:, 3] = 5.0
    >>> arbitrate(np.array([3.0, 3.0, 3.0, 12.0, 12.0]), np.array([3.0, 3.0, 3.0, 3.0, 18.0]), ev).tolist()
    [3.0, 3.0, 3.0, 3.0, nan]
    """
    guide = np.asarray(guide, dtype=np.float64)
    other = np.asarray(other, dtype=np.float64)
    evidence = np.asarray(evidence, dtype=np.float64)
    if guide.shape != other.shape or evidence.ndim != 2 or evidence.shape[0] != guide.shape[0]:
        raise ValueError(f"`guide` and `other` must have one entry per row of `evidence` {evidence.shape}, "
                         f"got {guide.shape} and {other.shape}")
    other_evidence = evidence if other_evidence is None else np.asarray(other_evidence, dtype=np.float64)
    if other_evidence.shape != evidence.shape:
        raise ValueError(f"`other_evidence` must have the shape of `evidence` {evidence.shape}, "
                         f"got {other_evidence.shape}")
    out = np.where(np.isfinite(guide), guide, other)
    s = settings
    both = np.isfinite(guide) & np.isfinite(other) & (np.abs(guide - other) > s.jump_px)
    eg, eo = evidence_near(evidence, guide, settings=s), evidence_near(other_evidence, other, settings=s)
    own = np.isfinite(guide)
    least = s.evidence_share * float(np.median(eg[own])) if own.any() else 0.0
    with np.errstate(invalid="ignore"):
        out[both & (eo > eg)] = other[both & (eo > eg)]
        # the two part and neither looks like the laser: neither guides the row
        out[both & (np.fmax(eg, eo) < least)] = np.nan
        out[~own & np.isfinite(other) & (eo < least)] = np.nan
    return out


def evidence_near(evidence, guide, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The most of ``evidence`` (H, W) within ``arbiter_half_px`` px of each row's ``guide`` (H,), px, shape (H,)
    (NaN where the guide has none): how :func:`arbitrate` reads a guide's laser evidence (a guide is a median of peaks,
    so the peak may lie a px or two off it).

    Examples
    --------
    >>> ev = np.zeros((2, 10)); ev[:, 6] = [3.0, 5.0]
    >>> evidence_near(ev, np.array([4.0, np.nan])).tolist()
    [3.0, nan]
    """
    from scipy.ndimage import maximum_filter1d

    ev = np.asarray(evidence, dtype=np.float64)
    g = np.asarray(guide, dtype=np.float64)
    if ev.ndim != 2 or g.shape != (ev.shape[0],):
        raise ValueError(f"`guide` must have one entry per row of `evidence` {ev.shape}, got {g.shape}")
    out = np.full(g.shape, np.nan)
    rows = np.flatnonzero(np.isfinite(g))
    if rows.size:
        near = maximum_filter1d(ev, 2 * settings.arbiter_half_px + 1, axis=1, mode="nearest")  # the edge: a shorter window
        out[rows] = near[rows, np.clip(np.rint(g[rows]).astype(np.int64), 0, ev.shape[1] - 1)]
    return out
