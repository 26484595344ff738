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

import numpy as np

__all__ = ["study", "render_mis"]


def render_mis(case, camera_spp: int, light_spp: int, seed: int) -> np.ndarray:
    """The object's pixels of ``case`` (:class:`bench.studies.perf.sampling._Case` of a shiny material) by
    the direct light plus the MIS-weighted bounce light (:meth:`scenes.backend.LoadedScene.bounce_mis`):
    unit radiance (H, W), 0 off the object's pixels."""
    from scenes import description
    from scenes import render_pass

    objpx = case.split
    direct = render_pass(case.laser_scene, case.pose, description.LaserPass("path", description.DIRECT_DEPTH, "all"),
                         objpx & case.scene.lit_pixels(case.theta), camera_spp, seed)
    return direct + case.laser_scene.bounce_mis(case.pose, objpx, camera_spp, light_spp, seed + 1)


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


def study(*, materials: str = "polished,glazed", objects: str = "cone,hand", counts: str = "4+2,8+2,8+4,16+2",
          angles: int = 2, ref_object_spp: int = 1024) -> int:
    """Render the shiny objects' pass by MIS at several camera + light counts against their own
    reference and print the table (``stripebench perf mis``).

    Parameters
    ----------
    materials : str
        Comma-separated shiny materials.
    objects : str
        Comma-separated objects.
    counts : str
        Comma-separated camera+light counts (e.g. ``8+4``).
    angles : int
        Calibration angles per case.
    ref_object_spp : int
        Sample count of the object pass's reference.

    Returns
    -------
    int
        0; bad values raise :class:`bench.errors.InputError`.
    """
    import scenes
    from bench.errors import InputError
    from bench.studies.perf import sampling as S
    from scenes import OBJECTS

    mats = [m for m in materials.split(",") if m]
    shiny = [m for m in S.MATERIALS if S.laser_candidates(m)[0][0] == "split"]
    if not mats or any(m not in shiny for m in mats):
        raise InputError(f"--materials must name some of {', '.join(shiny)}, got {materials!r}")
    objs = [o for o in objects.split(",") if o]
    if not objs or any(o not in OBJECTS for o in objs):
        raise InputError(f"--objects must name some of {', '.join(OBJECTS)}, got {objects!r}")
    counts = _counts(counts)
    print("| case | render | z stripe | z off | centre | energy | CPU s |\n| --- | --- | --- | --- | --- | --- | --- |",
          flush=True)
    for material in mats:
        for obj in objs:
            probe = scenes.make(obj, material=material, cache=False, seed=S.SEED, **S._TABLE)
            for theta in S.calibration_angles(probe, angles):
                case = S._Case(material, obj, S._TABLE, float(theta), 16, 16, ref_object_spp)
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
