"""Contact sheet: every object x material at 400 lux, one frame each, ground truth overlaid.

Usage::

    python -m scenes.contact_sheet OUT.png [--width 512 --height 480] [--objects cone hand]
                                           [--materials matte specular] [--dpi 60]

Each panel shows the 8-bit laser-on frame with a square-root display stretch (so
the few-DN ambient and the dark patches are visible) and the per-row truth:
red on the object, cyan on the backdrop.  Angles are chosen per object to show
something typical: the cone and sphere near their edge (where a mirror throws the
sheet forward onto the wall), the hand across its fingers, the plane in its middle.
"""

from __future__ import annotations

import argparse
import sys
from typing import Optional, Sequence

import numpy as np

from .materials import MATERIALS
from .registry import available, make

__all__ = ["SHOWCASE_ANGLE_DEG", "render_sheet", "main"]

SHOWCASE_ANGLE_DEG = {"cone": 2.3, "hand": 2.5, "plane": 0.0, "sphere": 2.7}


def render_sheet(out_png: str, *, objects: Sequence[str], materials: Sequence[str], width: int = 512,
                 height: int = 480, dpi: int = 60, progress: bool = True) -> None:
    """Render the grid (rows: objects, columns: materials) and save it as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from tqdm import tqdm

    fig, axes = plt.subplots(len(objects), len(materials), squeeze=False,
                             figsize=(3.2 * len(materials), 3.2 * height / width * len(objects) + 0.6))
    jobs = [(o, m) for o in objects for m in materials]
    for obj, mat in tqdm(jobs, desc="contact sheet", file=sys.stderr, disable=not progress):
        ax = axes[objects.index(obj), materials.index(mat)]
        theta = SHOWCASE_ANGLE_DEG.get(obj, 0.0)
        frame = make(obj, material=mat, ambient_lux=400.0, width=width, height=height).render(theta)
        ax.imshow(np.sqrt(frame.image / 255.0), cmap="gray", vmin=0, vmax=1, interpolation="nearest")
        rows = np.arange(height)
        cols = frame.truth.columns
        ax.plot(np.where(frame.truth.on_object, cols, np.nan), rows, "-", color="red", lw=0.6)
        ax.plot(np.where(frame.truth.valid & ~frame.truth.on_object, cols, np.nan), rows, "-", color="cyan",
                lw=0.6)
        ax.set_title(f"{obj} / {mat}, θ={theta:g}°, max {frame.image.max()} DN", fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("stripebench scenes at 400 lux (sqrt display stretch); truth: red object, cyan backdrop",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point."""
    ap = argparse.ArgumentParser(prog="python -m scenes.contact_sheet", description=__doc__.splitlines()[0])
    ap.add_argument("out", help="output PNG path")
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--objects", nargs="+", default=available(), choices=available())
    ap.add_argument("--materials", nargs="+", default=list(MATERIALS), choices=MATERIALS)
    ap.add_argument("--dpi", type=int, default=60)
    args = ap.parse_args(argv)
    render_sheet(args.out, objects=args.objects, materials=args.materials, width=args.width, height=args.height,
                 dpi=args.dpi)
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
