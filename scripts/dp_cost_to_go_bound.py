"""An experiment not kept: the DP solver pruned by a column-aware lower bound of the cost-to-go.

The solver of ``trackers._dp_kernels`` keeps a node in play while ``D + LB[r] < U``, with ``LB[r]``
a lower bound of the cost from row r to the bottom that only knows each row's cheapest pixel. This
prototype replaces ``LB[r]`` by a per-node bound (:func:`cost_to_go_bound`): the optimum of a
relaxed problem in which every move between columns j and j+1 costs its least possible value
``h_weight * (m_j + m_{j+1})`` (``m_j`` the column's least half cost over all rows) and the crossings
of each group of ``BOUND_GROUP`` row boundaries are charged at one column, ``group`` times the least
crossing cost there (a path's last crossings of the boundaries are ordered, its column moves between
them cost at least the relaxed metric, so the relaxed optimum is a lower bound; see the comments).
The first sweep's limit starts just above the bound's optimum and doubles its margin until the sweep
reaches the bottom; the certificate sweeps are the solver's, with a zero tolerance.

It is exact (the script checks, on every frame of the varied set, that the backtracked path, the
labelled optimal nodes and ``D`` on them are identical to the solver's) and far faster on the hardest
frames (noisy 960x600, 8-conn, ``h_weight=1``: 23 ms -> 5-8 ms), but the bound costs a full-frame pass
with row closures (0.3-0.45 ms at 512x480 on the shared 2-core machine), about what the whole solve of
an easy frame costs, so the median over the set did not improve (see docs/dp.md, Speed).

Run: ``.venv/bin/python scripts/dp_cost_to_go_bound.py [--per-kind N]``: per frame and
configuration the solver's and the prototype's CPU ms (least of 7 calls) and sweep counts, then medians.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
from numba import njit

sys.path.insert(0, ".")

from bench.studies.perf.frames import varied_frames  # noqa: E402
from trackers import _dp_kernels as K  # noqa: E402
from trackers.dp import _half_cost  # noqa: E402


@njit(cache=True, nogil=True)
def _crossing_bound(hc, k, conn8, hw, dg, hm, out):
    """``out[j]``: a lower bound of the cost of crossing from row k to row
    k + 1 starting at column j, less the column travel a diagonal crossing
    makes (``hm`` charges it); returns the least over j."""
    W = hc.shape[1]
    for j in range(W):
        out[j] = hc[k, j] + hc[k + 1, j]
    if conn8 and W > 1:
        for j in range(W - 1):  # down-right, then down-left
            x = dg * (hc[k, j] + hc[k + 1, j + 1]) - hm[j]
            y = out[j]
            out[j] = x if x < y else y
        for j in range(1, W):
            x = dg * (hc[k, j] + hc[k + 1, j - 1]) - hm[j - 1]
            y = out[j]
            out[j] = x if x < y else y
    m = out[0]
    for j in range(1, W):
        x = out[j]
        m = x if x < m else m
    return m


@njit(cache=True, nogil=True)
def cost_to_go_bound(hc, conn8, hw, group, Hg, grp, off):
    """A lower bound of every node's cost to the bottom row (the pruning
    bound of :func:`accumulate`).

    Why it is a lower bound: a path from row r to the bottom row crosses
    every boundary k >= r between rows k and k+1; its last crossing of each
    is downward and they come in the order of k. Any edge that moves
    between columns j and j+1 (horizontal, or diagonal with weight
    ``sqrt(1 + hw**2) > hw``) costs at least ``hw * (m_j + m_{j+1})``, with
    ``m_j`` the least half cost of column j over all rows; a crossing
    starting at column a costs at least ``cv(k, a)`` (the vertical edge, or a
    diagonal one less the column move it makes, which the metric charges).
    So the path costs at least the sum of its last crossings' ``cv`` plus the
    metric length of the column sequence they visit. Within a group of n
    boundaries, the n crossings cost at least n times the least of them,
    charged at its column (the triangle inequality covers the column moves
    dropped). Bottom-up, each closing row is that group charge plus the
    bound below, closed along the row under the metric (so it is 1-Lipschitz
    in the metric); a row inside a group adds, per boundary down to the next
    closing row, the least ``cv`` of that boundary over all columns. Rounding
    is far below the 1e-9 margin of the limits.

    Parameters
    ----------
    hc : (H, W) float64
        Half node costs.
    conn8 : bool
    hw : float
        ``h_weight`` (> 0).
    group : int
        Boundaries between rows per group (>= 1): the bound is closed along
        the row every ``group`` rows.
    Hg : (1 + ceil((H - 1) / group), W) float64
        Output: the bound on the closing rows.
    grp, off : (H,) int64 and float64
        Output: the bound at node (r, j) is ``off[r] + Hg[grp[r], j]``.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    cm = hc[0].copy()
    for r in range(1, H):
        for j in range(W):
            x = hc[r, j]
            cm[j] = x if x < cm[j] else cm[j]
    hm = np.empty(W)  # least cost of a move between columns j and j + 1
    hmr = np.empty(W)  # hmr[j] = hm[j - 1]
    for j in range(W - 1):
        hm[j] = hw * (cm[j] + cm[j + 1])
    hm[W - 1] = np.inf
    hmr[0] = np.inf
    for j in range(1, W):
        hmr[j] = hm[j - 1]
    cur = np.zeros(W)  # the bound on the closing row below
    cv = np.empty(W)
    cvm = np.empty(W)
    rmin = np.empty(H)
    L = np.empty(W)
    R = np.empty(W)
    for j in range(W):
        Hg[0, j] = 0.0
    grp[H - 1] = 0
    off[H - 1] = 0.0
    s = H - 1
    k = 0
    while s > 0:
        top = s - group if s - group > 0 else 0
        n = s - top
        for j in range(W):
            cvm[j] = np.inf
        for b in range(top, s):
            rmin[b] = _crossing_bound(hc, b, conn8, hw, dg, hm, cv)
            for j in range(W):
                x = cv[j]
                y = cvm[j]
                cvm[j] = x if x < y else y
        for j in range(W):
            cvm[j] = cur[j] + n * cvm[j]
        # close along the row: two independent chains, left and right
        xl = np.inf
        xr = np.inf
        for i in range(W):
            jr = W - 1 - i
            y = cvm[i]
            xl = y if y < xl else xl
            L[i] = xl
            xl = xl + hm[i]
            y = cvm[jr]
            xr = y if y < xr else xr
            R[jr] = xr
            xr = xr + hmr[jr]
        k += 1
        for j in range(W):
            x = L[j]
            y = R[j]
            x = x if x < y else y
            cur[j] = x
            Hg[k, j] = x
        grp[top] = k
        off[top] = 0.0
        acc = 0.0
        for r in range(s - 1, top, -1):
            acc += rmin[r]
            grp[r] = k - 1
            off[r] = acc
        s = top


@njit(cache=True, nogil=True)
def _relax_span(D, hc, r, s, conn8, hw, dg, W, a, b, Ur, hr):
    """Relax nodes a..b of row r through the edges from row s, then
    propagate along row r from the improved nodes.

    A value v at node (r, j) is *relevant* if ``v + hr[j] < Ur`` (``hr``:
    the row's bound less its offset, ``Ur``: the limit less the offset; see
    the module notes); propagation past the improved range stops at the
    first node it cannot make relevant. Returns ``(changed, lo, hi, va,
    vb)``: whether a relevant value improved; the hull lo..hi of the
    relevant columns of the visited range va..vb (lo > hi if none, or if
    nothing improved at all)."""
    first = -1
    last = -1
    changed = False
    for j in range(a, b + 1):
        v = D[s, j] + (hc[s, j] + hc[r, j])
        if conn8:
            if j > 0:
                w = D[s, j - 1] + dg * (hc[s, j - 1] + hc[r, j])
                v = w if w < v else v
            if j < W - 1:
                w = D[s, j + 1] + dg * (hc[s, j + 1] + hc[r, j])
                v = w if w < v else v
        old = D[r, j]
        if v < old:
            D[r, j] = v
            if v + hr[j] < Ur:
                if first < 0:
                    first = j
                last = j
                changed = True
    if first < 0:
        return False, W, -1, a, b
    # left-to-right chain from the first improved node, onwards while it
    # improves relevant values
    x = D[r, first]
    j = first + 1
    while j < W:
        y = x + hw * (hc[r, j - 1] + hc[r, j])
        old = D[r, j]
        if y < old:
            rel = y + hr[j] < Ur
            if j > last and not rel:
                break
            D[r, j] = y
            changed = changed or rel
            x = y
        else:
            if j > last:
                break
            x = old
        j += 1
    vb = j - 1
    # right-to-left chain from there
    x = D[r, vb]
    j = vb - 1
    while j >= 0:
        y = x + hw * (hc[r, j] + hc[r, j + 1])
        old = D[r, j]
        if y < old:
            rel = y + hr[j] < Ur
            if j < first and not rel:
                break
            D[r, j] = y
            changed = changed or rel
            x = y
        else:
            if j < first:
                break
            x = old
        j -= 1
    va = j + 1
    if va > a:
        va = a
    if vb < b:
        vb = b
    lo = W
    hi = -1
    for k in range(va, vb + 1):
        if D[r, k] + hr[k] < Ur:
            if lo == W:
                lo = k
            hi = k
    return changed, lo, hi, va, vb


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
def _forward(D, hc, conn8, hw, dg, limit, lo, hi, vlo, vhi, Hg, grp, off):
    """Monotone forward sweep restricted to relevant nodes (bound below
    ``limit``): row r is relaxed from the relevant span of row r - 1 only.
    Returns the least bottom value (+inf if no node of the bottom row was
    reached)."""
    H, W = hc.shape
    hr = Hg[grp[0]]
    Ur = limit - off[0]
    l_ = W
    h_ = -1
    for j in range(W):
        D[0, j] = 0.0
        if hr[j] < Ur:
            if l_ == W:
                l_ = j
            h_ = j
    lo[0] = l_
    hi[0] = h_
    vlo[0] = 0
    vhi[0] = W - 1
    for r in range(1, H):
        if lo[r - 1] > hi[r - 1]:
            lo[r] = W
            hi[r] = -1
            vlo[r] = W
            vhi[r] = -1
            continue
        a, b = _span(lo, hi, r - 1, W)
        ch, l_, h_, va, vb = _relax_span(D, hc, r, r - 1, conn8, hw, dg, W, a, b, limit - off[r], Hg[grp[r]])
        lo[r] = l_
        hi[r] = h_
        vlo[r] = va
        vhi[r] = vb
    best = np.inf
    for j in range(vlo[H - 1], vhi[H - 1] + 1):
        if D[H - 1, j] < best:
            best = D[H - 1, j]
    return best


#: Rows per group of the pruning bound (:func:`cost_to_go_bound`).
BOUND_GROUP = 4


@njit(cache=True, nogil=True)
def accumulate(hc, conn8, bound, D, rowmin, centre, hw=1.0):  # the solver signature of trackers._dp_kernels
    """Fill ``D`` with distances from the top row; returns the sweep count
    (forward attempts plus certificate sweeps).

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
        :func:`row_stats`); not used by this solver (the bound of
        :func:`cost_to_go_bound` replaces them), kept so that the signature
        is the reference solver's (:mod:`trackers._dp_reference`).
    hw : float, default 1.0
        ``h_weight``, the horizontal edge weight (> 0, finite); diagonal
        edges weigh ``sqrt(1 + hw**2)``.
    """
    H, W = hc.shape
    dg = np.sqrt(1.0 + hw * hw)
    lo = np.empty(H, np.int64)
    hi = np.empty(H, np.int64)
    vlo = np.empty(H, np.int64)
    vhi = np.empty(H, np.int64)
    for r in range(H):
        for j in range(W):
            D[r, j] = np.inf
    if bound:
        group = BOUND_GROUP
        Hg = np.empty((1 + (H - 1 + group - 1) // group, W))
        grp = np.empty(H, np.int64)
        off = np.empty(H)
        cost_to_go_bound(hc, conn8, hw, group, Hg, grp, off)
        low = np.inf  # the bound on the optimum
        for j in range(W):
            x = Hg[grp[0], j] + off[0]
            low = x if x < low else low
        # the first sweep needs a limit above the optimum: start just above
        # the bound, double the margin until the sweep reaches the bottom
        margin = low * 2.0 ** -7 + 1e-300
        attempts = 0
        while True:
            limit = low + margin if attempts < 40 else np.inf
            best = _forward(D, hc, conn8, hw, dg, limit, lo, hi, vlo, vhi, Hg, grp, off)
            attempts += 1
            if best < limit:
                break
            for r in range(H):
                for j in range(vlo[r], vhi[r] + 1):
                    D[r, j] = np.inf
            margin *= 2.0
        U = best * (1.0 + 1e-9) + 1e-300
        # shrink the spans to the nodes relevant under the path just found
        for r in range(H):
            hr = Hg[grp[r]]
            Ur = U - off[r]
            l_ = W
            h_ = -1
            for j in range(vlo[r], vhi[r] + 1):
                if D[r, j] + hr[j] < Ur:
                    if l_ == W:
                        l_ = j
                    h_ = j
            lo[r] = l_
            hi[r] = h_
    else:
        Hg = np.zeros((1, W))
        grp = np.zeros(H, np.int64)
        off = np.zeros(H)
        U = np.inf
        _forward(D, hc, conn8, hw, dg, U, lo, hi, vlo, vhi, Hg, grp, off)
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
            ch, l_, h_, va, vb = _relax_span(D, hc, r, r + 1, conn8, hw, dg, W, a, b, U - off[r], Hg[grp[r]])
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
            ch, l_, h_, va, vb = _relax_span(D, hc, r, r - 1, conn8, hw, dg, W, a, b, U - off[r], Hg[grp[r]])
            if ch:
                changed = True
                ver[r] += 1
                lo[r] = min(lo[r], l_)
                hi[r] = max(hi[r], h_)
        sweeps += 1
        if not changed:
            break
    return sweeps


def _cpu_ms(fn, reps=7):
    fn()
    best = np.inf
    for _ in range(reps):
        t0 = time.thread_time()
        fn()
        best = min(best, time.thread_time() - t0)
    return 1e3 * best


def _same_result(hc, conn8, hw, Da, Db):
    H, W = hc.shape
    out = []
    for D in (Da, Db):
        rows = np.empty(H * W, np.int64)
        cols = np.empty(H * W, np.int64)
        n = K.backtrack(D, hc, conn8, rows, cols, hw)
        mark = np.zeros((H, W), np.uint8)
        r2 = np.empty(H * W, np.int64)
        c2 = np.empty(H * W, np.int64)
        K.optimal_nodes(D, hc, conn8, 1e-11, mark, r2, c2, hw)
        out.append((rows[:n].copy(), cols[:n].copy(), mark))
    (ra, ca, ma), (rb, cb, mb) = out
    on = (ma & 1).astype(bool)
    return (np.array_equal(ra, rb) and np.array_equal(ca, cb) and np.array_equal(ma, mb)
            and np.array_equal(Da[on], Db[on]))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--per-kind", type=int, default=1)
    args = parser.parse_args(argv)
    times = {}
    differ = 0
    for label, img in varied_frames(args.per_kind, seed=0):
        hc, rowmin, centre, _ = _half_cost(img, 1.0)
        cells = [f"{label:20s}"]
        for conn8 in (False, True):
            for hw in (1.0, 0.25):
                Da = np.empty_like(hc)
                Db = np.empty_like(hc)
                sa = K.accumulate(hc, conn8, True, Da, rowmin, centre, hw)
                sb = accumulate(hc, conn8, True, Db, rowmin, centre, hw)
                same = _same_result(hc, conn8, hw, Da, Db)
                differ += not same
                ta = _cpu_ms(lambda: K.accumulate(hc, conn8, True, Da, rowmin, centre, hw))
                tb = _cpu_ms(lambda: accumulate(hc, conn8, True, Db, rowmin, centre, hw))
                key = f"{8 if conn8 else 4}/{hw:g}"
                times.setdefault(key, []).append((ta, tb))
                cells.append(f"{key} {ta:5.2f} -> {tb:5.2f} ms ({sa} -> {sb} sweeps){'' if same else ' DIFFERENT'}")
        print(*cells, flush=True)
    for key, v in times.items():
        v = np.array(v)
        print(f"{key}: median {np.median(v[:, 0]):.3f} -> {np.median(v[:, 1]):.3f} ms, worst {v[:, 0].max():.2f} -> "
              f"{v[:, 1].max():.2f} ms, median ratio {np.median(v[:, 0] / v[:, 1]):.2f}")
    print(f"frames x configurations with a different result: {differ}")
    return 1 if differ else 0


if __name__ == "__main__":
    raise SystemExit(main())
