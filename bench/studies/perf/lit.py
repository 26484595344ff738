"""Is :meth:`scenes.Scene.lit_pixels` a superset of the pixels with direct laser light?

Usage: ``stripebench perf lit [--sizes 128x120,256x240,512x480] [--every 2] [--spp 16]``

The laser passes of :data:`scenes.description.DIRECT_DEPTH` (the ``auto`` choices' direct light) are
rendered on :meth:`scenes.Scene.lit_pixels` only. This check renders that light on the *whole*
image (``path`` at max depth 2, ``--spp`` samples per pixel, seed 5) for every object, on the wall
alone, on the table alone and on both, for ``matte`` and ``polished``, at every ``--every``-th
default mirror angle of each ``--sizes``, and counts the pixels with light outside the mask and
their share of the frame's light. It prints one line per case and a total, and exits 1 when any
light falls outside (the mask would then drop light, a bias): run it after changing
``lit_pixels``, the objects or the laser.
"""

from __future__ import annotations

import numpy as np

import scenes
from scenes import description

__all__ = ["study", "GEOMETRIES", "MATERIALS"]

GEOMETRIES = (("wall", "none"), ("none", "table"), ("wall", "table"))
"""``(background, support)`` of the checked cases."""
MATERIALS = ("matte", "polished")


def check_frame(s, theta: float, spp: int, seed: int = 5):
    """``(pixels with direct light outside lit_pixels, their share of the frame's direct light,
    share of the image lit_pixels marks)`` of one frame of scene ``s``."""
    laser = s._load()[0]
    img = laser.render(description.pose_updates(s.rig, theta), spp, seed,
                       integrator=("path", description.DIRECT_DEPTH)).astype(np.float64)
    lit = s.lit_pixels(theta)
    outside = (img > 0) & ~lit
    total = img.sum()
    return int(outside.sum()), float(img[outside].sum() / total) if total > 0 else 0.0, float(lit.mean())


def study(*, sizes=((128, 120), (256, 240), (512, 480)), every: int = 2, spp: int = 16) -> int:
    """Count the pixels with direct laser light outside ``Scene.lit_pixels`` on every object, geometry
    and material (``stripebench perf lit``).

    Parameters
    ----------
    sizes : sequence of (int, int)
        Image sizes.
    every : int
        Every ``every``-th default mirror angle.
    spp : int
        Samples per pixel of the whole-image render.

    Returns
    -------
    int
        0, or 1 when a frame has direct light outside ``lit_pixels``.
    """
    from scenes import variant

    print(f"direct light (path, max depth {description.DIRECT_DEPTH}, {spp} spp) outside Scene.lit_pixels; "
          f"renderer {variant.renderer()}")
    print(f"{'size':>8} {'object':<7} {'background':<10} {'support':<7} {'material':<9} {'frames':>6} "
          f"{'outside px':>10} {'outside light':>13} {'lit share':>9}")
    frames = bad = 0
    for w, h in sizes:
        for obj in scenes.OBJECTS:
            for background, support in GEOMETRIES:
                for material in MATERIALS:
                    s = scenes.make(obj, material=material, background=background, support=support, width=w,
                                    height=h, cache=False)
                    rows = [check_frame(s, float(a), spp) for a in s.default_angles()[::every]]
                    out = sum(r[0] for r in rows)
                    frames += len(rows)
                    bad += sum(r[0] > 0 for r in rows)
                    print(f"{w}x{h:<4} {obj:<7} {background:<10} {support:<7} {material:<9} {len(rows):6d} "
                          f"{out:10d} {max(r[1] for r in rows):13.2e} {np.mean([r[2] for r in rows]):9.3f}",
                          flush=True)
    print(f"{frames} frames: {bad} with direct light outside lit_pixels")
    return 1 if bad else 0
