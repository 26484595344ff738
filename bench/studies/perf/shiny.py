"""Which laser-pass integrator renders shiny materials within the sensor noise, and at what cost.

Usage: ``stripebench perf shiny [--size 128x120] [--spp 4 16] [--ref-spp 4096] [--cost]``

For each case (object, material, mirror angle) it renders the laser pass (unit power, scaled to the
default 3 mW and converted to DN by the default sensor, noise-free) with

* ``path``: path tracing, max depth 3, every pixel;
* ``ptracer``: light tracing, max depth 3, every pixel;
* ``split``: the shipped choice for ``polished``/``glazed`` (:func:`scenes.description.laser_passes`):
  ``path`` on the pixels that see the object (:meth:`scenes.Scene.split_pixels`), ``ptracer`` on the
  others,

and compares them with a reference: ``split`` at ``--ref-spp`` (``path`` converges slowly on the
sheet reflected onto the wall, ``ptracer`` on the highlight and on the wall seen in the object, so
each reference pixel comes from the integrator that converges there; the script also prints how
far the two high-spp integrators differ per region).  Regions: ``object`` (pixels that see the
object), ``wall`` (the others that see a surface), ``wall-off`` (wall pixels more than 5 mm from
the laser plane: where only reflected light lands).  Per region it prints the laser energy
relative to the reference and ``z``, the rms over the region's pixels of (render - reference) /
sensor noise, the sensor noise being the shot + read noise at the reference level plus the
ADC's quantisation (1/sqrt(12) DN).  ``z < 1`` means the Monte Carlo noise is below the sensor's.

``--mask`` prints, for the cone at 2.3 deg (the sheet grazes its side and is mirrored onto the wall)
per shiny material, how much of the laser energy on the wall away from the laser plane falls within
2 px of :attr:`scenes.Truth.false_mask`, on what share of that wall, and how bright it is there.

``--support table`` puts the table under the object for ``--mask`` and ``--sweep`` (the false
stripe's "wall" region is then every surface but the object). ``--sweep N`` scans N default angles of the cone, hand and sphere per shiny material at ``--size``
and prints the frames with a false stripe in view and its brightest one (peak laser DN within
2 px of the mask on the wall off the laser plane).

``--cost`` also times ``Scene.render`` per frame at 512x480 (default spp, cache off, after a first
frame that loads the scene and compiles the kernels) for ``matte``, ``specular``, ``polished`` and
``glazed`` on the cone.
"""

from __future__ import annotations

import time
from typing import Optional

import numpy as np
from scipy import ndimage

import scenes
from scenes import description

__all__ = ["study", "CASES"]

CASES = (("cone", "polished", 2.3), ("cone", "glazed", 2.3), ("sphere", "polished", 0.0),
         ("sphere", "glazed", 0.0), ("hand", "polished", 0.0))


def _renders(name, material, theta, width, height, spps, ref_spp):
    s = scenes.make(name, material=material, width=width, height=height, cache=False)
    laser_scene, _ = s._load(s.params["spp"])
    pose = description.pose_updates(s.rig, theta)
    pts, on_obj = s.visible_points(theta)
    split = s.split_pixels(theta)
    scale = s.laser_power_inband_w() * s.sensor.electrons_per_radiance / s.sensor.gain_e_per_dn  # DN per unit

    def run(kind, spp, seed):
        return laser_scene.render(pose, spp, seed, integrator=(kind, description.MAX_DEPTH)) * scale

    ref_path, ref_pt = run("path", ref_spp, 1001), run("ptracer", ref_spp, 1002)
    out = {"ref": np.where(split, ref_path, ref_pt), "ref_path": ref_path, "ref_pt": ref_pt}
    for spp in spps:
        p, t = run("path", spp, 7), run("ptracer", spp, 7)
        out[f"path@{spp}"], out[f"ptracer@{spp}"], out[f"split@{spp}"] = p, t, np.where(split, p, t)
    _, n = s.rig.laser_plane(theta)
    wall = ~on_obj & np.isfinite(pts[..., 0])
    with np.errstate(invalid="ignore"):
        off = wall & (np.abs(pts @ n) > 0.5)
    return s, out, {"object": on_obj, "wall": wall, "wall-off": off}


def _dilate(mask: np.ndarray, k: int) -> np.ndarray:
    """``mask`` grown by up to ``k`` px along rows and columns (a plus-shaped structuring element)."""
    plus = np.zeros((2 * k + 1, 2 * k + 1), bool)
    plus[k, :] = plus[:, k] = True
    return ndimage.binary_dilation(mask, structure=plus)


def _mask(width: int, height: int, support: str = "none"):
    theta = 2.3
    print(f"\nfalse-stripe mask vs rendered reflection, cone at {theta} deg, {width}x{height}, default spp:")
    for material in ("specular", "polished", "glazed"):
        s = scenes.make("cone", material=material, width=width, height=height, cache=False, support=support)
        f = s.render(theta)
        pts, on_obj = s.visible_points(theta)
        _, n = s.rig.laser_plane(theta)
        with np.errstate(invalid="ignore"):
            off = ~_dilate(on_obj, 1) & np.isfinite(pts[..., 0]) & (np.abs(pts @ n) > 0.5)
        near = _dilate(f.truth.false_mask, 2) & off
        rad = f.laser_radiance.astype(float)
        dn = s.sensor.expected_dn(rad) - s.sensor.black_level_dn
        print(f"  {material:<9} mask {int(f.truth.false_mask.sum())} px in {int(f.truth.false_mask.any(1).sum())} rows;"
              f" within 2 px of it: {rad[near].sum() / rad[off].sum():.0%} of the off-plane wall's laser energy"
              f" on {near.sum() / off.sum():.1%} of its area; its peak {dn[near].max(initial=0):.1f} DN,"
              f" 99th percentile {np.percentile(dn[near], 99) if near.any() else 0:.1f} DN (laser only, noise-free)",
              flush=True)


def _sweep(n: int, width: int, height: int, support: str = "none"):
    print(f"\nfalse stripes over {n} default angles per object, {width}x{height}, default spp, support {support}:")
    for material in ("specular", "polished", "glazed"):
        for name in ("cone", "hand", "sphere"):
            s = scenes.make(name, material=material, width=width, height=height, cache=False, n_angles=n,
                            support=support)
            peaks, in_view = [], 0
            for theta in s.default_angles():
                f = s.render(float(theta))
                pts, on_obj = s.visible_points(float(theta))
                _, nrm = s.rig.laser_plane(float(theta))
                with np.errstate(invalid="ignore"):
                    off = ~_dilate(on_obj, 1) & np.isfinite(pts[..., 0]) & (np.abs(pts @ nrm) > 0.5)
                near = _dilate(f.truth.false_mask, 2) & off
                in_view += bool(f.truth.false_mask.any())
                dn = s.sensor.expected_dn(f.laser_radiance) - s.sensor.black_level_dn
                peaks.append((float(dn[near].max(initial=0.0)), float(theta)))
            best = max(peaks)
            print(f"  {material:<9} {name:<7} mask in view in {in_view}/{n} frames; brightest false stripe "
                  f"{best[0]:.1f} DN (at {best[1]:.2f} deg)", flush=True)


def _cost(spp: Optional[int]):
    print(f"\nper-frame cost at 512x480 (cone, laser spp {spp or scenes.DEFAULTS['spp']}, "
          f"ambient spp {scenes.DEFAULTS['ambient_spp']}, cache off, 3 frames after a warm-up):")
    for material in ("matte", "specular", "polished", "glazed"):
        s = scenes.make("cone", material=material, cache=False)
        angles = s.default_angles()
        s.render(float(angles[0]), spp=spp)
        t0 = time.perf_counter()
        for a in angles[[10, 20, 30]]:
            s.render(float(a), spp=spp)
        print(f"  {material:<9} {(time.perf_counter() - t0) / 3:6.2f} s/frame", flush=True)


def study(*, size=(128, 120), spp=(4, 16), ref_spp: int = 4096, cases: int = len(CASES), mask: bool = False,
          sweep: int = 0, support: str = "none", cost: bool = False, cost_spp=None) -> int:
    """Compare the laser-pass integrators on the shiny :data:`CASES` against a reference, and print
    the table (``stripebench perf shiny``).

    Parameters
    ----------
    size : (int, int)
        Width and height.
    spp : sequence of int
        Sample counts of the compared renders.
    ref_spp : int
        Sample count of the reference.
    cases : int
        The first ``cases`` of :data:`CASES`.
    mask : bool
        Also measure the false stripe's energy near the truth's mask.
    sweep : int
        Scan this many default angles per shiny material (0: none).
    support : str
        ``"none"`` or ``"table"``, for ``mask`` and ``sweep``.
    cost : bool
        Also time ``Scene.render`` per frame at 512x480.
    cost_spp : int, optional
        Sample count of ``cost`` (default: the scene's).

    Returns
    -------
    int
        0.
    """
    width, height = size
    for name, material, theta in CASES[:cases]:
        s, out, regions = _renders(name, material, theta, width, height, spp, ref_spp)
        ref = out["ref"]
        sigma = s.sensor.noise_dn(ref)
        print(f"\n{name}/{material} at {theta} deg, {width}x{height}, reference split@{ref_spp} "
              f"(peak {ref[regions['object']].max(initial=0):.0f} DN on the object, "
              f"{ref[regions['wall-off']].max(initial=0):.1f} DN on the wall off the plane)")
        print(f"  {'render':<14}" + "".join(f"{r + ' E/Eref':>17}{'z':>7}" for r in regions))
        for label in ["ref_path", "ref_pt"] + [f"{k}@{spp}" for spp in spp for k in ("path", "ptracer", "split")]:
            row = f"  {label:<14}"
            for m in regions.values():
                e_ref = ref[m].sum()
                ratio = out[label][m].sum() / e_ref if e_ref > 0 else np.nan
                z = np.sqrt(np.mean(((out[label][m] - ref[m]) / sigma[m]) ** 2)) if m.any() else np.nan
                row += f"{ratio:17.3f}{z:7.3f}"
            print(row, flush=True)
    if mask:
        _mask(width, height, support)
    if sweep:
        _sweep(sweep, width, height, support)
    if cost:
        _cost(cost_spp)
    return 0
