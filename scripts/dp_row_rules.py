"""Measure the DP trackers' row rules (which column a row reports).

Rules: ``mean`` (the mean column of the row's optimal-path nodes: the old
rule), ``crossing`` (the brightest node where an optimal path enters or
leaves the row vertically or diagonally), ``brightest`` (the brightest
optimal-path node of the row), ``crossing+walk5`` (``crossing``, and rows
whose optimal nodes span more than 5 columns are not reported).

Frames: synthetic stripes with a jump (a depth discontinuity: the stripe
moves 40 columns between two rows; in half of the frames the 3 rows
before it are dark) and with a cut,
seeded; and rendered frames of the sphere and the plane (seed 1, 512x480,
12 angles, the tuning set's renders, cached). For each rule and tracker:
at h_weight 1 and 0.1: reported rows, rows off by more than 3 px (of the reported), median and
worst error in px.

The rules are the DP trackers' documented parameters ``row_rule`` and
``max_walk`` (:class:`trackers.dp.DPTracker`); the default is ``crossing``.

Run with the project's Python: ``python scripts/dp_row_rules.py [--no-render]``.
"""

from __future__ import annotations

import argparse

import numpy as np

import trackers
from trackers.testing import make_stripe_image

#: label -> (row_rule, max_walk) of the DP trackers
RULES = {"mean": ("mean", None), "crossing": ("crossing", None), "brightest": ("brightest", None),
         "crossing+walk5": ("crossing", 5)}


def synthetic(n=6):
    out = []
    for seed in range(n):
        rng = np.random.default_rng(seed)
        img, truth = make_stripe_image(120, 160, seed=seed, noise=1.5, background=8.0)
        img = img.astype(float)
        k = int(rng.integers(40, 80))
        shift = int(rng.choice([-40, 40]))
        right = np.roll(img, shift, axis=1)
        img[k:] = right[k:]
        truth = truth.copy()
        truth[k:] += shift
        if seed % 2:  # odd seeds: the rows at the discontinuity are dark
            img[k - 2 : k + 1] = 8.0
            truth[k - 2 : k + 1] = np.nan
        c = int(rng.integers(10, 30))
        img[c : c + 4] = 8.0  # and a cut
        truth[c : c + 4] = np.nan
        out.append((np.clip(np.rint(img), 0, 255).astype(np.uint8), truth))
    return out


def rendered():
    import scenes

    out = []
    for scene, material in (("sphere", "patchy"), ("sphere", "glossy"), ("plane", "patchy"), ("plane", "absorbing")):
        s = scenes.make(scene, material=material, seed=1, width=512, height=480, spp=16)
        for a in s.object.default_angles(s.rig.zeta_deg, 12):
            f = s.render(float(a), spp=16, seed=1)
            out.append((f.image, np.where(f.truth.on_object, f.truth.columns, np.nan)))
    return out


def measure(frames, name, h_weight):
    for rule, (row_rule, walk) in RULES.items():
        t = trackers.make(name, h_weight=h_weight, row_rule=row_rule, max_walk=walk)
        errs, reported, lit = [], 0, 0
        for img, truth in frames:
            cols = t.track(img).columns
            ok = np.isfinite(truth)
            lit += int(ok.sum())
            m = ok & np.isfinite(cols)
            reported += int(m.sum())
            errs.append(np.abs(cols[m] - truth[m]))
        e = np.concatenate(errs)
        print(f"  {name:<13}{h_weight:<6g}{rule:<16}{reported:>6} / {lit:<6}{np.mean(e > 3) * 100:>8.2f} %{np.median(e):>9.2f}"
              f"{e.max():>9.1f}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--no-render", action="store_true", help="only the synthetic frames (no Mitsuba renders)")
    args = p.parse_args()
    sets = [("synthetic: jump + cut (6 frames, 160x120)", synthetic())]
    if not args.no_render:
        sets.append(("rendered: sphere/plane x patchy/glossy/absorbing, seed 1, 48 frames, object rows", rendered()))
    for title, frames in sets:
        print(title)
        print(f"  {'tracker':<13}{'h_w':<6}{'rule':<16}{'reported / truth':<18}{'> 3 px':>8}{'median':>9}{'worst':>9}")
        for name in ("dp4", "dp8", "dp8_subpixel"):
            for hw in (1.0, 0.1):
                measure(frames, name, hw)


if __name__ == "__main__":
    main()
