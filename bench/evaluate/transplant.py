"""A photograph's own stripe, moved to a known place: frames with truth made from one photograph.

A rig's photographs carry what renders may lack (their clutter, rivals, printed edges, the camera's own processing)
but no truth. A *transplant* keeps all of the photograph except the stripe's place. With the stripe found
(:func:`bench.evaluate.stripe.stripe_extents`):

1. **The clean plate** (:func:`transplant`): in each row from the first visible one to the last (a row between them
   that is not visible: an extent as wide as the median one on the line between its nearest visible rows' peaks, so
   that the stripe's faint stretches move with it), every channel of the photograph is replaced over the extent by
   the straight line between the medians of the ``side_px`` pixels either side of it, plus Gaussian noise of that
   channel's sensor noise; with a laser-off photograph, by its pixels.
2. **The stripe, moved:** the photograph minus that line over the extent (the stripe's own profile, clipping, colour
   and noise) is added to the photograph ``shift_px`` columns away, and the result is clipped to the photograph's
   range (a pixel of the stripe within ``clip_noise_k`` noise units of the top stays clipped). The two moved frames'
   shifts (:func:`shifts_for`) keep the moved stripe off *rivals*, pixels as high over their row as the stripe
   (:func:`rival_mask`). A row whose moved extent would leave the frame or meet its old extent is cleaned, not moved.
   The truth is the centre plus ``shift_px`` in the moved rows that have a guide; NaN in the others.
3. **The photograph in place:** the photograph itself is a frame too, its truth the estimated centre from the first
   visible row to the last (:func:`in_place_truth`): its glow, rivals and surroundings stay where they are, as no
   moved frame carries them.
4. **False-report frames:** moved again with ``end_cut`` of the stripe's span cut off each end (:func:`cut_ends`), so
   those rows keep the photograph's clutter without a stripe.

:mod:`bench.evaluate.rowstates` reads each frame's rows as a reference would. The moved stripe keeps the photograph's
stripe (width, contrast, saturation, colour, speckle) and its surroundings keep everything else; what changes is
where the stripe crosses them. The tuned values are fields of
:class:`bench.evaluate.predict_settings.PredictSettings`. Pure functions: arrays in, arrays out.

Examples
--------
>>> from bench.evaluate.stripe import stripe_extents
>>> rng = np.random.default_rng(0)
>>> x = np.arange(120.0)
>>> photo = np.clip(30 + 150 * np.exp(-0.5 * ((x - 50.3) / 1.5) ** 2) + rng.normal(0, 2, (40, 120)), 0, 255)
>>> photo = np.rint(photo).astype(np.uint8)
>>> ext = stripe_extents(photo)
>>> int(ext.visible.sum()), bool(abs(np.nanmedian(ext.centre) - 50.3) < 0.2)
(40, True)
>>> moved, truth = transplant(photo, ext, 30, seed=1)
>>> bool(np.allclose(truth, ext.centre + 30)), int(np.argmax(moved[0])), int(moved[:, 45:56].max()) < 60
(True, 80, True)
"""

from __future__ import annotations

import math

import numpy as np

from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.evaluate.stripe import Extents, channel_noise, clipped_at, span_extents, stripe_extents, working_frame

__all__ = ["shift_for", "rival_mask", "landed_rows", "shifts_for", "transplant", "in_place_truth", "cut_ends"]


def shift_for(ext: Extents, *, settings: PredictSettings = DEFAULT) -> int:
    """A shift (px) that moves most extents clear of themselves: the 90th-percentile extent width
    plus ``2 * side_px + 1``, at least ``min_shift_px`` (rows whose extent is wider are not moved).

    Examples
    --------
    >>> e = Extents(np.zeros(3, int), np.array([True, True, False]), np.array([8, 9, 0]), np.array([14, 15, 0]),
    ...             np.array([11.0, 12.0, np.nan]), 2.0)
    >>> shift_for(e)
    14
    """
    if not ext.visible.any():
        return settings.min_shift_px
    widths = (ext.hi - ext.lo + 1)[ext.visible]
    return int(max(settings.min_shift_px, math.ceil(np.percentile(widths, 90)) + 2 * settings.side_px + 1))


def rival_mask(frame, background, ext: Extents, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The frame's *rivals* to its stripe, shape (H, W) bool: in each row with a visible stripe, the pixels of the
    working frame (``frame`` less ``background``, smoothed along the row as :func:`stripe_extents` smooths it) standing
    over the row's median by at least ``rival_share`` x the stripe's height there, outside the row's extent and
    outside the run of such pixels that continues it either side (the stripe's own glow or bloom, which moves with it
    in the photograph's light, is not something else beside it).

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:, 44:47] += 150.0
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> m = rival_mask(img, None, e)
    >>> np.flatnonzero(m[5]).tolist()  # the rival, brighter than the stripe; the stripe's own extent is not one
    [44, 45, 46]
    """
    work, sm = working_frame(frame, background)
    lift = sm - np.median(work, axis=1)[:, None]
    height = np.nan_to_num(np.asarray(ext.height if ext.height is not None else np.zeros(work.shape[0]), float))
    level = settings.rival_share * np.maximum(height, 0.0)[:, None]
    out = ext.visible[:, None] & (lift >= level) & (height > 0)[:, None]
    W = work.shape[1]
    for r in np.flatnonzero(ext.visible):  # the extent, and what stands as high next to it: the stripe's own glow
        a, b = int(ext.lo[r]), int(ext.hi[r])
        while a > 0 and out[r, a - 1]:
            a -= 1
        while b < W - 1 and out[r, b + 1]:
            b += 1
        out[r, a:b + 1] = False
    return out


def landed_rows(ext: Extents, rivals, shift_px: int, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The visible rows of ``ext`` whose extent, moved by ``shift_px`` (px, signed) and widened by ``side_px``
    either side, meets ``rivals`` (:func:`rival_mask`, (H, W) bool), shape (H,) bool: where the moved stripe lands on
    a rival, which the photograph's stripe, beside it, does not (a row whose moved extent falls wholly outside the
    frame does not count; one only partly outside is counted on its part inside).

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:10, 34:37] += 150.0  # a rival 15 px right, rows 0-9
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> r = rival_mask(img, None, e)
    >>> int(landed_rows(e, r, 12).sum()), int(landed_rows(e, r, 22).sum())
    (10, 0)
    """
    return _landed(ext, _row_cumsum(rivals), shift_px, settings.side_px)


def _row_cumsum(rivals) -> np.ndarray:
    """Each row's running count of ``rivals`` (H, W) bool, shape (H, W + 1), a leading 0: what :func:`_landed` reads."""
    rivals = np.asarray(rivals, bool)
    return np.concatenate([np.zeros((rivals.shape[0], 1), int), np.cumsum(rivals, axis=1)], axis=1)


def _landed(ext: Extents, csum, shift_px: int, side_px: int) -> np.ndarray:
    """:func:`landed_rows` from the rivals' running counts ``csum`` (:func:`_row_cumsum`), read once per frame."""
    H, W = csum.shape[0], csum.shape[1] - 1
    out = np.zeros(H, bool)
    rows = np.flatnonzero(ext.visible)
    if rows.size == 0:
        return out
    a = np.clip(ext.lo[rows].astype(int) + shift_px - side_px, 0, W)
    b = np.clip(ext.hi[rows].astype(int) + shift_px + side_px + 1, 0, W)
    out[rows] = (b > a) & (csum[rows, b] - csum[rows, a] > 0)
    return out


def shifts_for(ext: Extents, rivals, *, settings: PredictSettings = DEFAULT) -> tuple[int, int]:
    """The two moved frames' shifts (px), ``(right, left)`` (both > 0; the second frame moves by ``-left``): in each
    direction the least of ``shift_for(ext)`` .. ``shift_for(ext) + rival_search_px`` whose moved extents meet
    ``rivals`` (:func:`rival_mask`, (H, W) bool) in the fewest visible rows (:func:`landed_rows`).

    Examples
    --------
    >>> img = np.full((20, 80), 10.0); img[:, 20] += 100.0; img[:, 34:37] += 150.0  # a rival 15 px right
    >>> e = stripe_extents(img, guide=np.full(20, 20.0))
    >>> shift_for(e), shifts_for(e, rival_mask(img, None, e))  # to the right, past the rival
    (12, (22, 12))
    """
    base = shift_for(ext, settings=settings)
    if not ext.visible.any():
        return base, base
    csum = _row_cumsum(rivals)  # once, for every shift tried
    out = []
    for sign in (1, -1):
        best = None
        for s in range(base, base + settings.rival_search_px + 1):
            met = int(_landed(ext, csum, sign * s, settings.side_px).sum())
            if best is None or met < best[0]:
                best = (met, s)
            if met == 0:
                break
        out.append(best[1])
    return out[0], out[1]


def transplant(original, ext: Extents, shift_px: int, *, background_original=None, seed: int = 0,
               noise_dn=None, keep=None, laser_channel: int | None = None, settings: PredictSettings = DEFAULT):
    """The photograph with its stripe moved ``shift_px`` columns (module docstring).

    Parameters
    ----------
    original : ndarray, shape (H, W) or (H, W, C), integer or float
        The photograph, turned as the tracker's frame (its rows and columns are ``ext``'s).
    ext : Extents
        :func:`stripe_extents` of the tracker's frame of ``original``.
    shift_px : int
        Columns to move the stripe by (either sign, non-zero).
    background_original : ndarray like ``original``, optional
        The laser-off photograph: the clean plate is taken from it.
    seed : int
        Seed of the clean plate's noise.
    noise_dn : array_like, shape (C,), optional
        :func:`channel_noise` of ``original``, when the caller has it (it is measured otherwise).
    keep : array_like of bool, shape (H,), optional
        The rows whose stripe is moved (default: all); the others are cleaned, not moved (:func:`cut_ends`).
    laser_channel : int, optional
        The laser's channel of a colour ``original``: where it stands at or above the ``auto`` knee
        (:data:`bench.evaluate.colour.AUTO_KNEE` of the top), its moved lift is at least the greatest of the other
        channels' (under the laser's light its own channel rises most; near the top it shows less only because it
        clips: a white core in a red glow).
    settings : PredictSettings
        The tuned values (``side_px``, ``clip_noise_k``).

    Returns
    -------
    moved : ndarray like ``original`` (same dtype)
    truth : ndarray of float64, shape (H,)
        The moved stripe's centre (px), NaN in rows where it was not moved.
    """
    img = np.asarray(original)
    if img.ndim not in (2, 3) or img.shape[0] != ext.peak.shape[0]:
        raise ValueError(f"`original` must be (H, W) or (H, W, C) with H = {ext.peak.shape[0]}, got {img.shape}")
    if isinstance(shift_px, bool) or not isinstance(shift_px, (int, np.integer)) or shift_px == 0:
        raise ValueError(f"`shift_px` must be a non-zero integer, got {shift_px!r}")
    f = img.astype(np.float64)
    planes = f[..., None] if f.ndim == 2 else f
    H, W, C = planes.shape
    if background_original is not None:
        bgp = np.asarray(background_original, dtype=np.float64)
        bgp = bgp[..., None] if bgp.ndim == 2 else bgp
        if bgp.shape != planes.shape:
            raise ValueError(f"`background_original` must have shape {img.shape}, got {np.shape(background_original)}")
    # each channel's noise: the clean plate's (without a laser-off photograph) and the clipping margin
    noise = (channel_noise(img, settings=settings) if noise_dn is None
             else np.broadcast_to(np.asarray(noise_dn, np.float64), (C,)))
    rng = np.random.default_rng(seed)
    if np.issubdtype(img.dtype, np.integer):
        lo_v, hi_v = float(np.iinfo(img.dtype).min), float(np.iinfo(img.dtype).max)
    else:
        lo_v, hi_v = -np.inf, np.inf
    top_at = clipped_at(img, noise, settings=settings)  # (C,): at or above it, a pixel counts as clipped
    li, knee = None, None  # the laser's channel, lifted at least as the others at or above the knee
    if laser_channel is not None and C > 1:
        if isinstance(laser_channel, bool) or not isinstance(laser_channel, (int, np.integer)) or \
                not 0 <= laser_channel < C:
            raise ValueError(f"`laser_channel` must be a channel of `original` (0-{C - 1}), got {laser_channel!r}")
        if np.isfinite(hi_v):
            from bench.evaluate.colour import AUTO_KNEE

            li, knee = int(laser_channel), AUTO_KNEE * hi_v
    out = planes.copy()
    truth = np.full(H, np.nan)
    s = int(shift_px)
    lo, hi = span_extents(ext, W)
    kept = np.ones(H, bool) if keep is None else np.asarray(keep, bool)
    for r in np.flatnonzero(lo >= 0):
        a, b = int(lo[r]), int(hi[r])
        if background_original is None:
            line = _line(planes[r], a, b, settings.side_px)
            out[r, a:b + 1] = line + rng.normal(0.0, 1.0, line.shape) * noise[None, :]
        else:
            line = bgp[r, a:b + 1]
            out[r, a:b + 1] = line
        side = settings.side_px
        if not kept[r] or a + s - side < 0 or b + s + side > W - 1 or abs(s) < b - a + 1 + side:
            continue  # the moved extent would leave the frame or meet the old one: removed, not moved
        src = planes[r, a:b + 1]
        lift = src - line
        if li is not None:
            near_top = src[:, li] >= knee
            lift[near_top, li] = np.maximum(lift[near_top, li], np.delete(lift[near_top], li, axis=1).max(axis=1))
        out[r, a + s:b + s + 1] = np.where(src >= top_at[None, :], hi_v, planes[r, a + s:b + s + 1] + lift)
        if np.isfinite(ext.centre[r]):
            truth[r] = ext.centre[r] + s
    out = np.clip(out, lo_v, hi_v)
    if np.issubdtype(img.dtype, np.integer):
        out = np.rint(out)
    out = out.astype(img.dtype)
    return (out[..., 0] if img.ndim == 2 else out), truth


def in_place_truth(ext: Extents) -> np.ndarray:
    """The estimated stripe's centre in the rows :func:`transplant` would clean or move, from the first visible row
    to the last, shape (H,), px (NaN elsewhere): the truth of the photograph itself as a frame of the prediction,
    read with :func:`bench.evaluate.rowstates.row_states`.

    Examples
    --------
    >>> vis = np.r_[False, True, True, False]
    >>> e = Extents(np.full(4, 5), vis, np.full(4, 3), np.full(4, 7), np.array([np.nan, 5.2, 5.4, 6.0]), 1.0)
    >>> in_place_truth(e).tolist()
    [nan, 5.2, 5.4, nan]
    """
    vis = np.flatnonzero(ext.visible)
    span = np.zeros(ext.visible.shape[0], bool)
    if vis.size:
        span[vis[0]:vis[-1] + 1] = True
    return np.where(span & np.isfinite(ext.centre), ext.centre, np.nan)


def cut_ends(ext: Extents, *, settings: PredictSettings = DEFAULT):
    """The rows whose stripe a false-report frame moves: the visible span without ``end_cut`` of it at each end.

    Returns
    -------
    numpy.ndarray of bool, shape (H,), or None
        True from the first visible row + k to the last - k (k = ``end_cut`` x the span, rounded), or None when
        fewer than ``end_cut_min_rows`` rows would stay (or no row is visible).

    Examples
    --------
    >>> vis = np.r_[np.zeros(10, bool), np.ones(100, bool), np.zeros(10, bool)]
    >>> e = Extents(np.zeros(120, int), vis, np.zeros(120, int), np.zeros(120, int), np.full(120, np.nan), 1.0)
    >>> k = cut_ends(e); int(np.argmax(k)), int(k.sum()), cut_ends(e, settings=PredictSettings(end_cut=0.35)) is None
    (25, 70, True)
    """
    vis = np.flatnonzero(ext.visible)
    if vis.size == 0:
        return None
    span = int(vis[-1] - vis[0] + 1)
    k = int(round(float(settings.end_cut) * span))
    if span - 2 * k < settings.end_cut_min_rows:
        return None
    keep = np.zeros(ext.visible.shape[0], bool)
    keep[vis[0] + k:vis[-1] - k + 1] = True
    return keep


def _few_median(pixels) -> np.ndarray:
    """``np.median(pixels, axis=0)`` of a few pixels (k, C), the same float64 values, without its overhead (the
    clean plate takes two per row).

    Examples
    --------
    >>> px = np.array([[3, 9], [1, 7], [2, 250]], dtype=np.uint8)
    >>> [bool(np.array_equal(_few_median(px[:k]), np.median(px[:k], axis=0))) for k in (1, 2, 3)]
    [True, True, True]
    """
    v = np.sort(np.asarray(pixels, dtype=np.float64), axis=0)
    n = v.shape[0]
    if n == 0:  # np.median's NaN (a stripe across the whole row), without its warning
        return np.full(v.shape[1:], np.nan)
    return v[n // 2] if n % 2 else (v[n // 2 - 1] + v[n // 2]) / 2.0


def _line(row, a: int, b: int, side_px: int) -> np.ndarray:
    """Row ``row`` (W, C) over columns ``a..b``: the line between the medians of the
    ``side_px`` pixels either side (shape (b - a + 1, C))."""
    W = row.shape[0]
    left = row[max(a - side_px, 0):a] if a > 0 else row[b + 1:b + 1 + side_px]
    right = row[b + 1:min(b + 1 + side_px, W)] if b < W - 1 else left
    ml, mr = _few_median(left), _few_median(right)
    t = (np.arange(a, b + 1) - (a - 1)) / float(b - a + 2)
    return ml[None, :] + t[:, None] * (mr - ml)[None, :]
