"""Look for a thin dark line drawn along a real set's stripes (a tracker's output saved with the photograph).

``python scripts/drawn_line.py [SET_DIR] [NAME ...]``

For each photograph of the real set ``SET_DIR`` (default: the shipped set) and each row with a reference column,
it looks within ``HALF_WIDTH`` px of the reference for a *narrow dip*: one pixel, or two side by side, darker in
every channel than ``DIP`` times the stripe's brightness on both sides of it (the brightest pixel within ``SIDE_PX``
px to the left, and to the right), with the pixel next to it on each side not so dark. A stripe's own profile, a speckle or a faint stripe makes such a dip in few rows;
an anti-aliased one-pixel line blended over the photograph makes it in most, with a tell-tale depth: on a clipped
(flat) stripe core, a black line drawn at opacity ``a`` leaves a one-pixel dip at ``1 - a`` of its sides where it
falls on a pixel, and two pixels at about ``1 - a / 2`` where it falls between two, the same in every channel.

The line itself is found and undone by :mod:`bench.evaluate.overlay` (``line_pixels``, ``undo_line``;
``make_real_set.py images`` applies them to a source with one), and ``predict`` names a photograph with one.

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

from bench.evaluate.overlay import EVEN  # an *even* dip: its depth differs by at most this much between channels

#: how far from the reference column (px) a dip is looked for
HALF_WIDTH = 6
#: how far (px) each side of a dip its sides' brightness is read
SIDE_PX = 3
#: a dip is darker than this share of its sides' brightness in every channel
DIP = 0.8


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
