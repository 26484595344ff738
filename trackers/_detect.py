"""Per-row detection statistics of the threshold-type trackers (numba kernel).

A row's stripe is its brightest pixel; whether the row has a stripe is decided
against that row alone, with statistics that texture in the rest of the frame
cannot inflate (see :func:`row_statistics` and
:class:`trackers.threshold.ThresholdTracker`):

* the row's background ``b``: the median of the row;
* the pixel noise ``s``: ``1.4826 / sqrt(2)`` times the median absolute
  difference of horizontally adjacent pixels, over a fixed sample of the
  frame. Smooth texture (shading, print, gradients, walls) changes little
  from one pixel to the next and edges are few, so the median difference
  measures the sensor's noise, not the scene (unlike the spread of the
  pixel values themselves, which measures the texture);
* the *runner-up* ``q``: the brightest pixel of the row outside the peak's
  exclusion zone (the contiguous run around the peak above half its contrast
  over ``b``, widened on each side by that run's length, at least 2 px).

Conventions as in :mod:`trackers._subpixel`: the image is ``uint8`` or
``float64`` (H, W) and every arithmetic is float64, so a ``uint8`` frame and
its ``float64`` copy give identical statistics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["MAX_SAMPLES", "NOISE_SAMPLES", "RowDetection", "row_statistics", "detect_rows"]

#: At most this many pixels of a row enter its median; wider rows are
#: sampled with a fixed stride.
MAX_SAMPLES = 64
#: About this many adjacent-pixel differences of a frame enter its noise.
NOISE_SAMPLES = 4096
_DIFF_TO_SIGMA = 1.482602218505602 / math.sqrt(2.0)


@njit(cache=True, nogil=True)
def _select(buf, n, k):
    """The ``k``-th smallest of ``buf[:n]`` (0-based; Hoare's quickselect, in place)."""
    lo = 0
    hi = n - 1
    while hi > lo:
        pivot = buf[(lo + hi) // 2]
        i = lo
        j = hi
        while i <= j:
            while buf[i] < pivot:
                i += 1
            while buf[j] > pivot:
                j -= 1
            if i <= j:
                t = buf[i]
                buf[i] = buf[j]
                buf[j] = t
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            return buf[k]
    return buf[k]


@njit(cache=True, nogil=True)
def _median(buf, n):
    """Median of ``buf[:n]`` (mean of the two middle values for even ``n``; reorders ``buf``)."""
    if n % 2 == 1:
        return _select(buf, n, n // 2)
    a = _select(buf, n, n // 2 - 1)
    b = buf[n // 2]
    for i in range(n // 2 + 1, n):  # the upper middle: smallest of the upper part
        if buf[i] < b:
            b = buf[i]
    return 0.5 * (a + b)


@njit(cache=True, nogil=True)
def row_statistics(image, col, mid, peak, bg, noise, runner_up, lo_out, hi_out):
    """Per-row peak, background, pixel noise and runner-up of a frame.

    Parameters
    ----------
    image : (H, W) uint8 or float64
    col : (H,) int64
        Output: the column of the row's maximum (leftmost on ties).
    mid : (H,) int64
        Output: the middle ``(lo + hi) // 2`` of the run ``lo..hi`` of pixels
        equal to the maximum that starts at ``col`` (``col`` itself unless the
        peak is a plateau, e.g. clipped).
    peak : (H,) float64
        Output: the row's maximum, image units.
    bg : (H,) float64
        Output: the row's median (of every ``ceil(W / MAX_SAMPLES)``-th pixel).
    noise : (H,) float64
        Output: ``1.4826 / sqrt(2)`` x the median of ``|I[r, j+1] - I[r, j]|``
        over every row and every ``max(1, H (W - 1) // NOISE_SAMPLES)``-th
        ``j``, the same for every row (0 for a one-column frame), image units.
    runner_up : (H,) float64
        Output: the brightest pixel outside the exclusion zone; ``bg`` if the
        zone covers the row.
    lo_out, hi_out : (H,) int64
        Output: the half-contrast run around the peak, ``lo..hi`` (inclusive):
        contiguous pixels brighter than ``bg + (peak - bg) / 2``.
    """
    H, W = image.shape
    step = (W + MAX_SAMPLES - 1) // MAX_SAMPLES
    buf = np.empty(W)
    for r in range(H):
        row = image[r]  # comparisons in the image's own dtype: the same order for uint8 and its float64 copy
        p = 0
        top = row[0]
        for j in range(1, W):
            if row[j] > top:
                top = row[j]
                p = j
        v = float(top)
        col[r] = p
        peak[r] = v
        e = p
        while e < W - 1 and row[e + 1] == top:
            e += 1
        mid[r] = (p + e) // 2
        n = 0
        for j in range(0, W, step):
            buf[n] = float(row[j])
            n += 1
        b = _median(buf, n)
        bg[r] = b
        half = b + 0.5 * (v - b)
        lo = p
        while lo > 0 and float(row[lo - 1]) > half:
            lo -= 1
        hi = p
        while hi < W - 1 and float(row[hi + 1]) > half:
            hi += 1
        lo_out[r] = lo
        hi_out[r] = hi
        m = hi - lo + 1
        if m < 2:
            m = 2
        a = lo - m
        z = hi + m + 1
        found = False
        q = top
        for j in range(0, a if a > 0 else 0):
            if not found or row[j] > q:
                q = row[j]
                found = True
        for j in range(z if z > 0 else 0, W):
            if not found or row[j] > q:
                q = row[j]
                found = True
        runner_up[r] = float(q) if found else b
    # the frame's pixel noise from about NOISE_SAMPLES adjacent differences,
    # every dstep-th column of every row (a set that a vertical flip maps onto itself)
    dstep = max(1, (H * (W - 1)) // NOISE_SAMPLES)
    total = 0
    for r in range(H):
        total += len(range(0, W - 1, dstep))
    dbuf = np.empty(max(total, 1))
    n = 0
    for r in range(H):
        row = image[r]
        for j in range(0, W - 1, dstep):
            dbuf[n] = abs(float(row[j + 1]) - float(row[j]))
            n += 1
    s = _DIFF_TO_SIGMA * _median(dbuf, n) if n > 0 else 0.0
    for r in range(H):
        noise[r] = s


@dataclass(frozen=True)
class RowDetection:
    """The per-row decision of :func:`detect_rows`; arrays of shape (H,).

    Attributes
    ----------
    col, mid : int64
        Leftmost maximum and middle of its plateau (see :func:`row_statistics`).
    peak, bg, runner_up : float64
        Image units.
    noise : float64
        The frame's pixel noise (the same in every row), floored (image units, > 0).
    hit : bool
        Whether the row reports a stripe.
    score : float64
        ``(peak - bg) / noise``: the peak's contrast in noise units.
    """

    col: np.ndarray
    mid: np.ndarray
    peak: np.ndarray
    bg: np.ndarray
    noise: np.ndarray
    runner_up: np.ndarray
    hit: np.ndarray
    score: np.ndarray


def detect_rows(image: np.ndarray, k_sigma: float, prominence: float, threshold=None) -> RowDetection:
    """Decide per row whether its brightest pixel is a stripe.

    A row is reported iff its peak's contrast over the row's background,
    ``c = peak - bg``, is positive and

    * ``c > k_sigma * noise`` (the peak stands out of the pixel noise), and
    * ``c > prominence * (runner_up - bg)`` (nothing else in the row comes close:
      the brightest pixel outside the peak's exclusion zone has less than
      ``1 / prominence`` of its contrast),

    with the statistics of :func:`row_statistics`; ``noise`` is floored at
    1e-3 of the frame's range (largest peak minus smallest row median) and at
    the smallest positive float, so noise-free and quantised rows have a
    finite score. With an explicit ``threshold`` (image units) a row is
    reported iff ``peak > threshold`` instead.

    Parameters
    ----------
    image : ndarray, shape (H, W), uint8 or float64
    k_sigma : float
        Noise multiple, >= 0.
    prominence : float
        Least ratio of the peak's contrast to the runner-up's, >= 0 (0 or 1: the
        runner-up never or only when it is as bright rejects the row).
    threshold : float or None

    Returns
    -------
    RowDetection

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> img = 10 + rng.normal(0, 1, (3, 40)); img[:, 20] = 60; img[1, 5] = 55; img[2, 20] = 13
    >>> detect_rows(img, 5.0, 1.5).hit.tolist()  # row 1: a runner-up nearly as bright; row 2: 3 sigma
    [True, False, False]
    >>> detect_rows(img, 5.0, 1.5, threshold=30).hit.tolist()
    [True, True, False]
    """
    H = image.shape[0]
    col = np.empty(H, np.int64)
    mid = np.empty(H, np.int64)
    lo = np.empty(H, np.int64)
    hi = np.empty(H, np.int64)
    peak, bg, noise, runner = (np.empty(H) for _ in range(4))
    row_statistics(image, col, mid, peak, bg, noise, runner, lo, hi)
    floor = max(1e-3 * (float(peak.max()) - float(bg.min())), np.finfo(np.float64).tiny)
    noise = np.maximum(noise, floor)
    contrast = peak - bg
    if threshold is None:
        hit = (contrast > 0) & (contrast > k_sigma * noise) & (contrast > prominence * (runner - bg))
    else:
        hit = peak > float(threshold)
    return RowDetection(col, mid, peak, bg, noise, runner, hit, contrast / noise)
