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
  pixel values themselves, which measures the texture); the quantisation's
  own noise is added to it (:func:`detect_rows`);
* the *runner-up* ``q``: the brightest pixel of the row outside the peak's
  exclusion zone (the contiguous run around the peak above half its contrast
  over ``b``, widened on each side by that run's length, at least 2 px);
* the *chain*: rows that pass are kept only where enough of them line up
  vertically (``min_run``), since a stripe is a curve and the brightest
  pixels of stripe-less rows scatter.

Conventions as in :mod:`trackers._subpixel`: the image is ``uint8`` or
``float64`` (H, W) and every arithmetic is float64, so a ``uint8`` frame and
its ``float64`` copy give identical statistics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["MAX_SAMPLES", "NOISE_SAMPLES", "RUN_STEP_PX", "RUN_SKIP", "RowDetection", "row_statistics", "detect_rows",
           "noise_level"]

#: At most this many pixels of a row enter its median; wider rows are
#: sampled with a fixed stride.
MAX_SAMPLES = 64
#: About this many adjacent-pixel differences of a frame enter its noise.
NOISE_SAMPLES = 4096
#: Two candidate rows link into a chain when their half-contrast runs overlap once
#: widened by this many px per row between them (a stripe tilted up to about 70
#: degrees from the vertical stays one chain).
RUN_STEP_PX = 3
#: A chain may skip this many rows that are not candidates (a dim row inside a stripe).
RUN_SKIP = 1
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
def _half_extent(row, p, half):
    """``(lo, hi)``: the run of pixels of ``row`` around ``p`` brighter than ``half`` (``p`` itself always in it)."""
    W = row.shape[0]
    lo = p
    while lo > 0 and float(row[lo - 1]) > half:
        lo -= 1
    hi = p
    while hi < W - 1 and float(row[hi + 1]) > half:
        hi += 1
    return lo, hi


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

    Returns
    -------
    bool
        Whether every pixel of the noise sample is a whole number (an 8- or
        16-bit frame, a float copy of one, or the difference of two): the
        frame is then quantised in steps of 1 (see :func:`detect_rows`).
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
        lo, hi = _half_extent(row, p, b + 0.5 * (v - b))
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
    integral = True
    for r in range(H):
        row = image[r]
        for j in range(0, W - 1, dstep):
            a = float(row[j])
            dbuf[n] = abs(float(row[j + 1]) - a)
            if integral and a != math.floor(a):
                integral = False
            n += 1
    s = _DIFF_TO_SIGMA * _median(dbuf, n) if n > 0 else 0.0
    for r in range(H):
        noise[r] = s
    return integral


@njit(cache=True, nogil=True)
def _link_runs(hit, lo, hi, min_run, step, skip, keep):
    """``keep[r]``: ``hit[r]`` and the chain of hit rows through ``r`` has at least ``min_run`` rows.

    Two hit rows ``r < r'`` with ``r' - r <= skip + 1`` are linked when their runs
    ``lo..hi`` overlap once widened by ``step * (r' - r)`` px; chains are the
    connected components of the links (union-find), so the result does not depend
    on the direction of the rows.
    """
    H = hit.shape[0]
    parent = np.arange(H)
    for r in range(H):
        if not hit[r]:
            continue
        for d in range(1, skip + 2):
            q = r + d
            if q >= H:
                break
            if hit[q] and lo[q] - step * d <= hi[r] and lo[r] - step * d <= hi[q]:
                a = r
                while parent[a] != a:
                    a = parent[a]
                b = q
                while parent[b] != b:
                    b = parent[b]
                if a != b:
                    if a < b:
                        parent[b] = a
                    else:
                        parent[a] = b
    size = np.zeros(H, np.int64)
    root = np.empty(H, np.int64)
    for r in range(H):
        a = r
        while parent[a] != a:
            a = parent[a]
        root[r] = a
        if hit[r]:
            size[a] += 1
    for r in range(H):
        keep[r] = hit[r] and size[root[r]] >= min_run


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
        The frame's pixel noise with the quantisation's (the same in every row),
        floored (image units, > 0).
    hit : bool
        Whether the row reports a stripe (a candidate in a long enough chain).
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


def noise_level(noise, peak, bg, integral: bool, quantum=None) -> np.ndarray:
    """The noise a row's contrast is judged against, image units (H,): the pixel noise of
    :func:`row_statistics` with the quantisation's own (``q**2 / 12``) added, floored at 1e-3 of the
    frame's range (largest peak minus smallest row median) and at the smallest positive float.

    ``q`` is ``quantum``, or (None) 1 for a frame of whole numbers (``integral``) and 0 otherwise. The sum
    of squares is formed only below 1e150 (beyond, ``q**2 / 12`` cannot change it), so a frame of values
    near the float range (a frame times 1e300) does not overflow to an infinite noise.

    >>> noise_level(np.array([0.0, 3.0, 1e300]), np.array([9.0, 9.0, 9.0]), np.zeros(3), True).round(3).tolist()
    [0.289, 3.014, 1e+300]
    """
    q = (1.0 if integral else 0.0) if quantum is None else float(quantum)
    floor = max(1e-3 * (float(peak.max()) - float(bg.min())), np.finfo(np.float64).tiny)
    big = 1e150
    n = np.minimum(noise, big)
    qq = min(q, big)
    summed = np.sqrt(n * n + qq * qq / 12.0)
    return np.maximum(np.where((noise < big) & (q < big), summed, np.maximum(noise, q / math.sqrt(12.0))), floor)


def detect_rows(image: np.ndarray, k_sigma: float, prominence: float, threshold=None, *, min_run: int = 1,
                width_ratio=None, quantum=None, ask=None) -> RowDetection:
    """Decide per row whether its brightest pixel is a stripe.

    A row is a *candidate* iff its peak's contrast over the row's background,
    ``c = peak - bg``, is positive and

    * ``c > k_sigma * noise`` (the peak stands out of the pixel noise), and
    * ``c > prominence * (runner_up - bg)`` (nothing else in the row comes close:
      the brightest pixel outside the peak's exclusion zone has less than
      ``1 / prominence`` of its contrast), and
    * the peak's half-contrast run is at most ``width_ratio`` times as wide as
      the median run of the frame's rows that pass the two tests above (at
      least 2 px): a lamp, a window or a white object is wider than the frame's
      laser stripe, whatever the stripe's own width (None: any width),

    with the statistics of :func:`row_statistics`. ``noise`` is the frame's pixel
    noise with the quantisation's own noise added, ``sqrt(s^2 + quantum^2 / 12)``
    (a quantiser of step ``q`` adds a uniform error of standard deviation
    ``q / sqrt(12)``; in a dark 8-bit frame most adjacent pixels are equal, the
    median difference is 0, and without this term every one-level excursion of
    a stripe-less row would stand "infinitely" far out of the noise), floored at
    1e-3 of the frame's range (largest peak minus smallest row median) and at the
    smallest positive float, so noise-free rows have a finite score.

    A candidate is reported iff it belongs to a *chain* of at least ``min_run``
    candidates: two candidates at most :data:`RUN_SKIP` + 1 rows apart are linked
    when their half-contrast runs overlap once widened by :data:`RUN_STEP_PX` px
    per row between them (a stripe is a curve; the brightest pixels of stripe-less
    rows scatter). ``min_run = 1`` reports every candidate; a frame of fewer than
    ``min_run`` rows needs a chain through all of them.

    With an explicit ``threshold`` (image units) a row is reported iff its peak
    exceeds it, and nothing else is applied.

    Parameters
    ----------
    image : ndarray, shape (H, W), uint8 or float64
    k_sigma : float
        Noise multiple, >= 0.
    prominence : float
        Least ratio of the peak's contrast to the runner-up's, >= 0 (0 or 1: the
        runner-up never or only when it is as bright rejects the row).
    threshold : float or None
    min_run : int
        Least number of linked candidate rows, >= 1.
    width_ratio : float or None
        Widest half-contrast run of a candidate, in medians of the frame's (None: no limit).
    quantum : float or None
        The frame's quantisation step (image units, >= 0); None: 1 where every
        sampled pixel is a whole number (an 8- or 16-bit frame, a float copy of one,
        a difference of two), else 0.
    ask : callable or None
        The stripe question (:func:`trackers._stripe.ask`, bound to the frame):
        ``ask(columns) -> (H,) bool`` for the candidates' columns (``mid``, NaN
        elsewhere); a candidate it says no to is not one (before the chain). None:
        not asked. Not used with an explicit ``threshold``.

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
    >>> dark = np.full((6, 50), 2, np.uint8); dark[:, 30] = 5; dark[2, 7] = 3  # a dim stripe, one stray level
    >>> detect_rows(dark, 4.0, 0.0).hit.tolist()
    [True, True, True, True, True, True]
    >>> dark[4:, 30] = 2; dark[4:, 9] = 5  # rows 4-5: the peak jumps far away
    >>> detect_rows(dark, 4.0, 0.0, min_run=3).hit.tolist()
    [True, True, True, True, False, False]
    """
    H = image.shape[0]
    col = np.empty(H, np.int64)
    mid = np.empty(H, np.int64)
    lo = np.empty(H, np.int64)
    hi = np.empty(H, np.int64)
    peak, bg, noise, runner = (np.empty(H) for _ in range(4))
    integral = row_statistics(image, col, mid, peak, bg, noise, runner, lo, hi)
    noise = noise_level(noise, peak, bg, integral, quantum)
    contrast = peak - bg
    if threshold is None:
        hit = (contrast > 0) & (contrast > k_sigma * noise) & (contrast > prominence * (runner - bg))
        if width_ratio is not None and hit.any():
            width = hi - lo + 1
            hit &= width <= width_ratio * max(float(np.median(width[hit])), 2.0)
        if ask is not None and hit.any():
            hit &= ask(np.where(hit, mid.astype(np.float64), np.nan))
        run = min(int(min_run), H)  # a chain through every row of a short frame is as long as it can be
        if run > 1:
            keep = np.empty(H, np.bool_)
            _link_runs(hit, lo, hi, run, RUN_STEP_PX, RUN_SKIP, keep)
            hit = keep
    else:
        hit = peak > float(threshold)
    return RowDetection(col, mid, peak, bg, noise, runner, hit, contrast / noise)
