"""The shiny objects' one-bounce light by multiple importance sampling: measured against their own pass.

Usage: ``stripebench perf mis [--materials polished,glazed] [--objects cone,hand] [--counts
4+2,8+2,8+4,16+2] [--angles 2] [--ref-object-spp 1024]``

On the procedure's cases (:mod:`bench.studies.perf.sampling`: the object on the table, nothing behind,
seed and angles the paper run does not use) it renders a shiny object's pixels as
``Scene.render`` does today, ``path`` at depth 3 and 16 spp (the table's count for the hand), and as

* the direct light (``path`` at depth 2 on the object's pixels that can see the laser's frustum,
  :meth:`scenes.Scene.lit_pixels`) at the camera count, plus
* the one-bounce light by camera paths (:func:`scenes.backend.bounce_mis`, the camera count) and by light
  paths (:func:`scenes.backend.light_indirect` with ``mis``, the light count: the pass the other pixels
  already render), each weighted by the balance heuristic,

and measures both against the object pass at ``--ref-object-spp`` with the procedure's units (z stripe,
z off, centroid shift in units of the sensor's; stripe energy), the other pixels at their reference.
``--counts`` lists ``camera+light`` counts. A study: the frames' passes do not use it yet.
"""

from __future__ import annotations

import time
from typing import Optional, Sequence

import numpy as np

__all__ = ["add_arguments", "command", "main", "render_mis"]


def render_mis(case, camera_spp: int, light_spp: int, seed: int) -> np.ndarray:
    """The object's pixels of ``case`` (:class:`bench.studies.perf.sampling._Case` of a shiny material) by
    the direct light plus the MIS-weighted bounce light (:meth:`scenes.backend.LoadedScene.bounce_mis`):
    unit radiance (H, W), 0 off the object's pixels."""
    from scenes import description
    from scenes.scene import render_pass

    objpx = case.split
    direct = render_pass(case.laser_scene, case.pose, description.LaserPass("path", description.DIRECT_DEPTH, "all"),
                         objpx & case.scene.lit_pixels(case.theta), camera_spp, seed)
    return direct + case.laser_scene.bounce_mis(case.pose, objpx, camera_spp, light_spp, seed + 1)


def add_arguments(parser) -> None:
    from bench.config.options import arg_type, int_in_range, positive_int

    parser.add_argument("--materials", default="polished,glazed", metavar="LIST",
                        help="comma-separated shiny materials (default polished,glazed)")
    parser.add_argument("--objects", default="cone,hand", metavar="LIST",
                        help="comma-separated objects (default cone,hand)")
    parser.add_argument("--counts", default="4+2,8+2,8+4,16+2", metavar="LIST",
                        help="comma-separated camera+light counts (default 4+2,8+2,8+4,16+2)")
    parser.add_argument("--angles", type=arg_type(lambda n, v: int_in_range(n, v, 1, 9), "--angles"), default=2,
                        metavar="N", help="calibration angles per case (default 2)")
    parser.add_argument("--ref-object-spp", type=arg_type(lambda n, v: positive_int(n, v, 65536), "--ref-object-spp"),
                        default=1024, metavar="N", help="spp of the object pass's reference (default 1024)")


def _counts(text: str):
    from bench.errors import InputError

    out = []
    for item in (x for x in text.split(",") if x):
        parts = item.split("+")
        if len(parts) != 2 or not all(p.isdigit() and int(p) >= 1 for p in parts):
            raise InputError(f"--counts must be camera+light counts >= 1 (e.g. 8+4), got {text!r}")
        out.append((int(parts[0]), int(parts[1])))
    if not out:
        raise InputError(f"--counts must be camera+light counts >= 1 (e.g. 8+4), got {text!r}")
    return out


def command(args) -> int:
    import scenes
    from bench.errors import InputError
    from bench.studies.perf import sampling as S
    from scenes.objects import OBJECTS

    mats = [m for m in args.materials.split(",") if m]
    shiny = [m for m in S.MATERIALS if S.laser_candidates(m)[0][0] == "split"]
    if not mats or any(m not in shiny for m in mats):
        raise InputError(f"--materials must name some of {', '.join(shiny)}, got {args.materials!r}")
    objs = [o for o in args.objects.split(",") if o]
    if not objs or any(o not in OBJECTS for o in objs):
        raise InputError(f"--objects must name some of {', '.join(OBJECTS)}, got {args.objects!r}")
    counts = _counts(args.counts)
    print("| case | render | z stripe | z off | centre | energy | CPU s |\n| --- | --- | --- | --- | --- | --- | --- |",
          flush=True)
    for material in mats:
        for obj in objs:
            probe = scenes.make(obj, material=material, cache=False, seed=S.SEED, **S._TABLE)
            for theta in S.calibration_angles(probe, args.angles):
                case = S._Case(material, obj, S._TABLE, float(theta), 16, 16, args.ref_object_spp)
                rows = [("path@3 16 (today)", lambda: case.render(case.object_pass, 16, 11))]
                rows += [(f"mis {a}+{b}", lambda a=a, b=b: render_mis(case, a, b, 11)) for a, b in counts]
                for label, fn in rows:
                    fn()  # compile first
                    c0 = time.process_time()
                    img = fn()
                    cost = time.process_time() - c0
                    m = case.object_metrics(img)
                    print(f"| {case.label} | {label} | {m['stripe']:.2f} | {m['off']:.2f} | {m['centre']:.2f} | "
                          f"{m['energy']:.4f} | {cost:.2f} |", flush=True)
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m bench.studies.perf.mis``: the same options as ``stripebench perf mis``."""
    from bench.config.options import study_main

    return study_main("python -m bench.studies.perf.mis", __doc__, add_arguments, command, argv)


if __name__ == "__main__":
    raise SystemExit(main())
