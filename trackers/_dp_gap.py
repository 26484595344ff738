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

Algorithm (exact, one pass, O(H * W)):

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
   positive, column-dependent step: ``F = min(L, R)`` of two independent
   prefix-minimum scans, ``L[j] = min(E[j], L[j-1] + step(j-1, j))`` from the
   left and ``R`` likewise from the right; O(W). The scans are latency-bound
   chains, so each runs on the four quarters of the row at once and is then
   continued across each boundary while the carried value improves it
   (:func:`_scans`; exact: a carried value that does not beat a chain's own
   value at one column cannot beat it at the next, both adding the same step).
3. ``Foff[r] = min(Foff[r-1] + ho[r-1] + ho[r], min_j F[r-1, j] + hc[r-1, j] + ho[r] + s)``.

The optimum is ``OPT = min(min_j F[H-1, j], Foff[H-1])``. An edge (q, p)
is *tight* if ``F[q] + e(q, p) == F[p]``. Every edge costs more than 0, so
the tight edges form an acyclic graph, and its paths from row 0 to a node
are exactly that node's optimal paths; a node therefore lies on an optimal
path iff it is reached from an optimal end (a bottom node with ``F = OPT``)
by following tight edges backwards. :func:`label` does that depth-first
(each node once; an off node's predecessors are the W pixels above it and
the off node above), so it costs the size of the union of optimal paths,
not O(H * W) (tight up to a relative tolerance for rounding, as the DP
trackers' labelling). Labelling the union of all optimal paths makes the
result independent of how ties are broken; and as every edge's cost is the
same in both directions (leaving and entering cost the same), the optimal
paths of the frame turned upside down are these turned upside down, so
flipping the frame flips the result.

:func:`backtrack` follows one optimal path for tests and teaching (its tie
rule is in its docstring).

The sums are evaluated in the same order in the three kernels (``F[q] + hc[q] + hc[p]``
vertically, ``F[q] + dg * hc[q] + dg * hc[p]`` diagonally, ``F[q] + step``
along a row), so tightness tests see the sweep's own roundings.

The sweep's loops index with unsigned integers (numba then drops the
negative-index wraparound, which lets the loops run on SIMD lanes and keeps
the scans' eight chains short); the values are the same expressions in the
same order.
"""

from __future__ import annotations

import numpy as np
from numba import njit


_U1 = np.uint64(1)


@njit(cache=True, nogil=True)
def sweep(hc, ho, switch, conn8, hw, F, Foff):
    """Least path costs from the top row.

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
    F : (H, W) float64, Foff : (H,) float64
        Outputs: ``F[r, j]`` the least cost of a path from row 0 to (r, j),
        ``Foff[r]`` to off(r).
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    U = np.empty(W)
    Ud = np.empty(W)
    E = np.empty(W)
    S = np.empty(W)
    L = np.empty(W)
    R = np.empty(W)
    uW = np.uint64(W)
    one = _U1
    F0 = F[0]
    for j in range(uW):
        F0[j] = 0.0
    Foff[0] = 0.0
    leave = _row_exits(F[0], hc[0], dg, U, Ud)
    for r in range(1, H):
        p = r - 1
        hr = hc[r]
        Fr = F[r]
        enter = Foff[p] + ho[p] + switch
        for j in range(uW):
            h = hr[j]
            v = U[j] + h
            x = enter + h
            E[j] = x if x < v else v
        if conn8 and W > 1:
            x = Ud[1] + dg * hr[0]
            E[0] = x if x < E[0] else E[0]
            for j in range(one, uW - one):
                dh = dg * hr[j]
                x = Ud[j - one] + dh
                y = Ud[j + one] + dh
                x = x if x < y else y
                e = E[j]
                E[j] = x if x < e else e
            x = Ud[W - 2] + dg * hr[W - 1]
            E[W - 1] = x if x < E[W - 1] else E[W - 1]
        S[0] = 0.0
        for j in range(one, uW):
            S[j] = hw * (hr[j - one] + hr[j])
        _scans(E, S, L, R, W)
        for j in range(uW):
            x = L[j]
            y = R[j]
            Fr[j] = x if x < y else y
        a = Foff[p] + ho[p] + ho[r]
        b = leave + (ho[r] + switch)
        Foff[r] = a if a < b else b
        leave = _row_exits(Fr, hr, dg, U, Ud)


@njit(cache=True, nogil=True, inline="always")
def _row_exits(Fr, hr, dg, U, Ud):
    """``U = F[r] + hc[r]`` and ``Ud = F[r] + dg * hc[r]`` (a row's values plus
    its half costs: the start of its vertical and diagonal edges down), and
    ``min(U)`` (the best way to leave for the off node below), kept in four
    accumulators so that the reduction is not one long dependency chain."""
    W = Fr.shape[0]
    uW = np.uint64(W)
    m0 = np.inf
    m1 = np.inf
    m2 = np.inf
    m3 = np.inf
    n4 = uW // np.uint64(4)
    for k in range(n4):
        j = k * np.uint64(4)
        u0 = Fr[j] + hr[j]
        u1 = Fr[j + np.uint64(1)] + hr[j + np.uint64(1)]
        u2 = Fr[j + np.uint64(2)] + hr[j + np.uint64(2)]
        u3 = Fr[j + np.uint64(3)] + hr[j + np.uint64(3)]
        U[j] = u0
        U[j + np.uint64(1)] = u1
        U[j + np.uint64(2)] = u2
        U[j + np.uint64(3)] = u3
        m0 = u0 if u0 < m0 else m0
        m1 = u1 if u1 < m1 else m1
        m2 = u2 if u2 < m2 else m2
        m3 = u3 if u3 < m3 else m3
    for j in range(n4 * np.uint64(4), uW):
        u0 = Fr[j] + hr[j]
        U[j] = u0
        m0 = u0 if u0 < m0 else m0
    for j in range(uW):
        Ud[j] = Fr[j] + dg * hr[j]
    m0 = m1 if m1 < m0 else m0
    m2 = m3 if m3 < m2 else m2
    return m2 if m2 < m0 else m0


@njit(cache=True, nogil=True, inline="always")
def _scans(E, S, L, R, W):
    """``L[j] = min_{i <= j} E[i] + S[i+1] + ... + S[j]`` and ``R[j] = min_{i >= j} E[i] + S[j+1] + ... + S[i]``.

    The scans are latency-bound chains, so for ``W >= 16`` each runs on the
    four quarters of the row at once (eight independent chains), and is then
    continued across each boundary from the previous quarter's last value
    for as long as that improves it: once a carried value does not beat a
    chain's own value at one column it cannot beat it at the next, both
    adding the same step.
    """
    if W < 16:
        a = E[0]
        L[0] = a
        for j in range(1, W):
            y = a + S[j]
            e = E[j]
            a = y if y < e else e
            L[j] = a
        b = E[W - 1]
        R[W - 1] = b
        for j in range(W - 2, -1, -1):
            y = b + S[j + 1]
            e = E[j]
            b = y if y < e else e
            R[j] = b
        return
    one = np.uint64(1)
    uW = np.uint64(W)
    q = uW // np.uint64(4)
    s1 = q
    s2 = np.uint64(2) * q
    s3 = np.uint64(3) * q
    a0 = E[0]
    a1 = E[s1]
    a2 = E[s2]
    a3 = E[s3]
    L[0] = a0
    L[s1] = a1
    L[s2] = a2
    L[s3] = a3
    b0 = E[s1 - one]
    b1 = E[s2 - one]
    b2 = E[s3 - one]
    b3 = E[uW - one]
    R[s1 - one] = b0
    R[s2 - one] = b1
    R[s3 - one] = b2
    R[uW - one] = b3
    for k in range(one, q):
        j = k
        y = a0 + S[j]
        e = E[j]
        a0 = y if y < e else e
        L[j] = a0
        j = s1 + k
        y = a1 + S[j]
        e = E[j]
        a1 = y if y < e else e
        L[j] = a1
        j = s2 + k
        y = a2 + S[j]
        e = E[j]
        a2 = y if y < e else e
        L[j] = a2
        j = s3 + k
        y = a3 + S[j]
        e = E[j]
        a3 = y if y < e else e
        L[j] = a3
        i = s1 - one - k
        y = b0 + S[i + one]
        e = E[i]
        b0 = y if y < e else e
        R[i] = b0
        i = s2 - one - k
        y = b1 + S[i + one]
        e = E[i]
        b1 = y if y < e else e
        R[i] = b1
        i = s3 - one - k
        y = b2 + S[i + one]
        e = E[i]
        b2 = y if y < e else e
        R[i] = b2
        i = uW - one - k
        y = b3 + S[i + one]
        e = E[i]
        b3 = y if y < e else e
        R[i] = b3
    for k in range(q, uW - s3):  # the last segment's tail
        j = s3 + k
        y = a3 + S[j]
        e = E[j]
        a3 = y if y < e else e
        L[j] = a3
        i = uW - one - k
        y = b3 + S[i + one]
        e = E[i]
        b3 = y if y < e else e
        R[i] = b3
    for st in (np.int64(s1), np.int64(s2), np.int64(s3)):
        c = L[st - 1]
        for j in range(st, W):
            y = c + S[j]
            if y < L[j]:
                L[j] = y
                c = y
            else:
                break
    for st in (np.int64(s3), np.int64(s2), np.int64(s1)):
        c = R[st]
        for j in range(st - 1, -1, -1):
            y = c + S[j + 1]
            if y < R[j]:
                R[j] = y
                c = y
            else:
                break


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
def label(hc, ho, switch, conn8, hw, F, Foff, rel_tol, mark, off_opt, rows, cols):
    """Label the nodes and crossing edges of every optimal path.

    Depth-first from the optimal ends along tight edges backwards (see the
    module notes; an edge is tight when ``|F[q] + e - F[p]| <= rel_tol * OPT``).
    ``mark`` (zeroed by the caller) gets bit 1 on every pixel of an optimal
    path and bit 2 where an optimal path enters or leaves the pixel's row by
    a vertical or diagonal edge or through an off node; ``off_opt[r]`` (set
    here) is True if an optimal path is off in row r. ``rows``/``cols``
    (length >= H * W) receive the labelled pixels; returns their number.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    opt = optimum(F, Foff)
    tol = rel_tol * abs(opt)
    for r in range(H):
        off_opt[r] = False
    stack = np.empty(H * W + H, np.int64)  # pixel r * W + j, off node H * W + r
    n = 0
    top = 0
    if Foff[H - 1] <= opt + tol:
        off_opt[H - 1] = True
        stack[top] = H * W + H - 1
        top += 1
    for j in range(W):
        if F[H - 1, j] <= opt + tol:
            mark[H - 1, j] = 1
            rows[n] = H - 1
            cols[n] = j
            n += 1
            stack[top] = (H - 1) * W + j
            top += 1
    while top > 0:
        top -= 1
        node = stack[top]
        if node >= H * W:
            r = node - H * W
            if r == 0:
                continue
            p = r - 1
            v = Foff[r]
            if abs(Foff[p] + ho[p] + ho[r] - v) <= tol and not off_opt[p]:
                off_opt[p] = True
                stack[top] = H * W + p
                top += 1
            c = ho[r] + switch
            for k in range(W):
                if abs(F[p, k] + hc[p, k] + c - v) <= tol:
                    mark[p, k] |= 2
                    if not mark[p, k] & 1:
                        mark[p, k] |= 1
                        rows[n] = p
                        cols[n] = k
                        n += 1
                        stack[top] = p * W + k
                        top += 1
            continue
        r = node // W
        j = node - r * W
        if r == 0:
            continue
        p = r - 1
        v = F[r, j]
        h = hc[r, j]
        for dj in range(-1, 2):
            k = j + dj
            if k < 0 or k >= W or (dj != 0 and not conn8):
                continue
            if dj == 0:
                x = F[p, k] + hc[p, k] + h
            else:
                x = F[p, k] + dg * hc[p, k] + dg * h
            if abs(x - v) <= tol:
                mark[r, j] |= 2
                mark[p, k] |= 2
                if not mark[p, k] & 1:
                    mark[p, k] |= 1
                    rows[n] = p
                    cols[n] = k
                    n += 1
                    stack[top] = p * W + k
                    top += 1
        if abs(Foff[p] + ho[p] + switch + h - v) <= tol:
            mark[r, j] |= 2
            if not off_opt[p]:
                off_opt[p] = True
                stack[top] = H * W + p
                top += 1
        for dj in (-1, 1):
            k = j + dj
            if k < 0 or k >= W:
                continue
            s = hw * (hc[r, k] + h) if dj < 0 else hw * (h + hc[r, k])
            if abs(F[r, k] + s - v) <= tol and not mark[r, k] & 1:
                mark[r, k] |= 1
                rows[n] = r
                cols[n] = k
                n += 1
                stack[top] = r * W + k
                top += 1
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
            if abs(Foff[r - 1] + ho[r - 1] + ho[r] - v) <= tol:
                r -= 1
                continue
            found = False
            for k in range(W):
                if abs(F[r - 1, k] + hc[r - 1, k] + (ho[r] + switch) - v) <= tol:
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
        if abs(F[p, j] + hc[p, j] + h - v) <= tol:
            r = p
            continue
        if conn8 and j > 0 and abs(F[p, j - 1] + dg * hc[p, j - 1] + dg * h - v) <= tol:
            r = p
            j -= 1
            continue
        if conn8 and j < W - 1 and abs(F[p, j + 1] + dg * hc[p, j + 1] + dg * h - v) <= tol:
            r = p
            j += 1
            continue
        if abs(Foff[p] + ho[p] + switch + h - v) <= tol:
            r = p
            is_off = True
            continue
        if j > 0 and abs(F[r, j - 1] + hw * (hc[r, j - 1] + h) - v) <= tol:
            j -= 1
            continue
        if j < W - 1 and abs(F[r, j + 1] + hw * (h + hc[r, j + 1]) - v) <= tol:
            j += 1
            continue
        return -1
