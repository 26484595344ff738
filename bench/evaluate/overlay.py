"""A thin line drawn over a photograph (a tracker's output saved with the frame): found, and its darkening undone.

Some published laser-stripe photographs are not a camera's pixels alone: the program that took them drew its
detected line over the stripe, anti-aliased and half transparent. Every tracker, reference and prediction then
reads that line. A black line at opacity ``a`` leaves each pixel it covers by a share ``c`` at ``1 - a c`` of its
value, in every channel alike, so where the shares are whole or half it can be undone exactly
(docs/real.md, "A line drawn over `ag_tape`'s stripe"). Pure computation: arrays in, arrays and rows out.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ALPHA", "COVERS", "EVEN", "DRAWN_SHARE", "line_pixels", "undo_line", "line_rows", "drawn_over"]

#: An *even* dip: its depth differs by at most this much between channels (a grey frame's dips all are)
EVEN = 0.05
#: The drawn line's opacity, as measured on ``ag_tape``'s source (the one photograph found with one): its one-pixel even
#: dips on the clipped core are 0.50 of their sides (median of 186), its two-pixel ones 0.76 (``1 - a / 2`` = 0.75)
ALPHA = 0.5
#: How much of a pixel a one-pixel-wide line drawn at whole or half-pixel positions covers: all of it, or half (where
#: it falls between two pixels, or at its end)
COVERS = (1.0, 0.5)
#: A darkened pixel's depth (per channel, its brightness over the brighter pixel just outside its dip) lies within this
#: of ``1 - ALPHA * cover`` in every channel, and its channels' depths within EVEN of each other, for a dip to found the
#: line; along the line found, within LOOSE_TOL and LOOSE_EVEN (where the line crosses the stripe's unclipped flank,
#: the pixels beside it stand under what it covered, and unevenly by channel)
DEPTH_TOL = 0.06
LOOSE_TOL = 0.09
LOOSE_EVEN = 0.10
#: A dip is read only where the pixels beside it are at least this bright in every channel (DN): on a dark background
#: a ratio says nothing
MIN_SIDE_DN = 40.0
#: From one row to the next the line moves at most this many px (per row of a gap); a chain bridges gaps of at most
#: GAP_ROWS rows
STEP_PX = 4
GAP_ROWS = 3


#: A photograph is named as having a line drawn over it (:func:`drawn_over`) where the line found runs through at least
#: this share of its rows (:func:`line_rows`). On the shipped set: ``ag_tape``'s source 0.51 (235 of 465 rows), the
#: shipped ``ag_tape`` with it undone 0.01, the other 23 photographs 0.00-0.04
DRAWN_SHARE = 0.25


def _runs(f: np.ndarray, r, c, w: int, alpha: float, tol: float, even: float):
    """The dip test, the one home of what a black line at ``alpha`` leaves, for the runs of ``w`` pixels starting at
    rows ``r`` and columns ``c`` (int arrays, shape (N,)) of the photograph ``f`` (H, W, C): ``(ok, covers, miss)``,
    shapes (N,), (N, w) and (N,). A run is a dip where the pixels beside it are bright enough (MIN_SIDE_DN in every
    channel), brighter than it and not darkened themselves (against the next ones out), and each of its pixels' depths
    (over the brighter pixel beside the run) lies within ``tol`` of ``1 - alpha * cover`` for a cover of COVERS in
    every channel, its channels within ``even`` of each other; ``covers`` holds each pixel's nearest cover and ``miss``
    the run's summed misses. Runs too near the frame's edge are not dips."""
    r, c = np.asarray(r, np.int64), np.asarray(c, np.int64)
    W = f.shape[1]
    ok = (c >= 2) & (c + w <= W - 2)
    c = np.clip(c, 2, max(W - w - 2, 2))
    left, right = f[r, c - 1], f[r, np.minimum(c + w, W - 1)]
    side, low = np.maximum(left, right), np.minimum(left, right)
    ok &= np.all(low >= MIN_SIDE_DN, axis=-1)
    half = 1 - alpha * min(COVERS) + DEPTH_TOL  # a pixel under this share of the next one out is darkened itself
    outer_right = f[r, np.minimum(c + w + 1, W - 1)]
    ok &= ~np.all(left < half * f[r, c - 2], axis=-1) & ~np.all(right < half * outer_right, axis=-1)
    covers_all = np.asarray(COVERS)
    covers, miss = np.zeros((r.size, w)), np.zeros(r.size)
    for k in range(w):
        px = f[r, np.minimum(c + k, W - 1)]
        d = px / np.where(side > 0, side, np.inf)
        ok &= np.all(px < low, axis=-1) & ((d.max(axis=-1) - d.min(axis=-1)) <= even)
        off = np.abs(d[:, None, :] - (1 - alpha * covers_all)[None, :, None]).max(axis=-1)  # (N, len(COVERS))
        best = np.argmin(off, axis=1)
        m = off[np.arange(r.size), best]
        ok &= m <= tol
        covers[:, k], miss = covers_all[best], miss + m
    return ok, covers, miss


def _seeds(f: np.ndarray, alpha: float) -> np.ndarray:
    """``(row, col)`` of every dip that founds a line (shape (N, 2), in row order): one pixel covered whole, or two
    covered half each, by :func:`_runs` with the founding tolerances (DEPTH_TOL, EVEN), for every pixel (the cheap
    test first: a run darker than both its sides in every channel)."""
    H, W, _ = f.shape
    found = np.zeros((H, W), bool)
    for w, want in ((1, [1.0]), (2, [0.5, 0.5])):
        if W < w + 4:
            continue
        j = np.arange(2, W - w - 1)  # the run's first column
        low = np.minimum(f[:, j - 1], f[:, j + w])
        dark = np.ones(low.shape[:2], bool)
        for k in range(w):
            dark &= np.all(f[:, j + k] < low, axis=-1)
        r, i = np.nonzero(dark)
        ok, covers, _ = _runs(f, r, j[i], w, alpha, DEPTH_TOL, EVEN)
        ok &= np.all(covers == want, axis=1)
        found[r[ok], j[i][ok]] = True
    return np.argwhere(found)


def _chain(seeds: np.ndarray) -> list:
    """The longest chain of ``seeds`` (``(row, col)`` in row order): each within STEP_PX px per row of the chain's last
    and at most GAP_ROWS rows after it (a seed joins the longest chain it continues)."""
    best, active = [], []  # the chains a later seed may still continue: their last row within GAP_ROWS + 1
    for r, j in seeds:
        r, j = int(r), int(j)
        still = []
        for c in active:  # a chain whose last row lies too far above can grow no more
            (still if r - c[-1][0] <= GAP_ROWS + 1 else best).append(c)
        active = still
        fits = [c for c in active if 0 < r - c[-1][0] and abs(j - c[-1][1]) <= STEP_PX * (r - c[-1][0])]
        if fits:
            max(fits, key=len).append((r, j))
        else:
            active.append([(r, j)])
    return max(best + active, key=len) if best or active else []


def _checked(image, alpha: float) -> np.ndarray:
    f = np.asarray(image, dtype=np.float64)
    if f.ndim != 3:
        raise ValueError(f"`image` must be a colour photograph (H, W, C), got shape {f.shape}")
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"`alpha` must lie between 0 and 1, got {alpha!r}")
    return f


def line_rows(image, alpha: float = ALPHA) -> int:
    """How many rows the line :func:`line_pixels` would find runs through by its founding dips (its longest chain), a
    quick reading for :func:`drawn_over`.

    Examples
    --------
    >>> img = np.full((20, 40, 3), 30.0); img[:, 16:25] = [200.0, 150.0, 180.0]
    >>> img[:10, 20] *= 0.5; img[10:, 20:22] *= 0.75
    >>> line_rows(img), line_rows(np.full((20, 40, 3), 90.0))
    (20, 0)
    """
    return len({r for r, _ in _chain(_seeds(_checked(image, alpha), alpha))})


def drawn_over(image, alpha: float = ALPHA) -> int:
    """Whether a line seems drawn over the photograph: the rows it runs through (:func:`line_rows`) where they are at
    least :data:`DRAWN_SHARE` of the photograph's, else 0 (so read as a truth value, yes or no). 0 for a grey image (a
    dip there is even in its one channel whatever made it).

    Examples
    --------
    >>> img = np.full((20, 40, 3), 30.0); img[:, 16:25] = [200.0, 150.0, 180.0]
    >>> img[:10, 20] *= 0.5
    >>> drawn_over(img), drawn_over(img[:, :, 0])
    (10, 0)
    """
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] < 3:
        return 0
    n = line_rows(a, alpha)
    return n if n >= DRAWN_SHARE * a.shape[0] else 0


def line_pixels(image, alpha: float = ALPHA) -> list[tuple[int, int, float]]:
    """The pixels a thin black line drawn at opacity ``alpha`` over a colour photograph darkened, and how much of each
    it covers.

    The line is found by its dips of one pixel at ``1 - alpha`` (a pixel it covers whole) or two at
    ``1 - alpha / 2`` (half each): the longest chain of such rows, each within STEP_PX px (per row) of the last and
    at most GAP_ROWS rows after it, is the line (a texture's scattered dips of that depth do not line up). Along it,
    and GAP_ROWS rows past its ends, each row's dip of one or two pixels nearest the chain's column (within STEP_PX)
    is read by :func:`_runs`, each pixel's cover from its depth (COVERS; past the chain's ends by the founding dips'
    tolerances, along it by the looser ones).

    Parameters
    ----------
    image : ndarray, shape (H, W, C)
        The photograph (DN).
    alpha : float
        The line's opacity (0-1).

    Returns
    -------
    list of (row, col, cover)
        One per darkened pixel, in row order.

    Examples
    --------
    A bright stripe with a line drawn down its middle: on a pixel in rows 0-9, between two in rows 10-19:

    >>> img = np.full((20, 40, 3), 30.0); img[:, 16:25] = [200.0, 150.0, 180.0]
    >>> img[:10, 20] *= 0.5; img[10:, 20:22] *= 0.75
    >>> px = line_pixels(img)
    >>> px[:2], px[-2:], len(px)
    ([(0, 20, 1.0), (1, 20, 1.0)], [(19, 20, 0.5), (19, 21, 0.5)], 30)
    """
    f = _checked(image, alpha)
    H = f.shape[0]
    chain = _chain(_seeds(f, alpha))
    if not chain:
        return []
    rows = np.array([r for r, _ in chain]); cols = np.array([c for _, c in chain], dtype=np.float64)
    out = []
    for r in range(max(0, rows[0] - GAP_ROWS), min(H, rows[-1] + GAP_ROWS + 1)):
        p = float(np.interp(r, rows, cols))
        tol, even = (LOOSE_TOL, LOOSE_EVEN) if rows[0] <= r <= rows[-1] else (DEPTH_TOL, EVEN)  # past its ends: strict
        js = np.arange(int(round(p)) - STEP_PX, int(round(p)) + STEP_PX + 1)
        runs = []
        for w in (1, 2):
            ok, covers, miss = _runs(f, np.full(js.size, r), js, w, alpha, tol, even)
            runs += [((float(m) + 0.01 * abs(j + (w - 1) / 2 - p), w), int(j), cv.tolist())
                     for j, cv, m, good in zip(js, covers, miss, ok) if good]
        if not runs:
            continue
        _, j, covers = min(runs)
        out += [(r, j + k, c) for k, c in enumerate(covers)]
        if covers == [0.5]:  # a line steeper than a px per row halves two pixels apart: the other half
            apart = [x for x in runs if x[2] == [0.5] and abs(x[1] - j) == 2]
            if apart:
                out.append((r, min(apart)[1], 0.5))
    return sorted(out)


def undo_line(image, pixels, alpha: float = ALPHA) -> np.ndarray:
    """``image`` with the darkening of :func:`line_pixels`' ``pixels`` undone: each divided by ``1 - alpha * cover``,
    rounded and clipped to the type's range (a pixel the line halved on a clipped core comes back within 1 DN of the
    top).

    Parameters
    ----------
    image : ndarray, shape (H, W, C), integer
        The photograph (DN).
    pixels : sequence of (row, col, cover)
        :func:`line_pixels`' answer.
    alpha : float
        The line's opacity.

    Returns
    -------
    ndarray like ``image``

    Examples
    --------
    >>> img = np.full((2, 5, 3), 200, np.uint8); img[:, 2] = 100
    >>> undo_line(img, [(0, 2, 1.0)])[:, 2].tolist()
    [[200, 200, 200], [100, 100, 100]]
    """
    a = np.asarray(image)
    if not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"`image` must hold integer DN, got {a.dtype}")
    out = a.astype(np.float64)
    for r, c, cover in pixels:
        out[r, c] = out[r, c] / (1.0 - alpha * cover)
    top = np.iinfo(a.dtype).max
    return np.clip(np.rint(out), 0, top).astype(a.dtype)
