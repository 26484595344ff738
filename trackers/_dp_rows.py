"""Numba kernel of the DP trackers' reporting rule (see :class:`trackers.dp.DPTracker`).

The solver (:mod:`trackers._dp_kernels`) finds the optimal paths; this module
turns the labelled optimal-path nodes into one column, a contrast and a local
noise estimate per row. Callers allocate the outputs. The public entry point
(for scripts and notebooks) is :func:`trackers.dp_stages.row_readings`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Row rules of :func:`marked_rows` (see :class:`trackers.dp.DPTracker`).
RULE_MEAN = 0
RULE_CROSSING = 1
RULE_BRIGHTEST = 2


@njit(cache=True, nogil=True)
def marked_rows(image, mark, rows, cols, inner, outer, rule, out_col, contrast, side_sd, span):
    """Per-row summary of the labelled optimal-path nodes for the DP trackers.

    ``rows``/``cols`` list the labelled nodes; ``mark`` is the label array of
    :func:`optimal_nodes` (bit 2: the node enters or leaves its row by a
    vertical or diagonal edge of an optimal path). For every row r:

    ``out_col[r]``
        the row's column (NaN if the row holds no labelled node), by ``rule``:
        ``RULE_MEAN`` the mean column of the labelled nodes; ``RULE_CROSSING``
        the brightest of the row's *crossing* nodes (bit 2; all labelled
        nodes if none has it); ``RULE_BRIGHTEST`` the brightest labelled
        node. Ties in brightness go to the lower median of the tied columns,
        so the column is always one of the nodes.
    ``contrast[r]``
        the intensity at that column (``RULE_MEAN``: the mean intensity of
        the labelled nodes) minus the mean of the side pixels ``inner`` to
        ``outer`` columns left and right of it (clipped to the image; 0 if
        no side pixel is in the image).
    ``side_sd[r]``
        the standard deviation of those side pixels (NaN if fewer than two).
    ``span[r]``
        the number of columns from the row's leftmost to its rightmost
        labelled node (0 if none).

    Where the stripe stays above half its height (over the darkest pixel
    within ``outer``) for more than ``inner - 2`` columns on a side (counted
    up to 64), that side's window moves out by the difference, so a wide or
    saturated stripe is not taken for its own background.

    ``image`` is (H, W) uint8 or float64, ``mark`` (H, W) uint8, ``rows`` and
    ``cols`` (n,) int64 (each labelled node once), ``inner <= outer`` >= 1;
    the outputs are (H,) float64, float64, float64 and int64. Tests:
    ``tests/trackers/test_dp_rows.py`` (a plain-Python reference).
    """
    H, W = image.shape
    cnts = np.zeros(H, np.int64)
    scols = np.zeros(H)
    svals = np.zeros(H)
    cmin = np.full(H, W, np.int64)
    cmax = np.full(H, -1, np.int64)
    for k in range(rows.shape[0]):
        r = rows[k]
        c = cols[k]
        cnts[r] += 1
        scols[r] += c
        svals[r] += image[r, c]
        cmin[r] = c if c < cmin[r] else cmin[r]
        cmax[r] = c if c > cmax[r] else cmax[r]
    tied = np.empty(W, np.int64)
    for r in range(H):
        cnt = cnts[r]
        if cnt == 0:
            out_col[r] = np.nan
            contrast[r] = np.nan
            side_sd[r] = np.nan
            span[r] = 0
            continue
        span[r] = cmax[r] - cmin[r] + 1
        if rule == RULE_MEAN:
            m = scols[r] / cnt
            level = svals[r] / cnt
        else:
            need = 3 if rule == RULE_CROSSING else 1
            any_cross = False
            if rule == RULE_CROSSING:
                for j in range(cmin[r], cmax[r] + 1):
                    if mark[r, j] & 2:
                        any_cross = True
                        break
            if not any_cross:
                need = 1
            best = -np.inf
            nt = 0
            for j in range(cmin[r], cmax[r] + 1):
                if (mark[r, j] & need) != need:
                    continue
                v = float(image[r, j])
                if v > best:
                    best = v
                    nt = 0
                if v == best:
                    tied[nt] = j
                    nt += 1
            m = float(tied[(nt - 1) // 2])
            level = best
        out_col[r] = m
        centre = int(np.floor(m + 0.5))
        # the stripe's half-maximum extent on each side of the path (wide or
        # saturated stripes push the side windows outwards)
        low = level
        for j in range(max(centre - outer, 0), min(centre + outer, W - 1) + 1):
            v = float(image[r, j])
            low = v if v < low else low
        half = 0.5 * (level + low)
        ext = [0, 0]
        for side in range(2):
            k = 0
            while k < 64:
                j = centre - (k + 1) if side == 0 else centre + (k + 1)
                if j < 0 or j >= W or image[r, j] < half:
                    break
                k += 1
            ext[side] = k
        n = 0
        s1 = 0.0
        s2 = 0.0
        for side in range(2):
            shift = ext[side] - (inner - 2) if ext[side] > inner - 2 else 0
            for d in range(inner + shift, outer + shift + 1):
                j = centre - d if side == 0 else centre + d
                if j < 0 or j >= W:
                    continue
                v = float(image[r, j])
                n += 1
                s1 += v
                s2 += v * v
        if n >= 2:
            mu = s1 / n
            var = (s2 - n * mu * mu) / (n - 1)
            if var < 0.0:
                var = 0.0
            side_sd[r] = np.sqrt(var)
            contrast[r] = level - mu
        elif n == 1:
            side_sd[r] = np.nan
            contrast[r] = level - s1
        else:
            side_sd[r] = np.nan
            contrast[r] = 0.0
