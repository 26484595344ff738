"""Rendering speed of ``scenes`` at 512x480 on this machine.

Usage: ``python -m bench.perf.scenes [--object hand] [--frames 100] [--per-material 6]``

Prints, for each material at the default spp, the frames per second of
``Scene.render`` with the disk cache off (Mitsuba scene already loaded, so no
JIT compilation is counted) and the split into laser pass, ambient pass and
ground truth; then the wall time of a ``--frames`` scan of one object, cold
(empty cache, scene loading and JIT included) and cached (a new ``Scene`` reading
the same cache).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from typing import Optional, Sequence

import numpy as np

import scenes
from scenes import description
from scenes.truth import ground_truth

__all__ = ["main"]


def _per_material(obj: str, material: str, n: int):
    s = scenes.make(obj, material=material, cache=False)
    angles = s.default_angles()
    s.render(float(angles[0]))  # load + JIT
    picks = angles[np.linspace(1, len(angles) - 1, n).astype(int)]
    t0 = time.perf_counter()
    for a in picks:
        s.render(float(a))
    fps = n / (time.perf_counter() - t0)
    laser, ambient = s._load(s.params["spp"])
    split = np.zeros(3)
    for a in picks:
        pose = description.pose_updates(s.rig, float(a))
        t = [time.perf_counter()]
        laser.render(pose, s.params["spp"], 1)
        t.append(time.perf_counter())
        ambient.render(pose, s.params["ambient_spp"], 2)
        t.append(time.perf_counter())
        ground_truth(s.rig, float(a), lambda o, d: laser.cast(o, d, ("backdrop", "object")),
                     fan_deg=s.params["laser_fan_deg"])
        t.append(time.perf_counter())
        split += np.diff(t)
    return fps, split / n


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bench.perf.scenes", description=__doc__.splitlines()[0])
    ap.add_argument("--object", default="hand", choices=scenes.available())
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--per-material", type=int, default=6, help="frames timed per material")
    ap.add_argument("--materials", nargs="+", default=list(scenes.MATERIALS), choices=scenes.MATERIALS,
                    help="materials timed (default: all; the translucent ones cost ~15x matte)")
    args = ap.parse_args(argv)
    d = scenes.DEFAULTS
    print(f"512x480, laser spp {d['spp']}, ambient spp {d['ambient_spp']}, object {args.object}")
    print(f"{'material':<10} {'frames/s':>8} {'laser s':>8} {'ambient s':>9} {'truth s':>8}")
    for m in args.materials:
        fps, (tl, ta, tt) = _per_material(args.object, m, args.per_material)
        print(f"{m:<10} {fps:8.2f} {tl:8.3f} {ta:9.3f} {tt:8.3f}", flush=True)
    with tempfile.TemporaryDirectory(prefix="stripebench-perf-") as tmp:
        for label in ("cold", "cached"):
            s = scenes.make(args.object, material="matte", cache_dir=tmp)
            angles = np.linspace(*s.default_angles()[[0, -1]], args.frames)
            t0 = time.perf_counter()
            for _ in s.scan(angles, progress=False):
                pass
            print(f"{args.frames}-frame scan of {args.object}/matte, {label}: {time.perf_counter() - t0:.1f} s",
                  flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
