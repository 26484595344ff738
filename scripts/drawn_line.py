"""Look for a thin dark line drawn along a real set's stripes (a tracker's output saved with the photograph).

``python scripts/drawn_line.py [SET_DIR] [NAME ...]``

For each photograph of the real set ``SET_DIR`` (default: the shipped set) and each row with a reference column,
it looks within ``HALF_WIDTH`` px of the reference for a *narrow dip*: one pixel, or two side by side, darker in
every channel than ``DIP`` times the stripe's brightness on both sides of it (the brightest pixel within ``SIDE_PX``
px to the left, and to the right), with the pixel next to it on each side not so dark. A stripe's own profile, a speckle or a faint stripe makes such a dip in few rows;
an anti-aliased one-pixel line blended over the photograph makes it in most, with a tell-tale depth: on a clipped
(flat) stripe core, a black line drawn at opacity ``a`` leaves a one-pixel dip at ``1 - a`` of its sides where it
falls on a pixel, and two pixels at about ``1 - a / 2`` where it falls between two, the same in every channel.

It prints, per photograph: the rows with a reference; then for one-pixel and for two-pixel dips, the rows with
one, the rows whose dip is *even* (of the same depth, within ``EVEN``, in every channel, as a black line blended
over the picture leaves it; a grey frame's dips all are) and those even dips' median depth (the dip's brightness
over its sides'). It reads the frames and references with
the installed ``bench.store.realset`` and changes nothing.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

#: how far from the reference column (px) a dip is looked for
HALF_WIDTH = 6
#: how far (px) each side of a dip its sides' brightness is read
SIDE_PX = 3
#: a dip is darker than this share of its sides' brightness in every channel
DIP = 0.8
#: an *even* dip: its depth differs by at most this much between channels (a grey frame's dips all are)
EVEN = 0.05


def narrow_dips(image, ref_cols) -> list[tuple[int, int, int, np.ndarray]]:
    """The narrow dips of ``image`` next to its references.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The photograph in the trackers' orientation (DN).
    ref_cols : ndarray, shape (H,)
        Reference column per row (px); NaN where there is none.

    Returns
    -------
    list of (row, col, width, depth)
        One per row with a dip: its first column, its width (1 or 2 px) and its depth per channel (the dip's
        mean brightness over the dimmer of its sides' brightest pixels), the deepest such dip of the row.

    Examples
    --------
    A bright stripe with a one-pixel line at half opacity drawn down its middle, in rows 0-9 of 20:

    >>> img = np.full((20, 40, 3), 30.0); img[:, 16:25] = 200.0
    >>> img[:10, 20] *= 0.5
    >>> dips = narrow_dips(img, np.full(20, 20.0))
    >>> [(r, c, w) for r, c, w, _ in dips][:2], len(dips), float(dips[0][3].max())
    ([(0, 20, 1), (1, 20, 1)], 10, 0.5)
    """
    img = np.asarray(image, dtype=np.float64)
    if img.ndim == 2:
        img = img[..., None]
    H, W = img.shape[:2]
    ref = np.asarray(ref_cols, dtype=np.float64)
    if ref.shape != (H,):
        raise ValueError(f"`ref_cols` must have shape ({H},), got {ref.shape}")
    found = []
    for r in np.flatnonzero(np.isfinite(ref)):
        c = int(round(ref[r]))
        best = None
        for w in (1, 2):
            for j in range(max(SIDE_PX, c - HALF_WIDTH), min(W - SIDE_PX - w, c + HALF_WIDTH - w + 2)):
                left = img[r, j - SIDE_PX:j].max(axis=0)
                right = img[r, j + w:j + w + SIDE_PX].max(axis=0)
                sides = np.minimum(left, right)
                if np.any(sides <= 0):
                    continue
                depth = img[r, j:j + w].mean(axis=0) / sides
                edges = np.stack([img[r, j - 1], img[r, j + w]]) / sides  # the pixels either side: not dark
                if np.all(depth <= DIP) and np.all(np.any(edges > DIP, axis=1)) \
                        and (best is None or depth.max() < best[3].max()):
                    best = (int(r), j, w, depth)
        if best is not None:
            found.append(best)
    return found


#: The drawn line's opacity, as measured on ``ag_tape`` (the one photograph that has one): its one-pixel even dips on
#: the clipped core are 0.50 of their sides (median of 186), its two-pixel ones 0.76 (``1 - a / 2`` = 0.75)
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


def _run_cover(x, j: int, w: int, alpha: float, tol: float = DEPTH_TOL, even: float = EVEN):
    """The cover of each of the ``w`` pixels from column ``j`` of row ``x`` (W, C) if they are a dip a black line at
    ``alpha`` leaves (each pixel's depth within ``tol`` of ``1 - alpha * cover`` for a cover of COVERS in every
    channel and its channels' depths within ``even`` of each other, the pixels beside the run bright enough, brighter
    than it and not darkened themselves), with its summed miss; else None."""
    W = x.shape[0]
    if j < 2 or j + w > W - 2:
        return None
    side = np.maximum(x[j - 1], x[j + w])
    low = np.minimum(x[j - 1], x[j + w])
    if np.any(low < MIN_SIDE_DN) or np.any(x[j:j + w] >= low):  # a dip: darker than both its sides (not a flank)
        return None
    # the pixels beside the run are not darkened themselves (against the next ones out): the run is the whole dip
    for inner, outer in ((j - 1, j - 2), (j + w, j + w + 1)):
        if np.all(x[inner] < (1 - alpha * min(COVERS) + DEPTH_TOL) * x[outer]):
            return None
    covers, miss = [], 0.0
    for k in range(w):
        d = x[j + k] / side
        if d.max() - d.min() > even:
            return None
        best = min(COVERS, key=lambda c: float(np.abs(d - (1 - alpha * c)).max()))
        m = float(np.abs(d - (1 - alpha * best)).max())
        if m > tol:
            return None
        covers.append(best)
        miss += m
    return covers, miss


def line_pixels(image, alpha: float = ALPHA) -> list[tuple[int, int, float]]:
    """The pixels a thin black line drawn at opacity ``alpha`` over a colour photograph darkened, and how much of each
    it covers.

    The line is found by its dips of one pixel at ``1 - alpha`` (a pixel it covers whole) or two at
    ``1 - alpha / 2`` (half each): the longest chain of such rows, each within STEP_PX px (per row) of the last and
    at most GAP_ROWS rows after it, is the line (a texture's scattered dips of that depth do not line up). Along it, and GAP_ROWS rows past its ends, each row's dip of one or
    two pixels nearest the chain's column (within STEP_PX) is read, each pixel's cover from its depth (COVERS; past the
    chain's ends by the founding dips' tolerances, along it by the looser ones).

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
    f = np.asarray(image, dtype=np.float64)
    if f.ndim != 3:
        raise ValueError(f"`image` must be a colour photograph (H, W, C), got shape {f.shape}")
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"`alpha` must lie between 0 and 1, got {alpha!r}")
    H, W = f.shape[:2]
    seeds = []  # (row, col) of every dip of one pixel covered whole or two covered half each
    for r in range(H):
        for j in range(2, W - 2):
            one, two = _run_cover(f[r], j, 1, alpha), _run_cover(f[r], j, 2, alpha)
            if (one is not None and one[0] == [1.0]) or (two is not None and two[0] == [0.5, 0.5]):
                seeds.append((r, j))
    chains = []  # each a list of (row, col); a seed joins the chain it continues that has the most rows
    for r, j in seeds:
        fits = [c for c in chains if 0 < r - c[-1][0] <= GAP_ROWS + 1 and abs(j - c[-1][1]) <= STEP_PX * (r - c[-1][0])]
        if fits:
            max(fits, key=len).append((r, j))
        else:
            chains.append([(r, j)])
    if not chains:
        return []
    chain = max(chains, key=len)
    rows = np.array([r for r, _ in chain]); cols = np.array([c for _, c in chain], dtype=np.float64)
    out = []
    for r in range(max(0, rows[0] - GAP_ROWS), min(H, rows[-1] + GAP_ROWS + 1)):
        p = float(np.interp(r, rows, cols))
        tol, even = (LOOSE_TOL, LOOSE_EVEN) if rows[0] <= r <= rows[-1] else (DEPTH_TOL, EVEN)  # past its ends: strict
        runs = []
        for w in (1, 2):
            for j in range(int(round(p)) - STEP_PX, int(round(p)) + STEP_PX + 1):
                got = _run_cover(f[r], j, w, alpha, tol, even)
                if got is not None:
                    runs.append(((got[1] + 0.01 * abs(j + (w - 1) / 2 - p), w), j, got[0]))
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


def main(argv=None) -> int:
    from bench.evaluate.pixels import rotate_image
    from bench.store import realset as real

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("set_dir", nargs="?", default=str(real.SHIPPED), help="a real set (default: the shipped one)")
    p.add_argument("names", nargs="*", help="photographs to look at (default: all)")
    a = p.parse_args(argv)
    try:
        images = real.load_dataset(a.set_dir)
    except (real.ImageError, OSError, ValueError) as e:
        print(f"drawn_line.py: {e}", file=sys.stderr)
        return 2
    unknown = sorted(set(a.names) - {im.name for im in images})
    if unknown:
        print(f"drawn_line.py: no photograph {', '.join(unknown)} in {a.set_dir!r}", file=sys.stderr)
        return 2
    print(f"{'photograph':<12} {'rows':>5} {'1 px':>5} {'even':>5} {'depth':>6} {'2 px':>5} {'even':>5} {'depth':>6}")
    for im in images:
        if a.names and im.name not in a.names:
            continue
        frame, _, original, ref = im.load()
        dips = narrow_dips(rotate_image(original, im.rotate_deg), ref)
        cells = []
        for w in (1, 2):
            even = [x[3].mean() for x in dips if x[2] == w and x[3].max() - x[3].min() <= EVEN]
            depth = f"{np.median(even):.2f}" if even else "-"
            cells.append(f"{sum(x[2] == w for x in dips):>5} {len(even):>5} {depth:>6}")
        print(f"{im.name:<12} {int(np.isfinite(ref).sum()):>5} " + " ".join(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
