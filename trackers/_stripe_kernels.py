"""Numba kernels of the stripe question (:func:`trackers._stripe.ask`, which documents the tests).

Each takes a frame (H, W) uint8 or float64 and per-row arrays, and fills (H,) outputs the caller
allocates; every arithmetic is float64, so a uint8 frame and its float64 copy give the same answers.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._detect import MAX_SAMPLES, _half_extent, _median


@njit(cache=True, nogil=True)
def _row_level(row, buf):
    """The median of every ``ceil(W / MAX_SAMPLES)``-th pixel of a row (the threshold family's background)."""
    W = row.shape[0]
    step = (W + MAX_SAMPLES - 1) // MAX_SAMPLES
    n = 0
    for j in range(0, W, step):
        buf[n] = float(row[j])
        n += 1
    return _median(buf, n)


@njit(cache=True, nogil=True)
def _row_evidence(frame, col, peak_out, contrast, lo_out, hi_out, level_out):
    """Per row with a finite ``col``: its peak (the brightest of the three pixels around ``col``, the
    leftmost on ties), the peak's contrast over the row's median and its half-contrast run
    ``lo..hi`` (contiguous pixels above ``level + contrast / 2``); ``peak_out`` -1 where ``col`` is NaN.
    Every output is (H,)."""
    H, W = frame.shape
    buf = np.empty(W)
    for r in range(H):
        c = col[r]
        if not math.isfinite(c):
            peak_out[r] = -1
            contrast[r] = np.nan
            lo_out[r] = 0
            hi_out[r] = -1
            level_out[r] = np.nan
            continue
        j0 = int(math.floor(c + 0.5))
        j0 = min(max(j0, 0), W - 1)
        row = frame[r]
        p = max(j0 - 1, 0)
        top = float(row[p])
        for j in range(p + 1, min(j0 + 1, W - 1) + 1):
            if float(row[j]) > top:
                top = float(row[j])
                p = j
        b = _row_level(row, buf)
        level_out[r] = b
        peak_out[r] = p
        contrast[r] = top - b
        lo, hi = _half_extent(row, p, b + 0.5 * (top - b))
        lo_out[r] = lo
        hi_out[r] = hi


@njit(cache=True, nogil=True)
def _flanks(frame, peak, contrast, level, ref_px, flank_out):
    """The higher of the two flanks' mean levels over the row's median, as a fraction of the peak's
    contrast: each flank the pixels ``d`` to ``2 d`` columns from the peak, ``d = max(ceil(ref_px), 2)``
    (clipped to the frame; a side with no pixel in the frame is not read: a stripe on the frame's edge has
    one flank; with neither, 1, not fallen). The floor of 2 px keeps a 1-2 px stripe's own second pixel
    out of its flanks."""
    H, W = frame.shape
    d0 = max(int(math.ceil(ref_px)), 2)
    for r in range(H):
        p = peak[r]
        if p < 0:
            flank_out[r] = np.nan
            continue
        c = contrast[r]
        worst = -np.inf
        for side in (-1, 1):
            s = 0.0
            n = 0
            for d in range(d0, 2 * d0 + 1):
                j = p + side * d
                if 0 <= j < W:
                    s += float(frame[r, j])
                    n += 1
            if n == 0:
                continue
            v = (s / n - level[r]) / c if c > 0 else 1.0
            if v > worst:
                worst = v
        flank_out[r] = worst if worst > -np.inf else 1.0


@njit(cache=True, nogil=True)
def _window_max(values, peak, lo, hi, out):
    """The largest of ``values[r, lo - 1 .. hi + 1]`` per row with a peak (NaN elsewhere)."""
    H, W = values.shape
    for r in range(H):
        if peak[r] < 0:
            out[r] = np.nan
            continue
        m = -np.inf
        for j in range(max(lo[r] - 1, 0), min(hi[r] + 1, W - 1) + 1):
            v = float(values[r, j])
            if v > m:
                m = v
        out[r] = m


@njit(cache=True, nogil=True)
def _off_ratio(on, off, peak, out):
    """The peak's contrast over its row's median in the laser-off frame over that in the laser-on frame
    (NaN where no peak; +inf where the laser-on contrast is not positive)."""
    H, W = on.shape
    buf = np.empty(W)
    for r in range(H):
        p = peak[r]
        if p < 0:
            out[r] = np.nan
            continue
        c_on = float(on[r, p]) - _row_level(on[r], buf)
        c_off = float(off[r, p]) - _row_level(off[r], buf)
        out[r] = c_off / c_on if c_on > 0 else np.inf


@njit(cache=True, nogil=True)
def _continuity(ok, col, rows, min_in_line, px_per_row, out):
    """``out[r]``: ``ok[r]`` and at least ``min(min_in_line, H - 1)`` rows ``r'`` with ``0 < |r' - r| <= rows``,
    ``ok[r']`` and ``|col[r'] - col[r]| <= px_per_row * |r' - r|`` (a frame of fewer rows than the test
    needs asks for every other row, as the threshold family's chain does)."""
    H = ok.shape[0]
    min_in_line = min(min_in_line, H - 1)
    for r in range(H):
        if not ok[r]:
            out[r] = False
            continue
        n = 0
        for rr in range(max(r - rows, 0), min(r + rows, H - 1) + 1):
            if rr != r and ok[rr] and abs(col[rr] - col[r]) <= px_per_row * abs(rr - r):
                n += 1
        out[r] = n >= min_in_line
