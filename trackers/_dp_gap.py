"""Numba kernels of the minimum-cost path that may leave rows out (see :mod:`trackers.dp_gap`).

The graph: the pixels of the frame, as in :mod:`trackers._dp_kernels` (half
node costs ``hc = c / 2``, an edge between neighbouring pixels costs its
weight times ``hc_p + hc_q``: 1 vertical, ``w = h_weight`` horizontal,
``sqrt(1 + w**2)`` diagonal with 8-connectivity), plus one *off* node per
row r with half cost ``ho[r]``. Edges, all directed downwards or along a
row (a path never steps upwards):

* pixel (r, j) to pixel (r, j +- 1): ``w * (hc[r, j] + hc[r, j +- 1])``;
* pixel (r-1, j) to pixel (r, j): ``hc[r-1, j] + hc[r, j]``, and with
  8-connectivity to (r, j +- 1): ``sqrt(1 + w**2) * (hc[r-1, j] + hc[r, j +- 1])``;
* off(r-1) to off(r): ``ho[r-1] + ho[r]``;
* pixel (r-1, j) to off(r) (*leaving*): ``hc[r-1, j] + ho[r] + s``;
* off(r-1) to pixel (r, j) (*entering*, at any column): ``ho[r-1] + hc[r, j] + s``;

with the switch cost ``s >= 0``. Every node of row 0 is a free start and
every node of row H-1 a goal. A path visits, in every row, either the off
node or a run of pixels; an interior node's cost is counted twice as a half
cost, once per edge, as in the paper's edge costs.

Algorithm (exact, one pass per direction, O(H * W)):

:func:`sweep` computes ``F[r, j]``, the least cost of a path from row 0 to
pixel (r, j), and ``Foff[r]`` for the off node, row by row. Every path to
row r comes from row r-1, so row r is final once row r-1 is:

1. ``E[j]`` = the least cost of reaching (r, j) by its edge from row r-1:
   from the pixel above (and the two diagonal ones), or by entering from
   off(r-1), whose best value ``Foff[r-1] + ho[r-1] + s`` is one number per
   row (the global minimum a jump after an absence needs: O(W), not O(W^2)).
2. ``F[r, j] = min_i E[i] + walk(i, j)``, the walk along row r costing
   ``w * sum(hc_k + hc_{k+1})`` over the columns between. A shortest path
   inside one row is monotone (a path that turns back visits a column
   twice; cutting out the loop removes edges that each cost
   ``w * (hc_p + hc_q) > 0``), so this is a 1-D distance transform with a
   positive, column-dependent step: a left-to-right prefix-minimum scan
   ``F[j] = min(E[j], F[j-1] + step(j-1, j))`` then a right-to-left one.
   The second scan starts from the first's values, so each ``F[j]`` is the
   minimum over walks from the left, from the right and (never better)
   both; O(W).
3. ``Foff[r] = min(Foff[r-1] + ho[r-1] + ho[r], min_j F[r-1, j] + hc[r-1, j] + ho[r] + s)``.

The same sweep on the frame turned upside down gives ``G``, the least cost
from each node to the bottom row (the graph is symmetric under the flip: an
edge's cost does not depend on its direction, and leaving and entering cost
the same). The optimum is ``OPT = min(min_j F[H-1, j], Foff[H-1])`` and a
node lies on an optimal path iff ``F + G == OPT``; an edge (p, q) iff
``F[p] + e(p, q) + G[q] == OPT`` (:func:`label`, up to a relative
tolerance for rounding). Labelling the union of all optimal paths makes the
result independent of how ties are broken, so flipping the frame flips it.

:func:`backtrack` follows one optimal path for tests and teaching (its tie
rule is in its docstring).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def sweep(hc, ho, switch, conn8, hw, down, D, Doff):
    """Least path costs from the top row (``down``) or from the bottom row.

    Parameters
    ----------
    hc : (H, W) float64
        Half node costs, > 0.
    ho : (H,) float64
        Half costs of the off nodes, > 0.
    switch : float
        Cost of leaving or entering the off state, >= 0.
    conn8 : bool
    hw : float
        ``h_weight``, > 0.
    down : bool
        True: ``D[r, j]`` is the least cost of a path from row 0 to (r, j);
        False: from (r, j) to row H-1 (the sweep on the flipped frame).
    D : (H, W) float64, Doff : (H,) float64
        Outputs.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    r0 = 0 if down else H - 1
    step = 1 if down else -1
    for j in range(W):
        D[r0, j] = 0.0
    Doff[r0] = 0.0
    for k in range(1, H):
        r = r0 + step * k
        p = r - step
        leave = np.inf
        enter = Doff[p] + ho[p] + switch
        for j in range(W):
            h = hc[r, j]
            up = D[p, j] + hc[p, j]
            leave = up if up < leave else leave
            v = up + h
            if conn8:
                if j > 0:
                    x = D[p, j - 1] + dg * (hc[p, j - 1] + h)
                    v = x if x < v else v
                if j < W - 1:
                    x = D[p, j + 1] + dg * (hc[p, j + 1] + h)
                    v = x if x < v else v
            x = enter + h
            D[r, j] = x if x < v else v
        for j in range(1, W):
            y = D[r, j - 1] + hw * (hc[r, j - 1] + hc[r, j])
            if y < D[r, j]:
                D[r, j] = y
        for j in range(W - 2, -1, -1):
            y = D[r, j + 1] + hw * (hc[r, j] + hc[r, j + 1])
            if y < D[r, j]:
                D[r, j] = y
        a = Doff[p] + ho[p] + ho[r]
        b = leave + ho[r] + switch
        Doff[r] = a if a < b else b


@njit(cache=True, nogil=True)
def optimum(F, Foff):
    """``OPT``: the least total cost, over the bottom row's pixels and off node."""
    H, W = F.shape
    best = Foff[H - 1]
    for j in range(W):
        if F[H - 1, j] < best:
            best = F[H - 1, j]
    return best


@njit(cache=True, nogil=True)
def label(hc, ho, switch, conn8, hw, F, Foff, G, Goff, rel_tol, mark, off_opt, rows, cols):
    """Label the nodes and crossing edges of every optimal path.

    ``mark[r, j]`` gets bit 1 if pixel (r, j) lies on an optimal path
    (``F + G <= OPT * (1 + rel_tol)``), bit 2 if an optimal path enters or
    leaves row r there by a vertical or diagonal edge or through an off
    node; ``off_opt[r]`` is True if an optimal path is off in row r.
    ``rows``/``cols`` (length >= H * W) receive the pixels with bit 1, row
    by row, left to right; returns their number.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    opt = optimum(F, Foff)
    lim = opt + rel_tol * abs(opt)
    for r in range(H):
        off_opt[r] = Foff[r] + Goff[r] <= lim
    n = 0
    for r in range(H):
        for j in range(W):
            if F[r, j] + G[r, j] <= lim:
                mark[r, j] = 1
                rows[n] = r
                cols[n] = j
                n += 1
            else:
                mark[r, j] = 0
    for r in range(1, H):
        p = r - 1
        enter = Foff[p] + ho[p] + switch
        leave = ho[r] + switch + Goff[r]
        for j in range(W):
            if not mark[r, j] & 1 and not mark[p, j] & 1:
                continue
            if F[p, j] + (hc[p, j] + hc[r, j]) + G[r, j] <= lim:
                mark[p, j] |= 2
                mark[r, j] |= 2
            if conn8:
                if j > 0 and F[p, j - 1] + dg * (hc[p, j - 1] + hc[r, j]) + G[r, j] <= lim:
                    mark[p, j - 1] |= 2
                    mark[r, j] |= 2
                if j < W - 1 and F[p, j + 1] + dg * (hc[p, j + 1] + hc[r, j]) + G[r, j] <= lim:
                    mark[p, j + 1] |= 2
                    mark[r, j] |= 2
            if mark[p, j] & 1 and F[p, j] + hc[p, j] + leave <= lim:
                mark[p, j] |= 2
            if mark[r, j] & 1 and enter + hc[r, j] + G[r, j] <= lim:
                mark[r, j] |= 2
    return n


@njit(cache=True, nogil=True)
def backtrack(hc, ho, switch, conn8, hw, F, Foff, rel_tol, rows, cols, off):
    """Follow one optimal path from the bottom row to row 0.

    Tie rule (the first candidate within the relative tolerance wins): the
    end is the bottom row's off node if it is optimal, else the leftmost
    optimal bottom pixel. From a pixel (r, j) the predecessor is looked for
    in the order: the pixel above, above-left, above-right (8-connectivity),
    off(r-1), the left neighbour, the right neighbour; from off(r): off(r-1),
    then the pixels of row r-1 from left to right. Writes the path's pixels
    (bottom to top) into ``rows``/``cols`` and ``off[r] = True`` for its off
    rows; returns the number of pixels, or -1 if no predecessor was found
    (a bug).
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    opt = optimum(F, Foff)
    for r in range(H):
        off[r] = False
    tol = rel_tol * abs(opt)
    r = H - 1
    j = -1
    if Foff[r] <= opt + tol:
        is_off = True
    else:
        is_off = False
        for k in range(W):
            if F[r, k] <= opt + tol:
                j = k
                break
    n = 0
    steps = 0
    while True:
        steps += 1
        if steps > H * W + H + 1:
            return -1
        if is_off:
            off[r] = True
            if r == 0:
                return n
            v = Foff[r]
            if Foff[r - 1] + ho[r - 1] + ho[r] <= v + tol:
                r -= 1
                continue
            found = False
            for k in range(W):
                if F[r - 1, k] + hc[r - 1, k] + ho[r] + switch <= v + tol:
                    r -= 1
                    j = k
                    is_off = False
                    found = True
                    break
            if not found:
                return -1
            continue
        rows[n] = r
        cols[n] = j
        n += 1
        if r == 0:
            return n
        v = F[r, j]
        h = hc[r, j]
        p = r - 1
        if F[p, j] + (hc[p, j] + h) <= v + tol:
            r = p
            continue
        if conn8 and j > 0 and F[p, j - 1] + dg * (hc[p, j - 1] + h) <= v + tol:
            r = p
            j -= 1
            continue
        if conn8 and j < W - 1 and F[p, j + 1] + dg * (hc[p, j + 1] + h) <= v + tol:
            r = p
            j += 1
            continue
        if Foff[p] + ho[p] + switch + h <= v + tol:
            r = p
            is_off = True
            continue
        if j > 0 and F[r, j - 1] + hw * (hc[r, j - 1] + h) <= v + tol:
            j -= 1
            continue
        if j < W - 1 and F[r, j + 1] + hw * (hc[r, j + 1] + h) <= v + tol:
            j += 1
            continue
        return -1
