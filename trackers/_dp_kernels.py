"""Numba kernels for the minimum-cost stripe path (see :mod:`trackers.dp`).

The graph: one node per pixel, node cost ``c = 1 / (max(I, 0) + eps)``. With
the horizontal weight ``w = h_weight > 0`` (finite), the edge between
neighbouring pixels p, q costs ``(c_p + c_q) / 2`` times 1 (vertical), ``w``
(horizontal) or ``sqrt(1 + w**2)`` (diagonal, 8-connectivity); ``w = 1`` is
the isotropic cost of skimage's ``MCP_Geometric``. The kernels work on half
node costs ``hc = c / 2``, so an edge costs its weight times ``hc_p + hc_q``.
Sources: every pixel of the top row (distance 0). Goal: any pixel of the
bottom row.

Algorithm (exact, label-correcting by row sweeps):

1. One forward sweep, top to bottom. Row r is relaxed from row r-1 (vertical
   and, for 8-connectivity, diagonal edges), then along the row by two
   independent chains (left-to-right and right-to-left). The shortest path
   *inside* one row from a set of seeds is monotone: a path that turns back
   visits a column twice, and cutting out the loop removes edges that each
   cost ``w * (hc_p + hc_q) > 0``; so ``min(L(a), R(a))`` is exact for every
   ``w > 0``. After this sweep ``D`` is exact for every path that never
   steps upwards, and ``U = min(D[H-1])`` is the cost of a real path (an
   upper bound).
2. Certificate sweeps, alternately bottom-up and top-down, relax every edge
   again and propagate improvements along the row from the changed columns
   only. An improvement is *relevant* only if the new value is below
   ``U - LB[r]``, where ``LB[r]`` is a lower bound on the cost from row r to
   the bottom row. Re-derived for ``w``: a path from row r to row H-1
   crosses every boundary between rows k and k+1 (k >= r) at least once, by
   a vertical edge (cost ``hc[k, j] + hc[k+1, j] >= rowmin[k] +
   rowmin[k+1]``) or a diagonal one (the same sum times ``sqrt(1 + w**2)
   >= 1``); its horizontal edges cost ``>= 0``. Hence
   ``LB[r] = sum_{k >= r} (rowmin[k] + rowmin[k+1])`` holds for every ``w``
   and does not depend on it (bounding the least crossing edge instead of
   the row minima was measured to shrink the set of relevant nodes by at
   most 2 % on the benchmark frames, so it is not done). A node on any
   optimal path satisfies ``d(p) <= U* - LB[r] <= U - LB[r]``; by induction
   along that path, once a sweep finds no relevant improvement, every node
   of every optimal path holds its exact distance. The sweeps stop then.
3. Backtracking from the cheapest bottom node follows, at each node, the
   neighbour q minimising ``D[q] + e(q, p)`` (fixed neighbour order, so ties
   are broken deterministically). Because the nodes of optimal paths are
   exact and every other ``D`` is an upper bound of a true distance, that
   neighbour lies on an optimal path.

The first sweep is banded by an upper bound known before it runs: the cost
of the best monotone path inside a corridor around the rows' brightest
pixels and their running median, computed with the same weighted edges (so
it is the cost of a real path for every ``w``; see :func:`accumulate`).

With ``bound=False`` the sweeps run until nothing changes at all, which makes
the whole field exact (used for figures of the accumulated cost).

Implementation (speed, not the result): the relaxation of a row from its
neighbour (:func:`_vertical`) has no data-dependent branch and unsigned loop
indices (numba then drops the negative-index wraparound, and the loop runs
on SIMD lanes); the walk along a row (:func:`_chains`) computes the two
chains independently, each as two halves at once (four independent
dependency chains instead of one), and takes their minimum. Every value is
the same floating-point expression, evaluated in the same order, as in the
straightforward loops: ``min(L, R)`` of the two chains equals the
right-to-left chain run over the left-to-right one's result (a walk that
turns back adds positive steps, and rounding is monotone), and a half's
chain continued from the other half's last value while that improves it
equals the chain run from the row's start (once a carried value does not
beat the chain's own at one column, it cannot at the next: both add the
same step). The fields are bit for bit those of the former scalar loops
(``python scripts/dp_kernel_identity.py``: the perf frame set, both
connectivities at ``h_weight`` 1 and 0.25, sweep counts, labels and paths
included; docs/dp.md, Speed).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_REL_TOL = 1e-12

# neighbours in the order backtracking prefers them (ties go to the first):
# up, up-left, up-right, left, right, down, down-left, down-right
_DR = np.array([-1, -1, -1, 0, 0, 1, 1, 1])
_DJ = np.array([0, -1, 1, -1, 1, 0, -1, 1])
_DIAG = np.array([False, True, True, False, False, False, True, True])


_U1 = np.uint64(1)
_U2 = np.uint64(2)


@njit(cache=True, nogil=True)
def half_cost_u8(image, eps, out, rowmin, centre, rightc=None):
    """``out = 0.5 / (image + eps)`` for a uint8 image (a 256-entry table);
    also each row's least half cost and its leftmost column (``centre``) and,
    if given, its rightmost column (``rightc``)."""
    lut = np.empty(256)
    for v in range(256):
        lut[v] = 0.5 / (v + eps)
    H, W = image.shape
    uW = np.uint64(W)
    for r in range(H):
        row = image[r]
        o = out[r]
        for j in range(uW):
            o[j] = lut[row[j]]
        m = row[0]
        for j in range(uW):
            x = row[j]
            m = x if x > m else m
        first = uW
        last = np.uint64(0)
        for j in range(uW):
            eq = row[j] == m
            first = min(first, j if eq else uW)
            last = max(last, j if eq else np.uint64(0))
        rowmin[r] = lut[m]
        centre[r] = first
        if rightc is not None:
            rightc[r] = last


@njit(cache=True, nogil=True)
def half_cost_float(image, eps, out, rowmin, centre, rightc=None):
    """``out = 0.5 / (max(image, 0) + eps)`` for a float64 image; also each
    row's least half cost and its leftmost column (``centre``) and, if given,
    its rightmost column (``rightc``)."""
    H, W = image.shape
    uW = np.uint64(W)
    for r in range(H):
        row = image[r]
        o = out[r]
        for j in range(uW):
            v = row[j]
            v = v if v > 0.0 else 0.0
            o[j] = 0.5 / (v + eps)
        row_stats_into(out, r, rowmin, centre, rightc)


@njit(cache=True, nogil=True)
def row_stats_into(hc, r, rowmin, centre, rightc=None):
    """Row r's least half cost, its leftmost column and, if ``rightc`` is
    given, its rightmost column."""
    W = hc.shape[1]
    uW = np.uint64(W)
    row = hc[r]
    m = row[0]
    for j in range(uW):
        x = row[j]
        m = x if x < m else m
    first = uW
    last = np.uint64(0)
    for j in range(uW):
        eq = row[j] == m
        first = min(first, j if eq else uW)
        last = max(last, j if eq else np.uint64(0))
    rowmin[r] = m
    centre[r] = first
    if rightc is not None:
        rightc[r] = last


@njit(cache=True, nogil=True)
def row_stats(hc, rowmin, centre, rightc=None):
    """Each row's least half cost, its leftmost column and, if ``rightc`` is
    given, its rightmost column."""
    for r in range(hc.shape[0]):
        row_stats_into(hc, r, rowmin, centre, rightc)


@njit(cache=True, nogil=True)
def _vertical(Dr, Ds, hr, hs, conn8, dg, a, b, limit, keep):
    """Relax nodes a..b of row r through the edges from row s (vertical and,
    with ``conn8``, diagonal): ``D[r, j] = min(D[r, j], candidate)``.

    Returns ``(n, nch, first, last)``: how many columns improved to below
    ``limit``, how many of them by more than the relative tolerance
    (``keep = 1 - tol``), and the first and last of them. Unsigned loop
    indices (no negative-index wraparound) let the loops vectorise."""
    W = hr.shape[0]
    one = _U1
    n = 0
    nch = 0
    first = np.uint64(W)
    last = np.uint64(0)
    if conn8 and W > 1:
        lo = np.uint64(a if a > 0 else 1)
        hi = np.uint64(b if b < W - 1 else W - 2)
        if a == 0:
            h = hr[0]
            v = Ds[0] + (hs[0] + h)
            w = Ds[1] + dg * (hs[1] + h)
            v = w if w < v else v
            o = Dr[0]
            Dr[0] = v if v < o else o
            rel = (v < o) & (v < limit)
            n += rel
            nch += rel & (v < o * keep)
            first = np.uint64(0) if rel else first
            last = one if rel else last
        for j in range(lo, hi + one):
            h = hr[j]
            v = Ds[j] + (hs[j] + h)
            w = Ds[j - one] + dg * (hs[j - one] + h)
            v = w if w < v else v
            w = Ds[j + one] + dg * (hs[j + one] + h)
            v = w if w < v else v
            o = Dr[j]
            Dr[j] = v if v < o else o
            rel = (v < o) & (v < limit)
            n += rel
            nch += rel & (v < o * keep)
            first = min(first, j if rel else np.uint64(W))
            last = max(last, j + one if rel else np.uint64(0))
        if b == W - 1:
            j = W - 1
            h = hr[j]
            v = Ds[j] + (hs[j] + h)
            w = Ds[j - 1] + dg * (hs[j - 1] + h)
            v = w if w < v else v
            o = Dr[j]
            Dr[j] = v if v < o else o
            rel = (v < o) & (v < limit)
            n += rel
            nch += rel & (v < o * keep)
            first = min(first, np.uint64(j) if rel else np.uint64(W))
            last = np.uint64(W) if rel else last
    else:
        for j in range(np.uint64(a), np.uint64(b) + one):
            v = Ds[j] + (hs[j] + hr[j])
            o = Dr[j]
            Dr[j] = v if v < o else o
            rel = (v < o) & (v < limit)
            n += rel
            nch += rel & (v < o * keep)
            first = min(first, j if rel else np.uint64(W))
            last = max(last, j + one if rel else np.uint64(0))
    return n, nch, np.int64(first), np.int64(last) - 1


@njit(cache=True, nogil=True)
def _chains(Dr, hr, hw, first, last, limit, keep, TL, TR, S):
    """Walks along one row: ``Dr[first..last] = min(L, R)``, the
    left-to-right and right-to-left chains ``L[j] = min(Dr[j], L[j-1] +
    step(j-1, j))`` (and ``R`` likewise) started from the current values
    (``first < last``). Returns how many values below ``limit`` improved by
    more than the relative tolerance (``keep = 1 - tol``).

    ``min(L, R)`` is the result of the two chains run one after the other
    (a walk that turns back is never cheaper: the steps are positive and
    rounding is monotone), and each chain runs as two halves at once (four
    independent chains, which the latency of one chain would otherwise
    leave idle), the second half then continued from the first half's last
    value for as long as that improves it: once a carried value does not beat
    the chain's own value at one column it cannot beat it at the next, both
    adding the same step. The result is bit for bit the sequential chains'."""
    one = _U1
    f = np.uint64(first)
    l = np.uint64(last)
    for j in range(f + one, l + one):
        S[j] = hw * (hr[j - one] + hr[j])
    n = l - f + one
    if n < 16:
        xl = Dr[f]
        xr = Dr[l]
        TL[f] = xl
        TR[l] = xr
        for k in range(one, n):
            j = f + k
            y = xl + S[j]
            o = Dr[j]
            xl = y if y < o else o
            TL[j] = xl
            i = l - k
            y = xr + S[i + one]
            o = Dr[i]
            xr = y if y < o else o
            TR[i] = xr
    else:
        h = n // _U2
        m = f + h  # halves f..m-1 and m..l (the second one longer by one if n is odd)
        l0 = Dr[f]
        l1 = Dr[m]
        r0 = Dr[m - one]
        r1 = Dr[l]
        TL[f] = l0
        TL[m] = l1
        TR[m - one] = r0
        TR[l] = r1
        for k in range(one, h):
            j = f + k
            y = l0 + S[j]
            o = Dr[j]
            l0 = y if y < o else o
            TL[j] = l0
            j = m + k
            y = l1 + S[j]
            o = Dr[j]
            l1 = y if y < o else o
            TL[j] = l1
            i = m - one - k
            y = r0 + S[i + one]
            o = Dr[i]
            r0 = y if y < o else o
            TR[i] = r0
            i = l - k
            y = r1 + S[i + one]
            o = Dr[i]
            r1 = y if y < o else o
            TR[i] = r1
        if n > h + h:  # the second half's last column
            y = l1 + S[l]
            o = Dr[l]
            TL[l] = y if y < o else o
            i = m
            y = r1 + S[i + one]
            o = Dr[i]
            TR[i] = y if y < o else o
        c = TL[m - one]
        for j in range(m, l + one):
            y = c + S[j]
            if y < TL[j]:
                TL[j] = y
                c = y
            else:
                break
        c = TR[m]
        i = m - one
        while True:
            y = c + S[i + one]
            if y < TR[i]:
                TR[i] = y
                c = y
            else:
                break
            if i == f:
                break
            i -= one
    nch = 0
    for j in range(f, l + one):
        x = TL[j]
        y = TR[j]
        v = x if x < y else y
        nch += (v < limit) & (v < Dr[j] * keep)
        Dr[j] = v
    return nch


@njit(cache=True, nogil=True)
def _relax_span(D, hc, r, s, conn8, hw, dg, W, a, b, limit, tol, TL, TR, S):
    """Relax nodes a..b of row r through the edges from row s, then
    propagate along row r from the improved nodes.

    Only values below ``limit`` matter (see the module notes): propagation
    past the improved range stops at the first node it cannot bring below
    ``limit``. Returns ``(changed, lo, hi, va, vb)``: whether a value below
    ``limit`` improved by more than the relative tolerance ``tol``; the hull
    lo..hi of the columns whose values this call brought below ``limit``
    (lo > hi if none); the range va..vb it visited."""
    keep = 1.0 - tol
    Dr = D[r]
    hr = hc[r]
    n, nch, first, last = _vertical(Dr, D[s], hr, hc[s], conn8, dg, a, b, limit, keep)
    if n == 0:
        return False, W, -1, a, b
    if last > first:
        nch += _chains(Dr, hr, hw, first, last, limit, keep, TL, TR, S)
    # onwards past last while the chain improves below limit
    x = Dr[last]
    j = last + 1
    while j < W:
        y = x + hw * (hr[j - 1] + hr[j])
        old = Dr[j]
        if not (y < limit and y < old):
            break
        Dr[j] = y
        nch += y < old * keep
        x = y
        j += 1
    hi = j - 1
    x = Dr[first]
    j = first - 1
    while j >= 0:
        y = x + hw * (hr[j] + hr[j + 1])
        old = Dr[j]
        if not (y < limit and y < old):
            break
        Dr[j] = y
        nch += y < old * keep
        x = y
        j -= 1
    lo = j + 1
    va = lo if lo < a else a
    vb = hi if hi > b else b
    return nch > 0, lo, hi, va, vb


@njit(cache=True, nogil=True)
def _span(lo, hi, r, W):
    a = lo[r] - 1
    b = hi[r] + 1
    if a < 0:
        a = 0
    if b > W - 1:
        b = W - 1
    return a, b


@njit(cache=True, nogil=True)
def _forward(D, hc, conn8, hw, dg, lb, limit0, tol, lo, hi, vlo, vhi, TL, TR, S):
    """Banded forward sweep: row r is relaxed from the relevant span of row
    r - 1 only (nodes with ``D < limit0 - lb``). Returns the least bottom value."""
    H, W = hc.shape
    for j in range(W):
        D[0, j] = 0.0
    lo[0] = 0
    hi[0] = W - 1
    vlo[0] = 0
    vhi[0] = W - 1
    for r in range(1, H):
        a, b = _span(lo, hi, r - 1, W)
        if lo[r - 1] > hi[r - 1]:
            lo[r] = W
            hi[r] = -1
            vlo[r] = W
            vhi[r] = -1
            continue
        ch, l_, h_, va, vb = _relax_span(D, hc, r, r - 1, conn8, hw, dg, W, a, b, limit0 - lb[r], tol, TL, TR, S)
        lo[r] = l_
        hi[r] = h_
        vlo[r] = va
        vhi[r] = vb
    best = np.inf
    for j in range(vlo[H - 1], vhi[H - 1] + 1):
        if D[H - 1, j] < best:
            best = D[H - 1, j]
    return best


@njit(cache=True, nogil=True)
def _corridor_bound(hc, conn8, hw, dg, left, right, TL, TR, S):
    """Cost of the best monotone path (down and along rows) confined to a
    corridor: row r may use columns ``left[r]..right[r]``; consecutive rows'
    ranges must overlap. It is the cost of a real path: an upper bound of
    the optimum, tight when the corridor holds the stripe."""
    H, W = hc.shape
    prev = np.full(W, np.inf)
    cur = np.full(W, np.inf)
    pa = 0
    pb = W - 1
    for j in range(W):
        prev[j] = 0.0
    for r in range(1, H):
        a = left[r]
        b = right[r]
        _vertical(cur, prev, hc[r], hc[r - 1], conn8, dg, a, b, np.inf, 1.0)
        if b > a:
            _chains(cur, hc[r], hw, a, b, np.inf, 1.0, TL, TR, S)
        for j in range(np.uint64(pa), np.uint64(pb) + _U1):
            prev[j] = np.inf
        prev, cur = cur, prev
        pa = a
        pb = b
    best = np.inf
    for j in range(pa, pb + 1):
        if prev[j] < best:
            best = prev[j]
    return best


@njit(cache=True, nogil=True)
def accumulate(hc, conn8, bound, D, rowmin, centre, hw=1.0, rightc=None):
    """Fill ``D`` with distances from the top row; returns the sweep count.

    Parameters
    ----------
    hc : (H, W) float64
        Half node costs, ``0.5 * c``.
    conn8 : bool
        8-connectivity if True, else 4-connectivity.
    bound : bool
        If True, only nodes that can lie on an optimal path are guaranteed
        exact; every other value is the cost of a real path or +inf (an upper
        bound). If False, the whole field is exact.
    D : (H, W) float64
        Output.
    rowmin, centre : (H,) float64 and int64
        Each row's least ``hc`` and a column where it occurs (see
        :func:`row_stats`).
    hw : float, default 1.0
        ``h_weight``, the horizontal edge weight (> 0, finite); diagonal
        edges weigh ``sqrt(1 + hw**2)``.
    rightc : (H,) int64, optional
        Each row's rightmost column holding ``rowmin`` (the half cost kernels
        give it with the row minima; computed here if omitted).

    Notes
    -----
    With ``bound``, the first (banded) forward sweep needs an upper bound of
    the optimum before it is known: the cost of the best monotone path inside
    a corridor spanning, in row r, the brightest pixels of the 9 nearest rows
    (all tied brightest pixels of a row, so a flat row spans its width) and
    the running median of the rows' brightest column (every other row within
    24 rows, refreshed every 8 rows; it keeps a glint from pulling the
    corridor off the stripe), +-8 columns. Every node of that path lies
    inside the band, so the sweep succeeds at once; the doubling retry only
    guards against rounding. The corridor only sets the band's width: the
    result is exact whatever it is. Measured on the perf frame set (one
    frame per kind and size, CPU ms median, 4-conn / 8-conn at
    ``h_weight=1``): 2.8 / 4.8 before the tie and median terms, 1.9 / 2.9
    with them (a gaps frame, 8-conn: 4.5 -> 1.6 ms).
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    lo = np.empty(H, np.int64)
    hi = np.empty(H, np.int64)
    vlo = np.empty(H, np.int64)
    vhi = np.empty(H, np.int64)
    lb = np.zeros(H)
    TL = np.empty(W)
    TR = np.empty(W)
    S = np.empty(W)
    uW = np.uint64(W)
    for r in range(H):
        Dr = D[r]
        for j in range(uW):
            Dr[j] = np.inf
    if bound:
        for r in range(H - 2, -1, -1):
            lb[r] = lb[r + 1] + rowmin[r] + rowmin[r + 1]
        tol = _REL_TOL
        # an upper bound from a corridor around each row's brightest pixels:
        # row r spans the brightest pixels of rows r-4..r+4 (all of a row's
        # tied brightest pixels: a flat row, a cut, spans its whole width),
        # widened by 8 columns (wide where the brightest pixel jumps: cuts,
        # glints)
        if rightc is None:
            rc = np.empty(H, np.int64)
            for r in range(H):
                row = hc[r]
                m = rowmin[r]
                k = np.uint64(0)
                for j in range(uW):
                    k = max(k, j if row[j] == m else np.uint64(0))
                rc[r] = max(np.int64(k), centre[r])
        else:
            rc = rightc
        left = np.empty(H, np.int64)
        right = np.empty(H, np.int64)
        fc = centre.astype(np.float64)
        med = 0
        for r in range(H):
            # and the median brightest column of every other row within 24
            # rows (refreshed every 8 rows), so that a glint shorter than
            # about 24 rows does not pull the corridor off the stripe
            if r % 8 == 0:
                a = r - 24 if r >= 24 else 0
                b = r + 32 if r + 32 < H else H
                med = int(np.median(fc[a:b:2]))
            a = r - 4 if r >= 4 else 0
            b = r + 4 if r + 4 < H else H - 1
            mn = med if med < centre[a] else centre[a]
            mx = med if med > rc[a] else rc[a]
            for i in range(a + 1, b + 1):
                x = centre[i]
                mn = x if x < mn else mn
                x = rc[i]
                mx = x if x > mx else mx
            left[r] = mn - 8 if mn >= 8 else 0
            right[r] = mx + 8 if mx + 8 < W else W - 1
        U0 = _corridor_bound(hc, conn8, hw, dg, left, right, TL, TR, S)
        slack = U0 * (1.0 + 1e-9) - lb[0]
        attempts = 0
        while True:
            limit0 = lb[0] + slack if attempts < 60 else np.inf
            best = _forward(D, hc, conn8, hw, dg, lb, limit0, tol, lo, hi, vlo, vhi, TL, TR, S)
            attempts += 1
            if best < limit0:
                break
            for r in range(H):
                for j in range(vlo[r], vhi[r] + 1):
                    D[r, j] = np.inf
            slack = 2.0 * slack + 1e-300
        U = best * (1.0 + 1e-9) + 1e-300
        # shrink the spans to the nodes relevant under the path just found
        for r in range(H):
            Dr = D[r]
            lim = U - lb[r]
            l_ = uW
            h_ = np.uint64(0)
            if vlo[r] <= vhi[r]:
                for j in range(np.uint64(vlo[r]), np.uint64(vhi[r]) + _U1):
                    inside = Dr[j] < lim
                    l_ = min(l_, j if inside else uW)
                    h_ = max(h_, j + _U1 if inside else np.uint64(0))
            lo[r] = np.int64(l_)
            hi[r] = np.int64(h_) - 1
    else:
        tol = 0.0
        U = np.inf
        _forward(D, hc, conn8, hw, dg, lb, U, tol, lo, hi, vlo, vhi, TL, TR, S)
        attempts = 1
    sweeps = attempts
    if H < 3:
        return sweeps
    # certificate sweeps. ver[r] counts the relevant changes of row r;
    # up[r] / dn[r] remember ver[r-1] / ver[r+1] when row r was last relaxed
    # from above / below, so a row is only relaxed again from a neighbour
    # that changed since.
    ver = np.ones(H, np.int64)
    up = np.ones(H, np.int64)
    dn = np.zeros(H, np.int64)
    while True:
        changed = False
        for r in range(H - 2, 0, -1):
            if lo[r + 1] > hi[r + 1] or dn[r] == ver[r + 1]:
                continue
            dn[r] = ver[r + 1]
            a, b = _span(lo, hi, r + 1, W)
            ch, l_, h_, va, vb = _relax_span(D, hc, r, r + 1, conn8, hw, dg, W, a, b, U - lb[r], tol, TL, TR, S)
            if ch:
                changed = True
                ver[r] += 1
                lo[r] = min(lo[r], l_)
                hi[r] = max(hi[r], h_)
        sweeps += 1
        if not changed:
            break
        changed = False
        for r in range(1, H):
            if lo[r - 1] > hi[r - 1] or up[r] == ver[r - 1]:
                continue
            up[r] = ver[r - 1]
            a, b = _span(lo, hi, r - 1, W)
            ch, l_, h_, va, vb = _relax_span(D, hc, r, r - 1, conn8, hw, dg, W, a, b, U - lb[r], tol, TL, TR, S)
            if ch:
                changed = True
                ver[r] += 1
                lo[r] = min(lo[r], l_)
                hi[r] = max(hi[r], h_)
        sweeps += 1
        if not changed:
            break
    return sweeps


@njit(cache=True, nogil=True)
def backtrack(D, hc, conn8, rows, cols, hw=1.0):
    """Follow the cheapest predecessors from the best bottom node to row 0.

    Writes the path (bottom to top) into ``rows``/``cols`` and returns its
    length. Neighbour order (ties resolved by the first): up, up-left,
    up-right, left, right, down, down-left, down-right (diagonals only with
    8-connectivity). The end node is the bottom-row node of least ``D``; ties
    go to the cheapest (brightest) node, then to the leftmost.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    r = H - 1
    j = 0
    best = D[r, 0]
    for k in range(1, W):
        v = D[r, k]
        if v < best or (v == best and hc[r, k] < hc[r, j]):
            best = v
            j = k
    n = 0
    rows[n] = r
    cols[n] = j
    n += 1
    limit = rows.shape[0]
    while r > 0:
        br = -1
        bj = -1
        bv = np.inf
        for m in range(8):
            dr, dj, diag = _DR[m], _DJ[m], _DIAG[m]
            if diag and not conn8:
                continue
            rr = r + dr
            jj = j + dj
            if rr < 0 or rr >= H or jj < 0 or jj >= W:
                continue
            e = hc[rr, jj] + hc[r, j]
            if diag:
                e *= dg
            elif dr == 0:
                e *= hw
            v = D[rr, jj] + e
            if v < bv:
                bv = v
                br = rr
                bj = jj
        r = br
        j = bj
        if n >= limit:
            return -1
        rows[n] = r
        cols[n] = j
        n += 1
    return n


@njit(cache=True, nogil=True)
def path_cost(hc, rows, cols, hw=1.0):
    """Sum of edge costs along a path given as pixel indices."""
    dg = np.sqrt(1.0 + hw * hw)
    total = 0.0
    for k in range(1, rows.shape[0]):
        e = hc[rows[k - 1], cols[k - 1]] + hc[rows[k], cols[k]]
        if rows[k] != rows[k - 1] and cols[k] != cols[k - 1]:
            e *= dg
        elif rows[k] == rows[k - 1]:
            e *= hw
        total += e
    return total


@njit(cache=True, nogil=True)
def optimal_nodes(D, hc, conn8, rel_tol, mark, out_r, out_c, hw=1.0):
    """Mark every node lying on some optimal top-to-bottom path.

    This is the paper's "expansive" backtracking: start at every bottom node
    whose ``D`` equals the optimum and repeatedly label each neighbour q of a
    labelled node p with ``D[q] + e(q, p) == D[p]`` (to a relative tolerance
    ``rel_tol`` of the optimum), stopping at the top row. Unlike one
    backtracked path, the labelled set does not depend on tie-breaking, so it
    is symmetric under flipping the image. Returns the number n of labelled
    nodes, listed in ``out_r[:n]``/``out_c[:n]`` (each of size H * W);
    ``mark`` (uint8, H x W, zeroed by the caller) receives bit 1 on every
    labelled node and bit 2 on every labelled node at either end of a tight
    vertical or diagonal edge (where an optimal path enters or leaves its
    row).
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    U = np.inf
    for j in range(W):
        if D[H - 1, j] < U:
            U = D[H - 1, j]
    tol = rel_tol * U
    stack_r = np.empty(H * W, np.int64)
    stack_c = np.empty(H * W, np.int64)
    n = 0
    count = 0
    for j in range(W):
        if D[H - 1, j] <= U + tol:
            mark[H - 1, j] = 1
            out_r[count] = H - 1
            out_c[count] = j
            count += 1
            stack_r[n] = H - 1
            stack_c[n] = j
            n += 1
    while n > 0:
        n -= 1
        r = stack_r[n]
        j = stack_c[n]
        if r == 0:
            continue
        for m in range(8):
            dr, dj, diag = _DR[m], _DJ[m], _DIAG[m]
            if diag and not conn8:
                continue
            rr = r + dr
            jj = j + dj
            if rr < 0 or rr >= H or jj < 0 or jj >= W:
                continue
            e = hc[rr, jj] + hc[r, j]
            if diag:
                e *= dg
            elif dr == 0:
                e *= hw
            if abs(D[rr, jj] + e - D[r, j]) > tol:
                continue
            if dr != 0:  # an optimal path crosses between the rows here
                mark[r, j] |= 2
                mark[rr, jj] |= 2
            if not mark[rr, jj] & 1:
                mark[rr, jj] |= 1
                out_r[count] = rr
                out_c[count] = jj
                count += 1
                stack_r[n] = rr
                stack_c[n] = jj
                n += 1
    return count
