"""Rendering speed of ``scenes`` at 512x480 on this machine.

Usage: ``stripebench perf scenes [--object hand] [--frames 100] [--per-material 6]
[--materials matte,glossy] [--background wall|none] [--support none|table]``

Prints the renderer (:func:`scenes.variant.renderer`), then for each material at
the default spp the frames per second of ``Scene.render`` with the disk cache off
(Mitsuba scene already loaded, so no JIT compilation is counted), the process
CPU time per frame (all threads; on a shared machine a steadier figure than the
wall time) and the split into laser pass, ambient pass and ground truth; then the wall time of a ``--frames`` scan of one object, cold
(empty cache, scene loading and JIT included) and cached (a new ``Scene`` reading
the same cache); ``--frames 0`` skips the scan.
"""

from __future__ import annotations

import sys
import tempfile
import time
from typing import Optional, Sequence

import numpy as np

import scenes
from scenes import description
from scenes.truth import ground_truth

__all__ = ["add_arguments", "command", "main"]


def _per_material(obj: str, material: str, n: int, geometry: dict):
    s = scenes.make(obj, material=material, cache=False, **geometry)
    angles = s.default_angles()
    s.render(float(angles[0]))  # load + JIT
    picks = angles[np.linspace(1, len(angles) - 1, n).astype(int)]
    t0, c0 = time.perf_counter(), time.process_time()
    for a in picks:
        s.render(float(a))
    fps = n / (time.perf_counter() - t0)
    cpu = (time.process_time() - c0) / n
    laser, ambient = s._load(s.params["spp"])
    split = np.zeros(3)
    for a in picks:
        pose = description.pose_updates(s.rig, float(a))
        t = [time.perf_counter()]
        for lp in description.laser_passes(material):  # split materials render two passes
            laser.render(pose, s.params["spp"], 1, integrator=(lp.kind, lp.max_depth))
        t.append(time.perf_counter())
        ambient.render(pose, s.params["ambient_spp"], 2)
        t.append(time.perf_counter())
        ground_truth(s.rig, float(a), lambda o, d: laser.cast(o, d, ("backdrop", "object", "support")),
                     fan_deg=s.params["laser_fan_deg"])
        t.append(time.perf_counter())
        split += np.diff(t)
    return fps, cpu, split / n


def _object(name, text):
    from bench.config import ConfigError

    if text not in scenes.available():
        raise ConfigError(f"{name} must be one of {', '.join(scenes.available())}, got {text!r}")
    return text


def _materials(name, text):
    from bench.config import ConfigError

    materials = [m for m in str(text).split(",") if m]
    bad = [m for m in materials if m not in scenes.MATERIALS]
    if bad or not materials:
        raise ConfigError(f"{name} must name some of {', '.join(scenes.MATERIALS)}, got {text!r}")
    return materials


def add_arguments(parser) -> None:
    """The benchmark's options (``stripebench perf scenes``)."""
    from bench.config.options import arg_type, int_in_range, positive_int

    parser.add_argument("--object", type=arg_type(_object, "--object"), default="hand",
                        help="the scanned object (default hand)")
    parser.add_argument("--frames", type=arg_type(lambda n, v: int_in_range(n, v, 0, 100000), "--frames"),
                        default=100, metavar="N", help="frames of the timed scan; 0 skips it (default 100)")
    parser.add_argument("--per-material", type=arg_type(lambda n, v: positive_int(n, v, 1000), "--per-material"),
                        default=6, metavar="N", help="frames timed per material (default 6)")
    parser.add_argument("--materials", type=arg_type(_materials, "--materials"), default=list(scenes.MATERIALS),
                        metavar="LIST", help="comma-separated materials (default: all; the translucent ones cost ~15x matte)")
    parser.add_argument("--background", default="wall", choices=("wall", "none"))
    parser.add_argument("--support", default="none", choices=("none", "table"))


def command(args) -> int:
    """Run the benchmark with parsed options."""
    materials = args.materials
    geometry = {"background": args.background, "support": args.support}
    d = scenes.DEFAULTS
    from scenes import variant

    print(f"512x480, laser spp {d['spp']}, ambient spp {d['ambient_spp']}, object {args.object}, "
          f"background {args.background}, support {args.support}, renderer {variant.renderer()}")
    print(f"{'material':<10} {'frames/s':>8} {'CPU s/frame':>11} {'laser s':>8} {'ambient s':>9} {'truth s':>8}")
    for m in materials:
        fps, cpu, (tl, ta, tt) = _per_material(args.object, m, args.per_material, geometry)
        print(f"{m:<10} {fps:8.2f} {cpu:11.3f} {tl:8.3f} {ta:9.3f} {tt:8.3f}", flush=True)
    if args.frames == 0:
        return 0
    with tempfile.TemporaryDirectory(prefix="stripebench-perf-") as tmp:
        for label in ("cold", "cached"):
            s = scenes.make(args.object, material="matte", cache_dir=tmp, **geometry)
            angles = np.linspace(*s.default_angles()[[0, -1]], args.frames)
            t0 = time.perf_counter()
            for _ in s.scan(angles, progress=False):
                pass
            print(f"{args.frames}-frame scan of {args.object}/matte, {label}: {time.perf_counter() - t0:.1f} s",
                  flush=True)
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m bench.studies.perf.scenes``: the same options as ``stripebench perf scenes``."""
    from bench.config.options import study_main

    return study_main("stripebench perf scenes", __doc__, add_arguments, command, argv)


if __name__ == "__main__":
    sys.exit(main())
