"""A frame with truth read as a photograph's reference reads it: which rows are scored, and how.

The shipped set's references (docs/real.md) score a row where the reference rule sees the stripe, leave out the rows
where it stands far under its typical height (:func:`dim_rows`, ``dim_share``; a clipped core is never dim,
:func:`clipped_peaks`), and score a clipped core in a glow near the top of the range (:func:`glow_rows`,
:func:`seen_states`). :func:`row_states` reads a transplant's frames so (:mod:`bench.evaluate.transplant`), and
:func:`unclear_rows` is the one home of the left-out rows, read on a transplant's estimate and on a render's truth.
The tuned values are fields of :class:`bench.evaluate.predict_settings.PredictSettings`. Pure functions.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.evaluate.stripe import Extents, clipped_at, span_extents

__all__ = ["dim_rows", "clipped_peaks", "unclear_rows", "glow_rows", "seen_states", "row_states"]


def dim_rows(ext: Extents, clipped=None, *, guided: bool = False, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The visible rows of ``ext`` whose stripe stands under ``dim_share`` of the median height (``ext.height``,
    the peak over the reference window's median) of its visible rows, shape (H,) bool: the rows a photograph's
    reference leaves out as unclear (measured on the shipped set's labels: ``scripts/reference_rows.py``); none
    without heights.
    ``clipped`` (H,) bool, optional: rows whose peak is clipped (:func:`clipped_peaks`), which are never dim: a
    clipped core stands low over its window's median only where a glow as bright fills the window. ``guided``: every
    row with a height, visible or not (the stripe's rows under ``visible_k`` of the frame's noise units that the
    reference rule, with its own noise unit, still sees).

    Examples
    --------
    >>> vis = np.ones(6, bool)
    >>> e = Extents(np.zeros(6), vis, np.zeros(6), np.zeros(6), np.zeros(6), 1.0,
    ...             height=np.array([50.0, 48.0, 52.0, 9.0, 11.0, 50.0]))
    >>> dim_rows(e).tolist()
    [False, False, False, True, False, False]
    >>> dim_rows(e, clipped=np.array([0, 0, 0, 1, 0, 0], bool)).tolist()
    [False, False, False, False, False, False]
    >>> e.visible[3] = False
    >>> dim_rows(e).tolist(), dim_rows(e, guided=True).tolist()
    ([False, False, False, False, False, False], [False, False, False, True, False, False])
    """
    out = np.zeros(np.shape(ext.visible), bool)
    if ext.height is None or not np.any(ext.visible):
        return out
    h = np.asarray(ext.height, dtype=np.float64)
    typical = np.nanmedian(h[ext.visible])
    if not np.isfinite(typical) or typical <= 0:
        return out
    with np.errstate(invalid="ignore"):
        out = (np.isfinite(h) if guided else ext.visible) & (h < settings.dim_share * typical)
    if clipped is not None:
        clipped = np.asarray(clipped, bool)
        if clipped.shape != out.shape:
            raise ValueError(f"`clipped` must have one entry per row, shape {out.shape}, got {clipped.shape}")
        out &= ~clipped
    return out


def clipped_peaks(original, ext: Extents, noise_dn=None, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The rows whose stripe peak (``ext.peak``) is clipped in ``original``, shape (H,) bool: a channel there stands
    within ``clip_noise_k`` of its noise units (at least 1 DN) of the top of an integer image's range, as
    :func:`transplant` keeps a clipped pixel clipped; none for a float image (no known top).

    Parameters
    ----------
    original : array_like, shape (H, W) or (H, W, C)
        The photograph (DN), turned as the frame ``ext`` was read from.
    ext : Extents
        Its stripe.
    noise_dn : array_like, shape (C,), optional
        Each channel's noise (DN); :func:`bench.evaluate.stripe.channel_noise` when None.

    Examples
    --------
    >>> img = np.full((3, 8), 40, np.uint8); img[:, 4] = [255, 200, 254]
    >>> e = Extents(np.full(3, 4), np.ones(3, bool), np.zeros(3), np.zeros(3), np.zeros(3), 1.0)
    >>> clipped_peaks(img, e, noise_dn=[1.0]).tolist()
    [True, False, True]
    """
    img = np.asarray(original)
    planes = img[..., None] if img.ndim == 2 else img
    H, W = planes.shape[:2]
    if np.shape(ext.peak) != (H,):
        raise ValueError(f"`original` must have the frame's {np.shape(ext.peak)[0]} rows, got shape {img.shape}")
    if not np.issubdtype(img.dtype, np.integer):
        return np.zeros(H, bool)
    top = clipped_at(img, noise_dn, settings=settings)
    cols = np.clip(np.asarray(ext.peak, dtype=np.int64), 0, W - 1)
    return np.any(planes[np.arange(H), cols, :].astype(np.float64) >= top, axis=-1)


def unclear_rows(ext: Extents, original=None, noise_dn=None, *, guided: bool = False,
                 settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The rows of ``ext`` a photograph's reference leaves out as unclear, shape (H,) bool: its :func:`dim_rows`
    (``guided`` as there), less those whose peak is clipped in ``original`` (:func:`clipped_peaks`, with ``noise_dn``)
    when it is given.
    The one home of the convention, read on a transplant's estimate (:func:`row_states`) and on a render's truth
    (``stripebench predictcheck --rows clear``).

    Examples
    --------
    A clipped core standing low in a glow (row 0), a faint stretch (row 1), a clear stripe:

    >>> img = np.full((5, 8), 40, np.uint8); img[:, 4] = [255, 60, 200, 200, 200]
    >>> e = Extents(np.full(5, 4), np.ones(5, bool), np.zeros(5), np.zeros(5), np.zeros(5), 1.0,
    ...             height=np.array([10.0, 20.0, 150.0, 160.0, 155.0]))
    >>> unclear_rows(e).tolist()
    [True, True, False, False, False]
    >>> unclear_rows(e, img, noise_dn=[1.0]).tolist()
    [False, True, False, False, False]
    """
    clipped = None if original is None else clipped_peaks(original, ext, noise_dn, settings=settings)
    return dim_rows(ext, clipped, guided=guided, settings=settings)


def glow_rows(frame, ext: Extents, *, settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The rows of ``ext`` whose stripe stands in a glow, shape (H,) bool: the median of ``frame`` (H, W; DN, an
    integer image) over ``glow_near_px`` to ``glow_far_px`` px either side of the row's peak is at least
    ``glow_share`` of the top of its range; none in a float frame (no known top) or a row without a guide. With
    :func:`clipped_peaks` these are the rows :func:`row_states` reads as :func:`seen_states` does.

    Examples
    --------
    A core at 255 in a glow of 230 (row 0) and of 120 (row 1):

    >>> img = np.full((2, 40), 120, np.uint8); img[0, 5:35] = 230; img[:, 20] = 255
    >>> e = Extents(np.full(2, 20), np.ones(2, bool), np.zeros(2), np.zeros(2), np.full(2, 20.0), 1.0)
    >>> glow_rows(img, e).tolist()
    [True, False]
    """
    img = np.asarray(frame)
    if img.ndim != 2:
        raise ValueError(f"`frame` must be 2-D, got shape {img.shape}")
    H, W = img.shape
    if np.shape(ext.peak) != (H,):
        raise ValueError(f"`frame` must have the stripe's {np.shape(ext.peak)[0]} rows, got shape {img.shape}")
    out = np.zeros(H, bool)
    if not np.issubdtype(img.dtype, np.integer):
        return out
    s = settings
    level = s.glow_share * float(np.iinfo(img.dtype).max)
    for r in np.flatnonzero(np.isfinite(ext.centre)):
        c = int(ext.peak[r])
        side = np.r_[img[r, max(c - s.glow_far_px, 0):max(c - s.glow_near_px + 1, 0)],
                     img[r, min(c + s.glow_near_px, W):min(c + s.glow_far_px + 1, W)]]
        out[r] = side.size > 0 and float(np.median(side)) >= level
    return out


def seen_states(image, truth, clipped=None) -> np.ndarray:
    """The states a photograph's reference gives the rows of ``truth`` (px, shape (H,), NaN: no stripe), shape (H,)
    int8: :func:`~bench.evaluate.outcomes.referenced_states`, and with ``clipped`` ((H,) bool: rows whose stripe's peak
    is clipped, :func:`clipped_peaks`) such a row is a stripe row even where the reference rule does not see it: a
    clipped core in a glow that fills the reference window, which the shipped set's references score (412 of the 469
    such rows of its estimates). The one home of that reading, used on a render's truth (``predictcheck --rows
    clear``) and, in the rows whose glow is the surface's (:func:`glow_rows`), on a transplant's frames
    (:func:`row_states`' ``seen``).

    Examples
    --------
    A clipped core standing 5 DN over a glow as wide as the window (row 0), and a faint unclipped row (row 1):

    >>> img = np.full((2, 20), 30, np.uint8); img[0, 4:17] = 250; img[0, 10] = 255; img[1, 10] = 33
    >>> seen_states(img, [10.0, 10.0]).tolist(), seen_states(img, [10.0, 10.0], np.array([True, False])).tolist()
    ([-1, -1], [1, -1])
    """
    from bench.evaluate.outcomes import STRIPE, UNSURE, referenced_states

    states = referenced_states(image, truth)
    if clipped is not None:
        clipped = np.asarray(clipped, bool)
        if clipped.shape != states.shape:
            raise ValueError(f"`clipped` must have one entry per row, shape {states.shape}, got {clipped.shape}")
        states[(states == UNSURE) & clipped] = STRIPE
    return states


def row_states(ext: Extents, truth, image, keep=None, unclear=None, seen=None, *,
               settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The row states of a transplant, read as a photograph's reference would be, shape (H,) int8.

    A row with a moved centre is :data:`bench.evaluate.outcomes.STRIPE` where the real set's
    reference rule sees the moved stripe in ``image`` (:func:`~bench.evaluate.outcomes.referenced_states`) and the
    row is not one left out (``unclear``, shape (H,) bool: :func:`unclear_rows` of ``ext`` and its photograph, which a
    reference leaves out, and ``bench.run.predict_frames.transplant_frames`` adds the rows where the moved stripe lands
    on a rival, :func:`bench.evaluate.transplant.landed_rows`; without it,
    :func:`dim_rows` of ``ext``), else ``UNSURE``; a row the stripe
    crosses without a moved centre is ``UNSURE``; every other row is
    ``NO_STRIPE`` at least ``GAP_ROWS`` rows from the stripe and ``UNSURE`` nearer
    (:func:`~bench.evaluate.outcomes.fallback_states`, the real set's rule for references without states).
    With ``keep`` (:func:`bench.evaluate.transplant.transplant`'s), the rows it leaves out hold no stripe and count as rows without one.
    With ``seen`` (shape (H,) bool: rows whose stripe is a clipped core in a glow, :func:`clipped_peaks` and
    :func:`glow_rows` of the photograph), those rows are read as :func:`seen_states` reads them, a stripe row where
    the reference rule does not see the core in its glow, as the shipped set's references score them.

    Examples
    --------
    >>> vis = np.r_[np.zeros(10, bool), np.ones(10, bool), np.zeros(20, bool)]
    >>> e = Extents(np.full(40, 5), vis, np.full(40, 3), np.full(40, 7), np.where(vis, 5.0, np.nan), 1.0)
    >>> img = np.zeros((40, 30)); img[10:20, 25] = 100.0
    >>> s = row_states(e, np.r_[np.full(10, np.nan), np.full(10, 25.0), np.full(20, np.nan)], img)
    >>> s[10:20].tolist() == [1] * 10, s[20:34].tolist() == [-1] * 14, s[34:].tolist() == [0] * 6
    (True, True, True)
    """
    from bench.evaluate.outcomes import STRIPE, UNSURE, fallback_states, referenced_states

    t = np.asarray(truth, dtype=np.float64)
    unclear = dim_rows(ext, settings=settings) if unclear is None else np.asarray(unclear, bool)
    if unclear.shape != t.shape:
        raise ValueError(f"`unclear` must have one entry per row, shape {t.shape}, got {unclear.shape}")
    lo, _ = span_extents(ext, np.shape(image)[1])
    crossed = (lo >= 0) | np.isfinite(ext.centre)
    if keep is not None:
        crossed &= np.asarray(keep, bool)
    states = fallback_states(np.where(crossed, 0.0, np.nan))
    states[states == STRIPE] = UNSURE
    moved = np.isfinite(t)
    if seen is not None and np.shape(seen) != t.shape:
        raise ValueError(f"`seen` must have one entry per row, shape {t.shape}, got {np.shape(seen)}")
    if moved.any():
        states[moved] = (referenced_states(image, t) if seen is None else seen_states(image, t, seen))[moved]
        states[moved & unclear] = UNSURE  # as a reference leaves an unclear row out
    return states.astype(np.int8)
