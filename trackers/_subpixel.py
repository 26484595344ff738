"""Sub-pixel peak estimators on image rows (numba kernels).

One function per estimator, each working on one row of a frame around an
integer *anchor* column, and :func:`refine`, the loop over rows that every
peak-type tracker shares (``centroid``, ``gauss3``, ``parabolic``,
``blais_rioux``, ``com_bg`` and the refinement step of ``dp8_subpixel``).

Conventions: columns are in pixel units, an integer being the centre of that
pixel; ``image`` is a ``uint8`` or ``float64`` (H, W) array and every
arithmetic is done in float64, so a ``uint8`` frame and its ``float64`` copy
give identical results.

Anchor rule shared by all estimators: the peak pixel ``p`` may belong to a
*plateau*, a run ``lo..hi`` of pixels equal to ``image[r, p]`` (saturated or
quantised stripes). The 3-point estimators then report the plateau's centre
``(lo + hi) / 2`` (for a 2-pixel plateau this is exactly what their formulas
give; for longer ones, clipped profiles, their model does not apply); so does
Blais-Rioux for plateaus of 5 pixels or more (its 5-tap filter then sees only
the flat top; for 5 and 6 pixels its crossing is that centre anyway). The
other estimators, and Blais-Rioux on shorter plateaus, are anchored at
``(lo + hi) // 2``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["ESTIMATORS", "LOG_FLOOR", "refine"]

GAUSS3 = 0
PARABOLIC = 1
BLAIS_RIOUX = 2
CENTROID = 3
COM = 4

#: Estimator names and their codes in :func:`refine`.
ESTIMATORS = {"gauss3": GAUSS3, "parabolic": PARABOLIC, "blais_rioux": BLAIS_RIOUX, "centroid": CENTROID, "com": COM}

#: ``gauss3`` takes logarithms of ``max(I - b, LOG_FLOOR * (peak - b))``.
LOG_FLOOR = 1e-3


@njit(cache=True, nogil=True)
def plateau(image, r, p):
    """``(lo, hi)``: the run of pixels of row ``r`` equal to ``image[r, p]`` containing ``p``."""
    W = image.shape[1]
    v = image[r, p]
    lo = p
    while lo > 0 and image[r, lo - 1] == v:
        lo -= 1
    hi = p
    while hi < W - 1 and image[r, hi + 1] == v:
        hi += 1
    return lo, hi


@njit(cache=True, nogil=True)
def gauss3_offset(a, b, c, bg):
    """Vertex of the parabola through ``(-1, ln a'), (0, ln b'), (1, ln c')``,
    ``x' = x - bg``: ``0.5 (ln a' - ln c') / (ln a' - 2 ln b' + ln c')``.

    ``a'`` and ``c'`` are floored at ``LOG_FLOOR * b'``. With ``b >= a, c``
    the offset lies in [-0.5, 0.5]; 0 when ``b' <= 0`` or the profile is flat.
    """
    top = b - bg
    if top <= 0.0:
        return 0.0
    floor = LOG_FLOOR * top
    la = np.log(max(a - bg, floor))
    lb = np.log(top)
    lc = np.log(max(c - bg, floor))
    den = la - 2.0 * lb + lc
    if den >= 0.0:
        return 0.0
    return 0.5 * (la - lc) / den


@njit(cache=True, nogil=True)
def parabola_offset(a, b, c):
    """Vertex of the parabola through ``(-1, a), (0, b), (1, c)``:
    ``0.5 (a - c) / (a - 2 b + c)``; in [-0.5, 0.5] when ``b >= a, c``; 0 when flat."""
    den = a - 2.0 * b + c
    if den >= 0.0:
        return 0.0
    return 0.5 * (a - c) / den


@njit(cache=True, nogil=True)
def _px(image, r, j):
    """``image[r, j]`` as float64 with the column clamped into the row."""
    W = image.shape[1]
    if j < 0:
        j = 0
    elif j > W - 1:
        j = W - 1
    return float(image[r, j])


@njit(cache=True, nogil=True)
def blais_rioux_filter(image, r, i):
    """Blais & Rioux's 4th-order derivative filter
    ``g(i) = I(i-2) + I(i-1) - I(i+1) - I(i+2)`` (edge pixels repeated)."""
    return _px(image, r, i - 2) + _px(image, r, i - 1) - _px(image, r, i + 1) - _px(image, r, i + 2)


@njit(cache=True, nogil=True)
def blais_rioux_column(image, r, p):
    """Zero crossing of :func:`blais_rioux_filter` next to the peak ``p``.

    ``g`` changes sign from negative to positive across the peak. The
    crossing is looked for in ``[p, p+1]`` if ``I(p+1) >= I(p-1)``, else in
    ``[p-1, p]``; with ``g0, g1`` the filter at the interval's ends ``i, i+1``
    the column is ``i + g0 / (g0 - g1)`` (linear interpolation), clamped to
    the interval (noise can leave the interval without a sign change).
    """
    W = image.shape[1]
    if W == 1:
        return float(p)
    i = p if _px(image, r, p + 1) >= _px(image, r, p - 1) else p - 1
    if i < 0:
        i = 0
    if i > W - 2:
        i = W - 2
    g0 = blais_rioux_filter(image, r, i)
    g1 = blais_rioux_filter(image, r, i + 1)
    if g0 == g1:
        return i + 0.5
    d = g0 / (g0 - g1)
    if d < 0.0:
        d = 0.0
    elif d > 1.0:
        d = 1.0
    return i + d


@njit(cache=True, nogil=True)
def centroid_column(image, r, p, level, half_window):
    """Gray-gravity centre: the run of contiguous pixels around ``p`` above
    ``level`` (at most ``half_window`` on each side), weights ``I - level``."""
    W = image.shape[1]
    lo = p
    while lo - 1 >= 0 and lo - 1 >= p - half_window and image[r, lo - 1] > level:
        lo -= 1
    hi = p
    while hi + 1 < W and hi + 1 <= p + half_window and image[r, hi + 1] > level:
        hi += 1
    sw = 0.0
    swx = 0.0
    for j in range(lo, hi + 1):
        w = image[r, j] - level
        sw += w
        swx += w * j
    if sw <= 0.0:
        return float(p)
    return swx / sw


@njit(cache=True, nogil=True)
def com_column(image, r, p, level, half_window):
    """Centre of mass as in Horus/FabScan: the pixels within ``half_window``
    of ``p`` above ``level`` (thresholded to zero otherwise), weights ``I``."""
    W = image.shape[1]
    lo = max(p - half_window, 0)
    hi = min(p + half_window, W - 1)
    sw = 0.0
    swx = 0.0
    for j in range(lo, hi + 1):
        v = float(image[r, j])
        if v > level:
            sw += v
            swx += v * j
    if sw <= 0.0:
        return float(p)
    return swx / sw


@njit(cache=True, nogil=True)
def estimate(image, r, p, bg, method, frac, half_window):
    """Sub-pixel column of the peak at ``p`` in row ``r`` by ``method``.

    ``bg`` is the background level (``gauss3``, ``centroid``, ``com``): the
    centroid's level is ``bg + frac (I(p) - bg)``, the centre of mass's
    ``bg + frac (I(p) - bg)`` too (``frac = 0`` for a plain threshold).
    """
    W = image.shape[1]
    lo, hi = plateau(image, r, p)
    v = float(image[r, p])
    if method == CENTROID:
        return centroid_column(image, r, (lo + hi) // 2, bg + frac * (v - bg), half_window)
    if method == COM:
        return com_column(image, r, (lo + hi) // 2, bg + frac * (v - bg), half_window)
    if method == BLAIS_RIOUX:
        if hi - lo >= 4:  # the 5-tap filter sees only the flat top
            return 0.5 * (lo + hi)
        return blais_rioux_column(image, r, (lo + hi) // 2)
    if hi > lo:
        return 0.5 * (lo + hi)
    if p == 0 or p == W - 1:
        return float(p)
    a = float(image[r, p - 1])
    c = float(image[r, p + 1])
    if method == GAUSS3:
        return p + gauss3_offset(a, v, c, bg)
    return p + parabola_offset(a, v, c)


@njit(cache=True, nogil=True)
def refine(image, centre, rows, bg, method, search, frac, half_window, out, ok):
    """Sub-pixel peak of each selected row near a given column.

    Parameters
    ----------
    image : (H, W) uint8 or float64
    centre : (H,) int64
        Integer column per row around which the peak is looked for.
    rows : (H,) bool
        Rows to process; the others get ``out = NaN``, ``ok = False``.
    bg : (H,) float64
        Background level per row (see :func:`estimate`).
    method : int
        An estimator code from :data:`ESTIMATORS`.
    search : int
        The peak ``p`` is the brightest pixel (leftmost on ties) of columns
        ``centre - search .. centre + search`` (clipped to the row). It must
        be a local maximum: if it lies on the window's edge next to a
        brighter pixel outside, the row is not refined (``ok = False``).
    frac, half_window
        As for :func:`estimate`.
    out : (H,) float64
        Output columns (NaN where not refined).
    ok : (H,) bool
        Output: whether the row was refined.
    """
    H, W = image.shape
    for r in range(H):
        if not rows[r]:
            out[r] = np.nan
            ok[r] = False
            continue
        c = centre[r]
        lo = c - search if c - search > 0 else 0
        hi = c + search if c + search < W - 1 else W - 1
        p = lo
        for j in range(lo + 1, hi + 1):
            if image[r, j] > image[r, p]:
                p = j
        if (p == lo and p > 0 and image[r, p - 1] > image[r, p]) or (
            p == hi and p < W - 1 and image[r, p + 1] > image[r, p]
        ):
            out[r] = np.nan
            ok[r] = False
            continue
        out[r] = estimate(image, r, p, bg[r], method, frac, half_window)
        ok[r] = True
