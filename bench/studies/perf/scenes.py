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

import tempfile
import time

import numpy as np

import scenes
from scenes import description
from scenes import render_pass

__all__ = ["study", "FRAME_VS_BARE", "object_value", "materials_value"]


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


#: The checks of ``--object`` and ``--materials`` (``check(name, text) -> value``; :mod:`bench.cli.perf`).
object_value = _object
materials_value = _materials


def study(*, object: str = "hand", frames: int = 100, per_material: int = 6, materials=None, spp="auto",
          ambient_spp="auto", strict: bool = False, background: str = "wall", support: str = "none") -> int:
    """Time every material's frames against the bare render, then a scan cold and cached
    (``stripebench perf scenes``).

    Parameters
    ----------
    object : str
        The scanned object.
    frames : int
        Frames of the timed scan; 0 skips it.
    per_material : int
        Frames timed per material.
    materials : list of str, optional
        The materials (default: every one of ``scenes.MATERIALS``).
    spp, ambient_spp : "auto" or int
        Laser-pass and ambient-pass samples per pixel.
    strict : bool
        Return 1 if frame / bare exceeds :data:`FRAME_VS_BARE`.
    background, support : str
        The scene's geometry.

    Returns
    -------
    int
        0, or 1 with ``strict`` when the target is missed.
    """
    from scenes import materials as M, variant

    materials = list(scenes.MATERIALS) if materials is None else materials
    geometry = {"background": background, "support": support}
    print(f"512x480, laser spp {spp}, ambient spp {ambient_spp}, object {object}, "
          f"background {background}, support {support}, renderer {variant.renderer()}")
    print(f"{'material':<10} {'frames/s':>8} {'CPU s/frame':>11} {'laser s':>8} {'ambient s':>9} {'truth s':>8} "
          f"{'frame/bare CPU':>14} {'wall':>5}  passes (spp)")
    missed = []
    for m in materials:
        fps, cpu, (tl, ta, tt), ratio, (passes, counts, amb) = _per_material(
            object, m, per_material, geometry, spp, ambient_spp)
        text = " + ".join(f"{p.kind}@{p.max_depth}:{n}" for p, n in zip(passes, counts)) + f"; ambient {amb}"
        print(f"{m:<10} {fps:8.2f} {cpu:11.3f} {tl:8.3f} {ta:9.3f} {tt:8.3f} {ratio[0]:14.2f} {ratio[1]:5.2f}  {text}",
              flush=True)
        if not M.is_translucent(m) and ratio[0] > FRAME_VS_BARE:
            missed.append(f"{m} {ratio[0]:.2f}")
    if missed:
        print(f"target missed: frame / bare <= {FRAME_VS_BARE} ({', '.join(missed)})")
    if strict and missed:
        return 1
    if frames == 0:
        return 0
    with tempfile.TemporaryDirectory(prefix="stripebench-perf-") as tmp:
        for label in ("cold", "cached"):
            s = scenes.make(object, material="matte", cache_dir=tmp, **geometry)
            angles = np.linspace(*s.default_angles()[[0, -1]], frames)
            t0 = time.perf_counter()
            for _ in s.scan(angles, progress=False):
                pass
            print(f"{frames}-frame scan of {object}/matte, {label}: {time.perf_counter() - t0:.1f} s",
                  flush=True)
    return 0
