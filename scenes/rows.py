"""Which image rows the object, the background and the support fill, read from the ground truth.

Usage::

    python -m scenes.rows [--objects cone hand] [--background wall|none] [--support none|table]
                          [--background-distance-cm 55] [--width 512 --height 480] [--n-angles 48]

For each object, over its default scan (``--n-angles`` mirror angles) and at the
angle nearest 0 (mid-scan), prints the first and last row and the number of rows
whose truth lies on each part (:data:`scenes.frame.PARTS`) and the rows with no
truth.  Only rays are cast (:meth:`scenes.Scene.truth`); nothing is rendered
(about 3 s per object at 512x480 here, on an idle machine).
"""

from __future__ import annotations

import argparse
import sys
from typing import Dict, Optional, Sequence

import numpy as np

from .frame import PARTS
from .registry import available, make

__all__ = ["part_rows", "main"]


def part_rows(scene, angles) -> Dict[str, np.ndarray]:
    """Rows with truth on each part over ``angles``.

    Parameters
    ----------
    scene : Scene
    angles : array_like
        Mirror angles (deg).

    Returns
    -------
    dict
        ``{part name: sorted unique row indices (int64)}`` for every name in
        :data:`scenes.frame.PARTS`, plus ``"none"``: rows without truth in at least one frame.
    """
    found = {name: set() for name in (*PARTS, "none")}
    for theta in np.atleast_1d(np.asarray(angles, float)):
        part = scene.truth(float(theta)).part
        for k, name in enumerate(PARTS):
            found[name].update(np.nonzero(part == k)[0].tolist())
        found["none"].update(np.nonzero(part < 0)[0].tolist())
    return {name: np.array(sorted(rows), dtype=np.int64) for name, rows in found.items()}


def _span(rows: np.ndarray) -> str:
    return f"{rows[0]}-{rows[-1]} ({len(rows)})" if len(rows) else "- (0)"


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command line; returns the exit status."""
    ap = argparse.ArgumentParser(prog="python -m scenes.rows", description=__doc__.splitlines()[0])
    ap.add_argument("--objects", nargs="+", default=available(), choices=available())
    ap.add_argument("--background", default="wall", choices=("wall", "none"))
    ap.add_argument("--background-distance-cm", type=float, default=None)
    ap.add_argument("--support", default="none", choices=("none", "table"))
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--n-angles", type=int, default=48)
    args = ap.parse_args(argv)
    extra = {} if args.background_distance_cm is None else {"background_distance_cm": args.background_distance_cm}
    try:
        made = [make(name, width=args.width, height=args.height, n_angles=args.n_angles, background=args.background,
                     support=args.support, cache=False, **extra) for name in args.objects]
    except ValueError as exc:
        ap.error(str(exc))
    print(f"{args.width}x{args.height}, background {args.background}, support {args.support}, "
          f"{args.n_angles} angles; rows: first-last (count)")
    for s in made:
        angles = s.default_angles()
        mid = float(angles[np.argmin(np.abs(angles))])
        scan, one = part_rows(s, angles), part_rows(s, [mid])
        print(f"{s.name:<7} scan: " + ", ".join(f"{k} {_span(v)}" for k, v in scan.items()))
        print(f"{'':<7} θ = {mid:+.3f}°: " + ", ".join(f"{k} {_span(v)}" for k, v in one.items()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
