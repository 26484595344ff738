"""Where a transplant's truth is not the stripe: its *phantom* rows, measured on renders.

``stripebench predict`` moves a photograph's own stripe (:mod:`bench.evaluate.transplant`) and scores the
trackers on the moved stripe. Its stripe estimate cannot tell the stripe from a bright line in line with
it (a floor's mirror image of the stripe, a rival), so some moved rows carry something that is not the
stripe. On renders the truth is known: this script makes the transplants of ``stripebench predictcheck``'s
cases and counts the moved rows scored as stripe rows where the render has no stripe (phantom rows),
with each tracker's hit rate on them and on the other (real) stripe rows. A tracker that rightly stays quiet
on a reflection is scored as missing it there, one that reports the reflection as hitting it. It also
prints how high the estimate's visible rows stand against the frame's median visible row (``Extents.height``,
the peak over the reference window's median), for real and phantom rows: the data a height rule would be chosen on.
Used for docs/predict.md:

    python scripts/transplant_phantoms.py --seed 1
    python scripts/transplant_phantoms.py --seed 1 --downscale 4 --line-fwhm 1.2
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--profile", default="field", help="the profile whose experiments are the cases (default field)")
    ap.add_argument("--seed", type=int, default=1, help="the cases' render seed (default 1)")
    ap.add_argument("--size", type=int, default=256, help="render width, px (default 256)")
    ap.add_argument("--downscale", type=int, default=1, help="render N times larger and shrink back (default 1)")
    ap.add_argument("--line-fwhm", type=float, default=None, help="every case's laser line width (mrad)")
    ap.add_argument("--estimate", default="auto", help="the transplant's stripe estimate (default auto)")
    ap.add_argument("--trackers", default="dp4,dp8,threshold,com_bg,steger", help="comma-separated trackers")
    args = ap.parse_args(argv)

    from bench.config import parse_trackers, profile
    from bench.evaluate.outcomes import HIT, STRIPE
    from bench.evaluate.transplant import stripe_extents
    from bench.run import predict as pr
    from bench.run.camera_view import laser_colour
    from bench.run.track import build_trackers
    from bench.studies.predict_check import case_frames

    cfg = profile(args.profile)
    labs = [t for t in args.trackers.split(",") if t]
    tr = build_trackers(parse_trackers(labs))
    hits = {lab: {"real": [0, 0], "phantom": [0, 0]} for lab in labs}
    ratios = {"real": [], "phantom": []}
    for exp in cfg.experiments:
        for name, case, params in case_frames(exp, cfg, seed=args.seed, width=args.size,
                                              height=args.size * 15 // 16, n_angles=pr.N_ANGLES,
                                              downscale=args.downscale, line_fwhm_mrad=args.line_fwhm):
            laser = laser_colour(params.get("laser_wavelength_nm", pr.LASER_NM["red"]))
            photo = pr.Photo(name, Path(name), case.image, None, case.original, laser)
            if args.estimate == "auto" and photo.colour:  # as transplant_frames finds it
                ext = stripe_extents(case.image, guide=pr.colour_guide(photo, case.original))
            else:
                ext = stripe_extents(case.image, estimate=args.estimate)
            vis = np.flatnonzero(ext.visible)
            if vis.size:
                ratio = ext.height[vis] / np.median(ext.height[vis])
                ph = ~np.isfinite(case.truth_columns[vis])
                ratios["real"].append(ratio[~ph])
                ratios["phantom"].append(ratio[ph])
            made = pr.transplant_frames(photo, seed=args.seed, estimate=args.estimate)
            if not made:
                continue
            per = pr.transplant_outcomes(tr, made)
            none = ~np.isfinite(case.truth_columns)
            for k, (_, _, states, _, _) in enumerate(made):
                stripe = states == STRIPE
                for kind, mask in (("real", stripe & ~none), ("phantom", stripe & none)):
                    for lab in labs:
                        hits[lab][kind][0] += int(np.sum(per[lab][k][mask] == HIT))
                        hits[lab][kind][1] += int(mask.sum())
    n_real, n_phantom = hits[labs[0]]["real"][1], hits[labs[0]]["phantom"][1]
    print(f"stripe rows of the transplants: {n_real} real, {n_phantom} phantom "
          f"({n_phantom / max(n_real + n_phantom, 1):.1%}: no stripe in the render there)")
    print(f"{'tracker':<12}{'hit rate, real rows':>22}{'hit rate, phantom rows':>25}")
    for lab in labs:
        r, p = hits[lab]["real"], hits[lab]["phantom"]
        print(f"{lab:<12}{r[0] / max(r[1], 1):>22.3f}{p[0] / max(p[1], 1):>25.3f}")
    print("the estimate's visible rows in the cases, height / the frame's median visible height:")
    for kind in ("real", "phantom"):
        x = np.concatenate(ratios[kind]) if ratios[kind] else np.zeros(0)
        if x.size:
            q = ", ".join(f"{v:.2f}" for v in np.quantile(x, (0.1, 0.25, 0.5, 0.75)))
            below = ", ".join(f"{np.mean(x < f):.3f}" for f in (0.2, 0.3, 0.5))
            print(f"  {kind:<8} {x.size:>5} rows; quartiles (10/25/50/75 %) {q}; share under 0.2 / 0.3 / 0.5: {below}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
