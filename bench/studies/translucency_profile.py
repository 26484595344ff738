"""The fast translucent path against the reference: ``translucency = "profile"`` vs ``"volpath"``.

Usage: ``python -m bench.cli.translucency_profile [--objects plane,sphere,hand] [--materials skin]
[--angles 3] [--size 512] [--seeds 1,2] [--out results/runs/translucency-profile]``

For each object x translucent material, at ``--angles`` mirror angles over the middle 80 % of the
object's default scan, both paths render every angle with each of the ``--seeds`` (render cache off,
the scene's spp: 16 laser, 8 ambient). The ``plane`` and the ``sphere`` stand in front of the wall at
55 cm (the translucency study's geometry), the ``hand`` on the table with nothing behind it (the
``paper`` profile's ``hand-skin``). Per case and path, over the object's rows with a truth:

* **depth bias**: the stripe centre of each row of the noise-free laser radiance (:func:`centres`, within
  ±W/14 px of the truth) by the parabolic peak, by the centroid of the peak's core (the pixels above half
  the maximum, weighted by their excess over it) and, beside them, by the centroid of the whole window (the tails' share), triangulated
  by the paper's eq. 3 against the truth column (mm; positive = farther); the median over rows, angles
  and seeds. The difference profile - volpath comes with a paired bootstrap 95 % interval over the rows
  (:data:`N_BOOT` resamples); ``angles.csv`` has the medians per mirror angle.
* **stripe width**: the FWHM (px, :func:`bench.studies.translucency.stripe_widths_px`) of each row's
  profile after a running mean over :data:`WIDTH_ROWS` rows aligned at their truth columns, the median
  over rows; the ratio profile / volpath. The FWHM of a noisy profile is biased low (noise raises the
  maximum), and volpath's renders are noisy; so the criterion compares volpath's with the profile path's
  **noise-matched** FWHM: of its renders plus volpath's own Monte Carlo noise at that angle, the
  difference of volpath's two seeds over sqrt 2 (``fwhm_matched``).
* **centre noise**: ``z``, the render noise of ``com_bg``'s column on the noise-free expected image
  between the two seeds (``std(c1 - c2) / sqrt 2`` over the rows) in units of the sensor noise (the same
  statistic between pairs of sensor draws of one render, :data:`SENSOR_DRAWS` pairs), as
  :func:`bench.studies.translucency.render_noise`; also with the robust scale ``1.4826 MAD`` (``z_robust``),
  and the count of rows whose column moved more than :data:`JUMP_PX` (``jump_rows``); and ``z_pixel``, the
  rms over the stripe's pixels of the laser pass's per-pixel render noise (the two seeds) in units of the
  sensor's noise at that level (:func:`_pixel_z`).
* **cost**: wall and CPU (summed over threads) seconds per frame of ``Scene.render``, of the frames not
  in the render cache (``rendered`` of them; the renders are cached, so a second run reuses them and
  reports no cost), after loading the scene (and, for the profile path, computing or reading the
  line-spread table: ``first_s``); the machine may be shared.
* the laser energy and the ambient level on the object's rows, profile / volpath.

Outputs in ``--out``: ``profiles.csv`` (per material: the time to compute its line-spread table, its size
and total diffuse reflectance, :data:`TABLE_FIELDS`), ``paths.csv`` (one line per case and path,
:data:`PATH_FIELDS`), ``angles.csv`` (per case and mirror angle, :data:`ANGLE_FIELDS`) and
``comparison.csv`` (one line per case, :data:`COMPARE_FIELDS`, with the criteria of issue 24: the
median bias within :data:`BIAS_TOL_MM` of volpath's, the noise-matched width within :data:`WIDTH_TOL` and
the profile path's noise below the sensor's: robust centre ``z`` and ``z_pixel`` below 1).

``--single-scatter`` instead checks ``volpath``'s single scattering (``max_depth`` 2) against
Chandrasekhar's, with and without Mitsuba's ray offset (:func:`scenes.subsurface.ray_offset_mm`): a
board (20 x 20 cm, turned by each of :data:`BOARD_YAWS_DEG` about the vertical, 36 cm out along the
laser at mirror angle 0, nothing else in the scene) under a 0.2 mrad line, 2048x1920 pixels of the
rig's field of view cropped to 96x64 around the stripe's middle, 64 spp, against the same board white
(Lambertian, albedo 1). Per board and material: the laser energy relative to the white board and the
mean shift of the stripe across the line (mm on the board; rows' centroids minus the white board's),
rendered and predicted (:class:`scenes.subsurface.Kernel` of a one-collision table); written to
``single_scatter.csv`` (:data:`SINGLE_FIELDS`).
"""

from __future__ import annotations

import csv
import pathlib
import sys
import time

import numpy as np

from bench.config.options import names_check, width16_value
from bench.evaluate.stats import mad_scale

__all__ = ["study", "DEFAULTS", "PATH_FIELDS", "COMPARE_FIELDS", "ANGLE_FIELDS",
           "TABLE_FIELDS", "SINGLE_FIELDS",
           "BIAS_TOL_MM", "WIDTH_TOL", "N_BOOT", "WIDTH_ROWS", "SENSOR_DRAWS", "BOARD_YAWS_DEG", "scene_kwargs",
           "centres", "aligned_fwhm", "measure_case", "compare", "single_scatter", "objects_value", "materials_value",
           "seeds_value"]

#: Criteria of issue 24: |median bias (profile) - median bias (volpath)| <= 0.05 mm (parabolic and core
#: centroid), the noise-matched FWHM within 5 %, the profile path's noise below the sensor's (robust centre
#: z < 1 and pixel z < 1).
BIAS_TOL_MM = 0.05
WIDTH_TOL = 0.05
N_BOOT = 2000
WIDTH_ROWS = 9
SENSOR_DRAWS = 8
#: A row whose ``com_bg`` column moves more than this between the two seeds counts as a jump (``jump_rows``):
#: the tracker took another piece of light, which dominates the standard deviation of the centre noise.
JUMP_PX = 3.0
PATHS = ("volpath", "profile")
PATH_FIELDS = ("object", "material", "path", "frames", "rendered", "rows", "bias_parabolic_mm", "bias_core_mm",
               "bias_window_mm", "fwhm_px", "fwhm_matched_px", "render_noise_px", "sensor_noise_px", "z", "z_robust",
               "jump_rows", "z_pixel", "s_per_frame", "cpu_s_per_frame",
               "first_s", "laser_energy", "ambient_mean")
COMPARE_FIELDS = ("object", "material", "rows", "bias_volpath_mm", "bias_profile_mm", "dbias_parabolic_mm",
                  "dbias_parabolic_lo", "dbias_parabolic_hi", "dbias_core_mm", "dbias_core_lo", "dbias_core_hi",
                  "dbias_window_mm", "dbias_window_lo", "dbias_window_hi", "fwhm_ratio", "fwhm_matched_ratio", "z_volpath", "z_profile", "laser_energy_ratio", "ambient_ratio",
                  "z_robust_volpath", "z_robust_profile", "z_pixel_volpath", "z_pixel_profile", "cost_ratio", "bias_ok",
                  "width_ok", "noise_ok")
ANGLE_FIELDS = ("object", "material", "mirror_angle_deg", "rows", "parabolic_volpath_mm", "parabolic_profile_mm",
                "core_volpath_mm", "core_profile_mm", "window_volpath_mm", "window_profile_mm", "fwhm_volpath_px",
                "fwhm_profile_px", "fwhm_matched_px")
TABLE_FIELDS = ("material", "wall_s", "cpu_s", "diffuse_reflectance", "megabytes", "mfp_mm", "photons")
SINGLE_FIELDS = ("material", "yaw_deg", "phi_deg", "view_deg", "offset_mm", "energy_volpath", "energy_theory",
                 "energy_theory_offset", "shift_volpath_mm", "shift_theory_mm", "shift_theory_offset_mm")
#: Board yaws of ``--single-scatter``, deg (0: the board faces the laser).
BOARD_YAWS_DEG = (0.0, 12.0, -12.0, 25.0, -25.0, 40.0, -40.0)
DEFAULTS = {"out": "results/runs/translucency-profile", "objects": ["plane", "sphere", "hand"],
            "materials": ["skin"], "angles": 3, "size": 512, "seeds": [1, 2]}


def scene_kwargs(obj: str) -> dict:
    """The geometry of a case: the hand as in the ``paper`` profile (on the table, nothing behind), the
    other objects as in the translucency study (the wall at 55 cm, no table)."""
    return {"background": "none", "support": "table"} if obj == "hand" else {}


def centres(laser: np.ndarray, truth_cols: np.ndarray, rows: np.ndarray, half: int):
    """Three stripe centres of ``laser`` in rows ``rows``, each searched within ``±half`` px of the truth.

    Returns
    -------
    parabolic, core, window : ndarray, shape (len(rows),)
        The parabolic peak (three pixels around the maximum), the centroid of the peak's core (the
        contiguous pixels at or above half the maximum, weighted by their excess over it: no pull towards
        the pixel grid) and the centroid of the whole window; NaN where the row has no light.

    Examples
    --------
    >>> x = np.arange(40.0)
    >>> img = np.exp(-0.5 * ((x - 20.3) / 2.0) ** 2)[None, :]
    >>> par, core, win = centres(img, np.array([20.0]), np.array([0]), 10)
    >>> round(float(par[0]), 1), round(float(core[0]), 1), round(float(win[0]), 2)
    (20.3, 20.3, 20.3)
    """
    img = np.asarray(laser, float)
    w = img.shape[1]
    par, core, win = (np.full(len(rows), np.nan) for _ in range(3))
    for i, r in enumerate(rows):
        c = int(round(truth_cols[r]))
        lo, hi = max(c - half, 0), min(c + half + 1, w)
        prof = np.clip(img[r, lo:hi], 0.0, None)
        if prof.size < 3 or prof.sum() <= 0:
            continue
        x = np.arange(lo, hi, dtype=float)
        win[i] = float((prof * x).sum() / prof.sum())
        k = int(np.argmax(prof))
        a, b = k, k
        while a > 0 and prof[a - 1] >= 0.5 * prof[k]:
            a -= 1
        while b < prof.size - 1 and prof[b + 1] >= 0.5 * prof[k]:
            b += 1
        wc = prof[a:b + 1] - 0.5 * prof[k]
        core[i] = float((wc * x[a:b + 1]).sum() / wc.sum()) if wc.sum() > 0 else x[k]
        if 0 < k < prof.size - 1:
            y0, y1, y2 = prof[k - 1], prof[k], prof[k + 1]
            den = y0 - 2 * y1 + y2
            par[i] = x[k] + (0.5 * (y0 - y2) / den if den != 0 else 0.0)
    return par, core, win


def aligned_fwhm(laser: np.ndarray, truth_cols: np.ndarray, rows: np.ndarray, half: int,
                 n_rows: int = WIDTH_ROWS) -> np.ndarray:
    """FWHM (px) of each row's profile after a running mean over ``n_rows`` rows aligned at their truth.

    Each row's window ``round(truth) ± half`` is stacked; the running mean runs over consecutive entries of
    the stack (rows in order); the FWHM is :func:`bench.studies.translucency.stripe_widths_px`'s.
    """
    from bench.studies.translucency import stripe_widths_px

    img = np.asarray(laser, float)
    w = img.shape[1]
    stack = np.full((len(rows), 2 * half + 1), np.nan)
    for i, r in enumerate(rows):
        c = int(round(truth_cols[r]))
        lo, hi = c - half, c + half + 1
        if lo < 0 or hi > w:
            continue
        stack[i] = img[r, lo:hi]
    ok = np.all(np.isfinite(stack), axis=1)
    out = np.full(len(rows), np.nan)
    if not ok.any():
        return out
    good = stack[ok]
    k = max(1, int(n_rows))
    csum = np.cumsum(np.vstack([np.zeros(good.shape[1]), good]), axis=0)
    idx = np.arange(len(good))
    a = np.clip(idx - k // 2, 0, len(good))
    b = np.clip(idx + k // 2 + 1, 0, len(good))
    mean = (csum[b] - csum[a]) / (b - a)[:, None]
    fwhm, _, _ = stripe_widths_px(mean, np.full(len(good), float(half)), half)
    out[ok] = fwhm
    return out


def _pixel_z(lasers, ambient, sensor, truth_cols, rows, half) -> np.ndarray:
    """Per-pixel render noise of the laser pass in units of the sensor's noise, on the stripe's pixels
    (``±half`` px of the truth on ``rows``): ``(DN_1 - DN_2) / sqrt 2`` of the two seeds' noise-free
    images over the shot, read and quantisation noise at their mean level (``bench.studies.perf.shiny``'s
    ``z`` with the second seed in place of a reference)."""
    a, b = (sensor.expected_dn(ambient + l) - sensor.black_level_dn for l in lasers)
    noise = sensor.noise_dn(0.5 * (a + b))
    out = []
    w = a.shape[1]
    for r in rows:
        c = int(round(truth_cols[r]))
        lo, hi = max(c - half, 0), min(c + half + 1, w)
        out.append(((a[r, lo:hi] - b[r, lo:hi]) / np.sqrt(2.0)) / noise[r, lo:hi])
    return np.concatenate(out) if out else np.zeros(0)


def _com_bg(frame, sensor, tracker, rows):
    img = sensor.expected_dn(frame.radiance)
    bg = sensor.expected_dn(frame.radiance - frame.laser_radiance)
    return tracker.track(img, background=bg).columns[rows]


def measure_case(obj: str, material: str, *, angles: int = 3, width: int = 512, seeds=(1, 2),
                 progress: bool = True) -> dict:
    """Render one case with both paths and measure them (see the module docstring).

    Returns
    -------
    dict
        ``{"volpath": {...}, "profile": {...}, "rows": n}``, each path's per-row arrays (``parabolic_mm``,
        ``centroid_mm``, ``fwhm_px``, in the same row order for both paths), noise, cost and levels.
    """
    import scenes
    import trackers

    from bench.evaluate.triangulation import depth_cm

    height = width * 15 // 16
    half = max(3, width // 14)
    com_bg = trackers.make("com_bg")
    out = {}
    common_rows = None
    noise_images = {}  # mirror angle -> volpath's Monte Carlo noise (L1 - L2) / sqrt 2
    for path in PATHS:
        s = scenes.make(obj, material=material, width=width, height=height, translucency=path, **scene_kwargs(obj))
        rig, sensor = s.rig, s.sensor
        full = s.default_angles()
        k = max(1, len(full) // 10)
        thetas = np.linspace(full[k], full[-1 - k], angles) if angles > 1 else full[len(full) // 2:][:1]
        t0 = time.perf_counter()
        s.truth(float(full[len(full) // 2]))  # loads the scene (and, for the profile path, its table)
        first = time.perf_counter() - t0
        wall, cpu, par_mm, cen_mm, win_mm, fwhm, fwhm_matched, sens, sens_mad, noise_all, at, pixel_z = (
            [] for _ in range(12))
        energy, ambient = [], []
        rng = np.random.default_rng(int(seeds[0]))
        for theta in thetas:
            cols_by_seed, lasers = [], []
            for seed in seeds:
                cached = s.is_cached(float(theta), seed=int(seed))
                w0, c0 = time.perf_counter(), time.process_time()
                f = s.render(float(theta), seed=int(seed))
                if not cached:  # the cost of rendering, not of reading the render cache
                    wall.append(time.perf_counter() - w0)
                    cpu.append(time.process_time() - c0)
                rows = np.nonzero(f.truth.valid & f.truth.on_object)[0]
                truth = f.truth.columns
                p, c, wc = centres(f.laser_radiance, truth, rows, half)
                d_truth = depth_cm(truth[rows], rig)
                par_mm.append(10.0 * (depth_cm(p, rig) - d_truth))
                cen_mm.append(10.0 * (depth_cm(c, rig) - d_truth))
                win_mm.append(10.0 * (depth_cm(wc, rig) - d_truth))
                at.append(np.full(len(rows), float(theta)))
                fwhm.append(aligned_fwhm(f.laser_radiance, truth, rows, half))
                lasers.append(f.laser_radiance.astype(np.float64))
                if path == "profile":
                    noisy = f.laser_radiance + noise_images[float(theta)]
                    fwhm_matched.append(aligned_fwhm(noisy, truth, rows, half))
                energy.append(float(f.laser_radiance[rows].sum()))
                amb = (f.radiance - f.laser_radiance)[rows]
                ambient.append(float(np.mean(amb)))
                cols_by_seed.append(_com_bg(f, sensor, com_bg, rows))
            d = cols_by_seed[0] - cols_by_seed[1]
            noise_all.append(d[np.isfinite(d)])
            pixel_z.append(_pixel_z(lasers, f.radiance - f.laser_radiance, sensor, f.truth.columns, rows, half))
            if path == "volpath":
                noise_images[float(theta)] = (lasers[0] - lasers[1]) / np.sqrt(2.0)
            bgr = f.radiance - f.laser_radiance
            for _ in range(SENSOR_DRAWS):
                a = com_bg.track(sensor.capture(f.radiance, rng), background=sensor.capture(bgr, rng)).columns[rows]
                b = com_bg.track(sensor.capture(f.radiance, rng), background=sensor.capture(bgr, rng)).columns[rows]
                dd = (a - b)[np.isfinite(a - b)]
                sens.append(np.std(dd) / np.sqrt(2.0) if dd.size else np.nan)
                sens_mad.append(mad_scale(dd) / np.sqrt(2.0))
            if progress:
                print(f"translucency_profile: {obj}/{material}/{path} at {theta:+.3f} deg"
                      + (f": {wall[-1]:.1f} s/frame" if wall else " (cached)"), file=sys.stderr, flush=True)
        d = np.concatenate(noise_all)
        rn, rn_mad = float(np.std(d) / np.sqrt(2.0)), float(mad_scale(d) / np.sqrt(2.0))
        jumps = int(np.sum(np.abs(d) > JUMP_PX))
        sn, sn_mad = float(np.nanmean(sens)), float(np.nanmean(sens_mad))
        out[path] = {"parabolic_mm": np.concatenate(par_mm), "core_mm": np.concatenate(cen_mm),
                     "window_mm": np.concatenate(win_mm), "theta_deg": np.concatenate(at),
                     "fwhm_px": np.concatenate(fwhm),
                     "fwhm_matched_px": np.concatenate(fwhm_matched) if fwhm_matched else np.concatenate(fwhm), "frames": len(thetas) * len(seeds), "render_noise_px": rn,
                     "sensor_noise_px": sn, "z": rn / sn, "z_robust": rn_mad / sn_mad, "jump_rows": jumps,
                     "z_pixel": float(np.sqrt(np.mean(np.concatenate(pixel_z) ** 2))),
                     "s_per_frame": float(np.mean(wall)) if wall else np.nan,
                     "cpu_s_per_frame": float(np.mean(cpu)) if cpu else np.nan, "rendered": len(wall),
                     "first_s": first, "laser_energy": float(np.mean(energy)), "ambient_mean": float(np.mean(ambient))}
        n = len(out[path]["parabolic_mm"])
        common_rows = n if common_rows is None else common_rows
        if n != common_rows:
            raise RuntimeError(f"{obj}/{material}: the paths have different truth rows ({n} vs {common_rows})")
    out["rows"] = common_rows
    return out


def _median_diff_ci(a: np.ndarray, b: np.ndarray, n_boot: int, seed: int):
    """Median of ``b`` minus median of ``a`` (paired rows, NaN in either dropped) and its bootstrap 95 % interval."""
    ok = np.isfinite(a) & np.isfinite(b)
    a, b = a[ok], b[ok]
    if a.size == 0:
        return np.nan, np.nan, np.nan
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, a.size, (n_boot, a.size))
    boots = np.median(b[idx], axis=1) - np.median(a[idx], axis=1)
    return float(np.median(b) - np.median(a)), float(np.percentile(boots, 2.5)), float(np.percentile(boots, 97.5))


def compare(obj: str, material: str, m: dict, seed: int = 0) -> tuple[list[dict], dict, list[dict]]:
    """Per-path lines (:data:`PATH_FIELDS`), the comparison line (:data:`COMPARE_FIELDS`) and per-angle lines
    (:data:`ANGLE_FIELDS`) of a case. The bias criterion is met when both peak estimators (parabolic and
    core centroid) are within :data:`BIAS_TOL_MM`; the window centroid is reported beside them."""
    lines = []
    for path in PATHS:
        r = m[path]
        lines.append({"object": obj, "material": material, "path": path, "frames": r["frames"], "rows": m["rows"],
                      "bias_parabolic_mm": float(np.nanmedian(r["parabolic_mm"])),
                      "bias_core_mm": float(np.nanmedian(r["core_mm"])),
                      "bias_window_mm": float(np.nanmedian(r["window_mm"])),
                      "fwhm_px": float(np.nanmedian(r["fwhm_px"])),
                      "fwhm_matched_px": float(np.nanmedian(r["fwhm_matched_px"])),
                      **{k: r[k] for k in ("rendered", "render_noise_px", "sensor_noise_px", "z", "z_robust", "jump_rows", "z_pixel",
                                           "s_per_frame",
                                           "cpu_s_per_frame", "first_s", "laser_energy", "ambient_mean")}})
    v, p = m["volpath"], m["profile"]
    d = {name: _median_diff_ci(v[f"{name}_mm"], p[f"{name}_mm"], N_BOOT, seed + i)
         for i, name in enumerate(("parabolic", "core", "window"))}
    ratio = lines[1]["fwhm_px"] / lines[0]["fwhm_px"]
    matched = lines[1]["fwhm_matched_px"] / lines[0]["fwhm_px"]
    cmp = {"object": obj, "material": material, "rows": m["rows"],
           "bias_volpath_mm": lines[0]["bias_parabolic_mm"], "bias_profile_mm": lines[1]["bias_parabolic_mm"],
           **{f"dbias_{name}{suffix}": d[name][i] for name in d for i, suffix in enumerate(("_mm", "_lo", "_hi"))},
           "fwhm_ratio": ratio, "fwhm_matched_ratio": matched, "z_volpath": v["z"], "z_profile": p["z"],
           "z_robust_volpath": v["z_robust"], "z_robust_profile": p["z_robust"], "z_pixel_volpath": v["z_pixel"],
           "z_pixel_profile": p["z_pixel"],
           "laser_energy_ratio": p["laser_energy"] / v["laser_energy"], "ambient_ratio": p["ambient_mean"] / v["ambient_mean"],
           "cost_ratio": v["s_per_frame"] / p["s_per_frame"],
           "bias_ok": bool(abs(d["parabolic"][0]) <= BIAS_TOL_MM and abs(d["core"][0]) <= BIAS_TOL_MM),
           "width_ok": bool(abs(matched - 1.0) <= WIDTH_TOL),
           "noise_ok": bool(p["z_robust"] < 1.0 and p["z_pixel"] < 1.0)}
    angles = []
    for theta in np.unique(v.get("theta_deg", np.zeros(0))):
        a, b = v["theta_deg"] == theta, p["theta_deg"] == theta
        angles.append({"object": obj, "material": material, "mirror_angle_deg": float(theta), "rows": int(a.sum()),
                       "parabolic_volpath_mm": float(np.nanmedian(v["parabolic_mm"][a])),
                       "parabolic_profile_mm": float(np.nanmedian(p["parabolic_mm"][b])),
                       "core_volpath_mm": float(np.nanmedian(v["core_mm"][a])),
                       "core_profile_mm": float(np.nanmedian(p["core_mm"][b])),
                       "window_volpath_mm": float(np.nanmedian(v["window_mm"][a])),
                       "window_profile_mm": float(np.nanmedian(p["window_mm"][b])),
                       "fwhm_volpath_px": float(np.nanmedian(v["fwhm_px"][a])),
                       "fwhm_profile_px": float(np.nanmedian(p["fwhm_px"][b])),
                       "fwhm_matched_px": float(np.nanmedian(p["fwhm_matched_px"][b]))})
    return lines, cmp, angles


def single_scatter(material: str, yaws=BOARD_YAWS_DEG, *, spp: int = 64, width: int = 2048) -> list[dict]:
    """``volpath``'s single scattering on a turned board against Chandrasekhar's (see the module docstring)."""
    import dataclasses

    from scenes import description, rig as _rig, shapes, subsurface
    from scenes import LoadedScene
    from scenes import laser_profile as profile
    from scenes import SceneObject

    rig = _rig.Rig().with_size(width, width * 15 // 16)
    laser = profile(0.2, 90.0)
    one = subsurface.compute(dataclasses.replace(subsurface.spec_for(material), max_collisions=1, photons=1))
    _, nl = rig.laser_plane(0.0)
    cam, origin = rig.camera_center_cm(0.0), rig.laser_origin_cm(0.0)
    out = []
    for yaw in yaws:
        place = _rig.translation(_rig.cylindrical_to_cartesian(36.0, -rig.zeta_deg, 0.0)) @ _rig.rotation_z(-rig.zeta_deg)
        mesh = shapes.planar_uv(shapes.rectangle(20.0, 20.0).transformed(_rig.rotation_z(yaw))).transformed(place)
        board = SceneObject("board", mesh, None, (0.0, 0.0))
        p0, n = mesh.vertices_cm.mean(axis=0), mesh.normals[0]
        n = n if n @ (cam - p0) > 0 else -n
        rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float), indexing="ij")
        o, d = rig.pixel_rays(cols, rows, 0.0)
        u_mm = 10.0 * ((o + (((p0 - o) @ n) / (d @ n))[..., None] * d) @ nl) / np.sqrt(1.0 - (nl @ n) ** 2)
        y0, x0 = rig.height // 2 - 32, int(np.argmin(np.abs(u_mm[rig.height // 2]))) - 48
        u = u_mm[y0:y0 + 64, x0:x0 + 96]
        imgs = []
        for mat, kind in ((material, ("volpath", 2)), ("matte", ("path", 2))):
            sc = description.laser_scene(rig, board, mat, laser, 0.0, spp)
            if mat == "matte":
                sc["object"]["bsdf"] = {"type": "diffuse", "reflectance": 1.0}
            sc["sensor"]["film"].update(crop_offset_x=x0, crop_offset_y=y0, crop_width=96, crop_height=64)
            imgs.append(LoadedScene(sc).render(description.pose_updates(rig, 0.0), spp, 7, integrator=kind).astype(float))
        vol, white = imgs
        shift = float(np.median((vol * u).sum(1) / vol.sum(1) - (white * u).sum(1) / white.sum(1)))
        omega, view = subsurface.local_geometry(p0, n, nl, origin, cam)
        off = float(subsurface.ray_offset_mm(p0))
        theory = []
        for offset in (0.0, off):
            k = subsurface.Kernel(one, omega, view, offset)
            x = np.linspace(-15.0, 15.0, 300001) * one.spec.mfp_mm
            dens = np.diff(k.cdf(x))
            theory.append((k.total, float(np.sum(0.5 * (x[1:] + x[:-1]) * dens) / dens.sum())))
        out.append({"material": material, "yaw_deg": float(yaw),
                    "phi_deg": float(np.degrees(np.arctan2(omega[0], omega[2]))),
                    "view_deg": float(np.degrees(np.arctan2(view[0], view[2]))), "offset_mm": off,
                    "energy_volpath": float(vol.sum() / white.sum()), "energy_theory": theory[0][0],
                    "energy_theory_offset": theory[1][0], "shift_volpath_mm": shift, "shift_theory_mm": theory[0][1],
                    "shift_theory_offset_mm": theory[1][1]})
    return out


def _write(rows: list[dict], path, fields) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def _objects():
    import scenes

    return scenes.available()


def _translucent():
    from scenes.materials import TRANSLUCENT

    return list(TRANSLUCENT)


def seeds_value(name, text):
    from bench.config import ConfigError

    parts = [v.strip() for v in str(text).split(",") if v.strip()]
    if len(parts) != 2 or not all(p.isdigit() for p in parts) or parts[0] == parts[1]:
        raise ConfigError(f"{name} must be two different integers >= 0, got {text!r}")
    return [int(p) for p in parts]


#: The checks of the study's option values, ``check(name, text) -> value`` raising
#: :class:`bench.config.ConfigError` (the command line's types: :mod:`bench.cli.studies`).
objects_value = names_check("object", _objects)
materials_value = names_check("material", _translucent)
_single_scatter = single_scatter


def study(*, out=DEFAULTS["out"], objects=DEFAULTS["objects"], materials=DEFAULTS["materials"],
          angles: int = DEFAULTS["angles"], size: int = DEFAULTS["size"], seeds=DEFAULTS["seeds"],
          single_scatter: bool = False, quiet: bool = False) -> int:
    """Run the comparison and write its tables into ``out`` (``python -m bench.cli.translucency_profile``).

    Parameters
    ----------
    out : path
        Output folder (created).
    objects, materials : list of str
        The objects and translucent materials.
    angles : int
        Mirror angles per case.
    size : int
        Image width, px, a multiple of 16.
    seeds : list of two int
        The two render seeds.
    single_scatter : bool
        Instead: volpath's single scattering on turned boards against Chandrasekhar's (:func:`single_scatter`).
    quiet : bool
        No progress bars.

    Returns
    -------
    int
        0.
    """
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if single_scatter:
        rows = [r for m in materials for r in _single_scatter(m)]  # the function; the flag shadows its name
        _write(rows, out / "single_scatter.csv", SINGLE_FIELDS)
        print(f"wrote {out / 'single_scatter.csv'}")
        print("| material | board yaw | in-section incidence / view | energy: volpath, theory, with offset | "
              "shift across the line (mm): volpath, theory, with offset |")
        print("| --- | --- | --- | --- | --- |")
        for r in rows:
            print(f"| {r['material']} | {r['yaw_deg']:+.0f}° | {r['phi_deg']:+.1f}° / {r['view_deg']:+.1f}° | "
                  f"{r['energy_volpath']:.4f}, {r['energy_theory']:.4f}, {r['energy_theory_offset']:.4f} | "
                  f"{r['shift_volpath_mm']:+.4f}, {r['shift_theory_mm']:+.4f}, {r['shift_theory_offset_mm']:+.4f} |")
        return 0
    tables = []
    for material in materials:
        from scenes import subsurface

        spec = subsurface.spec_for(material)
        w0, c0 = time.perf_counter(), time.process_time()
        t = subsurface.compute(spec)
        tables.append({"material": material, "wall_s": time.perf_counter() - w0, "cpu_s": time.process_time() - c0,
                       "diffuse_reflectance": t.diffuse_reflectance, "megabytes": t.collided.nbytes / 1e6,
                       "mfp_mm": spec.mfp_mm, "photons": spec.photons})
    _write(tables, out / "profiles.csv", TABLE_FIELDS)
    paths, comps, per_angles = [], [], []
    for material in materials:
        for obj in objects:
            m = measure_case(obj, material, angles=angles, width=size, seeds=seeds,
                             progress=not quiet)
            lines, cmp, per_angle = compare(obj, material, m, seed=seeds[0])
            paths += lines
            comps.append(cmp)
            per_angles += per_angle
            _write(paths, out / "paths.csv", PATH_FIELDS)
            _write(comps, out / "comparison.csv", COMPARE_FIELDS)
            _write(per_angles, out / "angles.csv", ANGLE_FIELDS)
    print(f"wrote {out / 'profiles.csv'}, {out / 'paths.csv'}, {out / 'comparison.csv'} and {out / 'angles.csv'}")
    for t in tables:
        print(f"{t['material']}: line-spread table computed in {t['wall_s']:.1f} s ({t['cpu_s']:.1f} CPU s), "
              f"{t['megabytes']:.1f} MB, total diffuse reflectance {t['diffuse_reflectance']:.4f}")
    print("| case | bias volpath / profile (mm, parabolic) | Δ parabolic [95 %] | Δ core centroid [95 %] | "
          "Δ window centroid [95 %] | FWHM ratio (noise-matched) | z volpath / profile | s/frame volpath / profile |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    by = {(r["object"], r["material"], r["path"]): r for r in paths}
    for c in comps:
        v, p = by[(c["object"], c["material"], "volpath")], by[(c["object"], c["material"], "profile")]
        print(f"| {c['object']} {c['material']} | {c['bias_volpath_mm']:+.3f} / {c['bias_profile_mm']:+.3f} | "
              f"{c['dbias_parabolic_mm']:+.3f} [{c['dbias_parabolic_lo']:+.3f}, {c['dbias_parabolic_hi']:+.3f}] | "
              f"{c['dbias_core_mm']:+.3f} [{c['dbias_core_lo']:+.3f}, {c['dbias_core_hi']:+.3f}] | "
              f"{c['dbias_window_mm']:+.3f} [{c['dbias_window_lo']:+.3f}, {c['dbias_window_hi']:+.3f}] | "
              f"{c['fwhm_ratio']:.3f} ({c['fwhm_matched_ratio']:.3f}) | {c['z_volpath']:.2f} / {c['z_profile']:.2f} | "
              f"{v['s_per_frame']:.1f} / {p['s_per_frame']:.2f} |")
    return 0
