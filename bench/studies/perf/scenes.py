"""Rendering speed of ``scenes`` at 512x480 on this machine.

Usage: ``stripebench perf scenes [--object hand] [--frames 100] [--per-material 6]
[--materials matte,glossy] [--background wall|none] [--support none|table] [--spp auto|N]
[--ambient-spp auto|N] [--strict]``

Prints the renderer (:func:`scenes.variant.renderer`), then for each material at
``--spp`` / ``--ambient-spp`` (default ``auto``: the counts of :mod:`scenes.sampling`, as the
experiment profiles render) the frames per second of ``Scene.render`` with the disk cache off
(Mitsuba scene already loaded, so no JIT compilation is counted), the process
CPU time per frame (all threads; on a shared machine a steadier figure than the
wall time), the split into laser pass(es), ambient pass and ground truth, and the
**frame / bare** ratio: the process CPU time (all threads) of a whole ``Scene.render`` (both passes,
truth, sensor) over that of a *bare* render of the same frame, one ``mi.render`` of its laser scene
with the material's own integrator at the fixed :data:`scenes.sampling.FIXED_SPP` samples per pixel
(what a plain Mitsuba script spends on the frame), and the same ratio of wall times beside it (the
light-traced passes run on one thread, so their wall time is their CPU time; in a run the
render-ahead helper uses the other core meanwhile). Target (``--strict`` exits 1 when a material
misses it): the CPU ratio <= :data:`FRAME_VS_BARE` (median over the timed frames) for every opaque
and shiny material.
Then the wall time of a ``--frames`` scan of one object, cold
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
from scenes.scene import render_pass

__all__ = ["add_arguments", "command", "main"]


FRAME_VS_BARE = 1.2
"""Target: a scan frame costs at most this many bare renders of it (module docstring)."""


def _per_material(obj: str, material: str, n: int, geometry: dict, spp, ambient_spp):
    from scenes.sampling import FIXED_SPP

    s = scenes.make(obj, material=material, cache=False, spp=spp, ambient_spp=ambient_spp, **geometry)
    angles = s.default_angles()
    s.render(float(angles[0]))  # load + JIT
    laser, *ambient = s._load()
    passes, counts, amb_spp = s.sample_counts()
    picks = angles[np.linspace(1, len(angles) - 1, n).astype(int)]
    pose0 = description.pose_updates(s.rig, float(picks[0]))
    laser.render(pose0, FIXED_SPP, 3)  # compile the bare render's kernel
    t0, c0 = time.perf_counter(), time.process_time()
    frame_s, bare_s, frame_cpu, bare_cpu = [], [], [], []
    for a in picks:
        t, c = time.perf_counter(), time.process_time()
        s.render(float(a))
        frame_s.append(time.perf_counter() - t)
        frame_cpu.append(time.process_time() - c)
    fps = n / (time.perf_counter() - t0)
    cpu = (time.process_time() - c0) / n
    for a in picks:
        pose = description.pose_updates(s.rig, float(a))
        t, c = time.perf_counter(), time.process_time()
        laser.render(pose, FIXED_SPP, 3)  # one mi.render, the scene's own integrator
        bare_s.append(time.perf_counter() - t)
        bare_cpu.append(time.process_time() - c)
    split = np.zeros(3)
    for a in picks:
        pose = description.pose_updates(s.rig, float(a))
        t = [time.perf_counter()]
        for lp, k, mask in zip(passes, counts, s.pass_pixels(float(a), passes)):  # as Scene.render: each on its pixels
            render_pass(laser, pose, lp, mask, k, 1)
        t.append(time.perf_counter())
        for amb in ambient:
            amb.render(pose, amb_spp, 2)
        t.append(time.perf_counter())
        s._truth(laser, float(a))
        t.append(time.perf_counter())
        split += np.diff(t)
    ratio = (float(np.median(np.asarray(frame_cpu) / np.asarray(bare_cpu))),
             float(np.median(np.asarray(frame_s) / np.asarray(bare_s))))
    return fps, cpu, split / n, ratio, (passes, counts, amb_spp)


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
    from bench.config.options import arg_type, int_in_range, positive_int, spp_value

    parser.add_argument("--object", type=arg_type(_object, "--object"), default="hand",
                        help="the scanned object (default hand)")
    parser.add_argument("--frames", type=arg_type(lambda n, v: int_in_range(n, v, 0, 100000), "--frames"),
                        default=100, metavar="N", help="frames of the timed scan; 0 skips it (default 100)")
    parser.add_argument("--per-material", type=arg_type(lambda n, v: positive_int(n, v, 1000), "--per-material"),
                        default=6, metavar="N", help="frames timed per material (default 6)")
    parser.add_argument("--materials", type=arg_type(_materials, "--materials"), default=list(scenes.MATERIALS),
                        metavar="LIST", help="comma-separated materials (default: all; the translucent ones cost ~15x matte)")
    parser.add_argument("--spp", type=arg_type(spp_value, "--spp"), default="auto", metavar="auto|N",
                        help="laser-pass samples per pixel (default auto: scenes.sampling)")
    parser.add_argument("--ambient-spp", type=arg_type(spp_value, "--ambient-spp"), default="auto", metavar="auto|N",
                        help="ambient-pass samples per pixel (default auto)")
    parser.add_argument("--strict", action="store_true", help=f"exit 1 if frame / bare > {FRAME_VS_BARE}")
    parser.add_argument("--background", default="wall", choices=("wall", "none"))
    parser.add_argument("--support", default="none", choices=("none", "table"))


def command(args) -> int:
    """Run the benchmark with parsed options."""
    from scenes import materials as M, variant

    materials = args.materials
    geometry = {"background": args.background, "support": args.support}
    print(f"512x480, laser spp {args.spp}, ambient spp {args.ambient_spp}, object {args.object}, "
          f"background {args.background}, support {args.support}, renderer {variant.renderer()}")
    print(f"{'material':<10} {'frames/s':>8} {'CPU s/frame':>11} {'laser s':>8} {'ambient s':>9} {'truth s':>8} "
          f"{'frame/bare CPU':>14} {'wall':>5}  passes (spp)")
    missed = []
    for m in materials:
        fps, cpu, (tl, ta, tt), ratio, (passes, counts, amb) = _per_material(
            args.object, m, args.per_material, geometry, args.spp, args.ambient_spp)
        text = " + ".join(f"{p.kind}@{p.max_depth}:{n}" for p, n in zip(passes, counts)) + f"; ambient {amb}"
        print(f"{m:<10} {fps:8.2f} {cpu:11.3f} {tl:8.3f} {ta:9.3f} {tt:8.3f} {ratio[0]:14.2f} {ratio[1]:5.2f}  {text}",
              flush=True)
        if not M.is_translucent(m) and ratio[0] > FRAME_VS_BARE:
            missed.append(f"{m} {ratio[0]:.2f}")
    if missed:
        print(f"target missed: frame / bare <= {FRAME_VS_BARE} ({', '.join(missed)})")
    if args.strict and missed:
        return 1
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
