"""Row outcomes of trackers on the renders of a configuration's classes, with and without the laser-off frame.

Renders only: the configuration's experiments are rendered (the scenes' disk cache makes a rerun cheap) and
nothing else is read; a ``real_set`` in the configuration is ignored. Each frame is tracked as a run gives
it (``--channel auto``) or through another channel of a colour frame (``r``, ``g``, ``b``, ``gray``,
``excess``), once with its laser-off frame and once without; each experiment's ``condition`` (else its
name) is a class. Prints per class and mode F1 over rows / hit rate / false-report rate
(docs/detection.md) and the mean over classes (each class weighted equally); ``--out`` keeps the counts
(JSON) and ``--table`` reads such files back (summed) without rendering. Used for docs/learned.md:

    python scripts/learned_conditions.py --profile field --seed 0 --trackers learned,threshold,com_bg \\
        --out field-s0.json
    python scripts/learned_conditions.py --table field-s0.json field-s1.json

A tracker is a name, or ``LABEL=NAME@WEIGHTS`` for a ``learned`` weights file (``old=learned@old.npz``).

Phone-like renders (the second render family of docs/predict.md: narrow, high-contrast stripes, as a camera
app's shrunk frame shows them): ``--size 256 --downscale 4 --line-fwhm 1.2`` renders every class at
1024 x 960 with a 1.2 mrad line and shrinks each frame (and its laser-off frame and truth) by 4
(:func:`bench.evaluate.pixels.downscale`), as ``stripebench predictcheck --downscale 4 --line-fwhm 1.2`` does.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

COUNTS = ("n_hit", "n_wrong", "n_missed", "n_false", "n_quiet")


def figures(c: dict) -> tuple[float, float, float]:
    """F1 over rows, hit rate (recall), false-report rate of outcome counts (docs/detection.md)."""
    from bench.evaluate.outcomes import detection_figures

    f = detection_figures(c)
    return f["f1"], f["recall"], f["false_report_rate"]


def frames(config, seed: int, channel: str, *, size: int | None = None, downscale: int = 1,
           line_fwhm_mrad: float | None = None):
    """(class, image, laser-off frame, true columns) of every frame of ``config``'s experiments; with
    ``size`` the frames are ``size`` px wide (15/16 as high), rendered ``downscale`` times larger and
    shrunk back (:func:`bench.studies.predict_check.family_scene`, ``shrink_frame``; without ``size``, the
    profile's size), and ``line_fwhm_mrad`` replaces every experiment's line width."""
    from bench.config import with_overrides
    from bench.run.camera_view import tracker_images
    from bench.run.plan import angles_for, renderer_for
    from bench.studies.predict_check import family_scene, shrink_frame

    cfg = with_overrides(config, seed=seed, real_set="")
    renderer_for(cfg)
    width, height = (int(size), int(size) * 15 // 16) if size is not None else (cfg.render["width"],
                                                                             cfg.render["height"])
    for e in cfg.experiments:
        scene = family_scene(e, cfg, seed=cfg.seed, width=width, height=height, downscale=downscale,
                             line_fwhm_mrad=line_fwhm_mrad)
        for a in angles_for(e, scene):
            fr = shrink_frame(scene.render(float(a), spp=scene.params["spp"], seed=cfg.seed), downscale)
            img, off = tracker_images(fr, scene.params, channel)
            yield e.condition or e.key, img, off, fr.truth_columns


def make_tracker(spec: str):
    import trackers

    label, _, rest = spec.partition("=")
    if not rest:
        return label, trackers.make(label)
    name, _, weights = rest.partition("@")
    return label, trackers.make(name, weights=weights) if weights else trackers.make(name)


def evaluate(config, seed: int, channel: str, specs, **family) -> dict:
    """``{"LABEL|MODE|CLASS": counts}`` (MODE ``bg`` with the laser-off frame, ``nobg`` without)."""
    from bench.evaluate.outcomes import outcome_counts, row_outcomes

    made = [make_tracker(s) for s in specs]
    res: dict = {}
    for cls, img, off, truth in frames(config, seed, channel, **family):
        for label, tr in made:
            for mode, bg in (("bg", off), ("nobg", None)):
                c = outcome_counts(row_outcomes(tr.track(img, background=bg).columns, truth))
                acc = res.setdefault(f"{label}|{mode}|{cls}", dict.fromkeys(COUNTS, 0))
                for k in COUNTS:
                    acc[k] += int(c[k])
    return res


def table(res: dict) -> str:
    labels = list(dict.fromkeys(k.split("|")[0] for k in res))
    classes = sorted({k.split("|")[2] for k in res})
    lines = []
    for mode in ("bg", "nobg"):
        half = "with" if mode == "bg" else "without"
        lines.append(f"== {half} the laser-off frame: F1 / hit rate / false-report rate")
        lines.append("class".ljust(27) + "".join(lb[:17].rjust(18) for lb in labels))
        for c in classes:
            lines.append(c[:26].ljust(27) + "".join(("%.3f/%.3f/%.3f" % figures(res[f"{lb}|{mode}|{c}"])).rjust(18)
                                                    for lb in labels))
        lines.append("class-mean F1".ljust(27) + "".join(
            ("%.3f" % np.mean([figures(res[f"{lb}|{mode}|{c}"])[0] for c in classes])).rjust(18) for lb in labels))
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--profile", help="an embedded profile (e.g. field)")
    src.add_argument("--config", help="a configuration file (TOML)")
    src.add_argument("--table", nargs="+", metavar="JSON", help="print the table of saved counts (summed)")
    ap.add_argument("--seed", type=int, default=0, help="render seed (default 0)")
    ap.add_argument("--channel", default="auto", help="the view of a colour frame (default auto)")
    ap.add_argument("--trackers", default="learned,threshold,com_bg,steger,dp8,dp_gap",
                    help="comma-separated trackers (NAME or LABEL=NAME@WEIGHTS)")
    ap.add_argument("--size", type=int, help="frame width (px; height 15/16 of it) instead of the profile's")
    ap.add_argument("--downscale", type=int, default=1, help="render N times larger and shrink back (needs --size)")
    ap.add_argument("--line-fwhm", type=float, help="every experiment's laser line width (mrad)")
    ap.add_argument("--out", help="write the counts here (JSON)")
    args = ap.parse_args(argv)
    if args.downscale != 1 and args.size is None:
        ap.error("--downscale needs --size")
    if args.table:
        res: dict = {}
        for f in args.table:
            for k, c in json.loads(open(f).read()).items():
                acc = res.setdefault(k, dict.fromkeys(COUNTS, 0))
                for kk in COUNTS:
                    acc[kk] += c[kk]
    else:
        from bench.config import load, profile

        config = profile(args.profile) if args.profile else load(args.config)
        res = evaluate(config, args.seed, args.channel, [s for s in args.trackers.split(",") if s],
                       size=args.size, downscale=args.downscale, line_fwhm_mrad=args.line_fwhm)
        if args.out:
            with open(args.out, "w") as fh:
                json.dump(res, fh, indent=0)
    print(table(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())
