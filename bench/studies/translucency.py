"""Translucency study (``stripebench translucency``): the peak bias of subsurface scattering.

On a translucent surface (``skin``, ``marble``, ``wax``; see :mod:`scenes.materials`) the laser
light enters, scatters under the surface and leaves around the entry point: the stripe is wider
and dimmer, and its centre is not where the laser sheet meets the surface. This study renders
the ``plane`` and the ``sphere`` in each translucent material and the opaque ``matte`` reference
at several mirror angles, runs every sub-pixel tracker on the frames and compares its columns
with the geometric ground truth (the sheet's intersection with the surface, which the medium
does not change).

Per row on the object it records the local **angle of incidence** (between the reversed laser ray
and the surface normal at the truth point, deg), the rendered stripe's width on the noise-free
laser radiance (FWHM and the 10-90 % energy width within ±1/14 of the image width of the truth,
px), and each tracker's error in px (``column - truth``) and in depth (eq. 3 of the paper, mm).
**Sign convention:** a positive depth error means the point is reported *farther* from the mirror
axis (deeper, away from the rig) than the surface; a positive px error means a larger column,
which in this rig is a *nearer* point.

Outputs in ``--out`` (default ``results/runs/translucency``): ``translucency.csv``, one line per
(object, material, incidence bin, tracker), columns :data:`FIELDS`; ``translucency.png``, stripe
width and depth bias ± spread against the angle of incidence; with ``--spp-study`` also
``render_noise.csv`` (:func:`render_noise`): the Monte Carlo noise of the stripe's centre
against spp beside the sensor's own noise.
"""

from __future__ import annotations

import csv
import pathlib
import sys
import time

import numpy as np

from bench.config.options import names_check, width16_value
from bench.evaluate.stats import mad_scale

__all__ = ["study", "DEFAULTS", "MAX_ANGLES", "FIELDS", "NOISE_FIELDS", "INCIDENCE_BINS_DEG", "incidence_deg", "stripe_widths_px", "run_study",
           "summarise", "render_noise", "write_csv", "plot", "objects_value", "materials_value", "spp_count",
           "spp_list"]

#: Columns of ``translucency.csv``.
FIELDS = ("object", "material", "incidence_lo_deg", "incidence_hi_deg", "tracker", "rows", "reported",
          "fwhm_px", "width1090_px", "peak_rel", "bias_px", "spread_px", "bias_mm", "spread_mm", "median_mm",
          "iqr_mm")
#: Columns of ``render_noise.csv``.
NOISE_FIELDS = ("object", "material", "spp", "rows", "mc_noise_px", "sensor_noise_px", "mc_noise_mad_px",
                "sensor_noise_mad_px", "s_per_frame", "cpu_s_per_frame")
#: Edges of the angle-of-incidence bins, deg.
INCIDENCE_BINS_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0)


def incidence_deg(points_cm: np.ndarray, laser_origin_cm: np.ndarray, mesh) -> np.ndarray:
    """Angle between the reversed laser ray and the surface normal at each point, deg.

    Parameters
    ----------
    points_cm : ndarray, shape (N, 3)
        Points on the surface (world cm); NaN rows give NaN.
    laser_origin_cm : ndarray, shape (3,)
        The laser's pinhole (world cm).
    mesh : scenes.shapes.Mesh
        The surface; the normal is the vertex normal of the nearest vertex.

    Returns
    -------
    ndarray, shape (N,)
        0 = normal incidence, 90 = grazing.

    Examples
    --------
    >>> from scenes import shapes
    >>> plate = shapes.rectangle(10.0, 10.0)           # in y = 0, normal -Y
    >>> incidence_deg(np.array([[0.0, 0.0, 0.0]]), np.array([0.0, -10.0, 10.0]), plate).round(3)
    array([45.])
    """
    from scipy.spatial import cKDTree

    p = np.asarray(points_cm, float).reshape(-1, 3)
    out = np.full(len(p), np.nan)
    ok = np.isfinite(p).all(axis=1)
    if not ok.any():
        return out
    _, idx = cKDTree(mesh.vertices_cm).query(p[ok])
    n = mesh.normals[idx]
    to_laser = np.asarray(laser_origin_cm, float) - p[ok]
    to_laser /= np.linalg.norm(to_laser, axis=1, keepdims=True)
    out[ok] = np.degrees(np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", n, to_laser)), 0.0, 1.0)))
    return out


def stripe_widths_px(laser_radiance: np.ndarray, truth_columns: np.ndarray, half_window_px: int):
    """Per-row width of the noise-free stripe around the truth.

    Parameters
    ----------
    laser_radiance : ndarray, shape (H, W)
        Laser-only radiance.
    truth_columns : ndarray, shape (H,)
        Truth column per row (NaN: no stripe; the row gets NaN).
    half_window_px : int
        The profile is read within ``±half_window_px`` of the rounded truth.

    Returns
    -------
    fwhm_px, width1090_px, peak : ndarray, shape (H,)
        Full width at half maximum (linear interpolation between the samples that cross half the
        row's maximum, walking out from the maximum), the width holding the central 80 % of the
        window's energy, and the maximum radiance.

    Examples
    --------
    >>> x = np.arange(41.0)
    >>> img = np.exp(-0.5 * ((x - 20.0) / 2.0) ** 2)[None, :]
    >>> f, w, p = stripe_widths_px(img, np.array([20.0]), 15)
    >>> round(float(f[0]), 2), round(float(w[0]), 2)   # sigma 2 px: FWHM 4.71, 10-90 % 5.13 (continuous)
    (4.76, 5.1)
    """
    img = np.asarray(laser_radiance, float)
    h, w = img.shape
    fwhm = np.full(h, np.nan)
    w1090 = np.full(h, np.nan)
    peak = np.full(h, np.nan)
    for r in np.where(np.isfinite(truth_columns))[0]:
        c = int(round(truth_columns[r]))
        lo, hi = max(c - half_window_px, 0), min(c + half_window_px + 1, w)
        prof = np.clip(img[r, lo:hi], 0.0, None)
        if prof.size < 3 or prof.max() <= 0:
            continue
        k = int(np.argmax(prof))
        half = 0.5 * prof[k]
        left = k
        while left > 0 and prof[left - 1] >= half:
            left -= 1
        right = k
        while right < prof.size - 1 and prof[right + 1] >= half:
            right += 1
        xl = left - 0.5 if left == 0 else left - (prof[left] - half) / (prof[left] - prof[left - 1])
        xr = right + 0.5 if right == prof.size - 1 else right + (prof[right] - half) / (prof[right] - prof[right + 1])
        fwhm[r] = xr - xl
        # energy width on the piecewise-constant profile (each sample covers one pixel)
        cum = np.concatenate([[0.0], np.cumsum(prof)]) / prof.sum()
        edges = np.arange(prof.size + 1) - 0.5
        w1090[r] = np.interp(0.9, cum, edges) - np.interp(0.1, cum, edges)
        peak[r] = prof[k]
    return fwhm, w1090, peak


def _subpixel_trackers(names=None):
    import trackers

    names = names if names is not None else trackers.available()
    return [t for t in (trackers.make(n) for n in names) if t.subpixel]


def run_study(objects=("plane", "sphere"), materials=("matte", "skin", "marble", "wax"), *, n_angles: int = 5,
              width: int = 128, height: int = 120, spp: int = 64, seed: int = 0, tracker_names=None,
              progress: bool = True) -> list[dict]:
    """Render every object x material at ``n_angles`` mirror angles and measure every sub-pixel tracker.

    The angles are the object's default scan (:meth:`scenes.Scene.default_angles`) without its first
    and last tenth (where the stripe only grazes the object's edge). Returns one dict per row of
    the object (keys ``object, material, mirror_angle_deg, row, incidence_deg, fwhm_px,
    width1090_px, peak, truth_px, depth_truth_mm`` and ``<tracker>_px``, NaN where it reported
    nothing); :func:`summarise` bins them.
    """
    import scenes

    from bench.evaluate.triangulation import depth_cm

    tracker_list = _subpixel_trackers(tracker_names)
    records = []
    for obj_name in objects:
        for material in materials:
            s = scenes.make(obj_name, material=material, width=width, height=height, spp=spp, seed=seed)
            rig, obj = s.rig, s.object
            full = s.default_angles()
            k = max(1, len(full) // 10)
            angles = np.linspace(full[k], full[-1 - k], n_angles)
            t0 = time.time()
            for theta in angles:
                f = s.render(float(theta))
                rows = np.where(f.truth.valid & f.truth.on_object)[0]
                if rows.size == 0:
                    continue
                inc = incidence_deg(f.truth.points_cm[rows], rig.laser_origin_cm(theta), obj.mesh)
                fwhm, w1090, peak = stripe_widths_px(f.laser_radiance, np.where(f.truth.on_object, f.truth.columns,
                                                                                np.nan), max(3, width // 14))
                truth = f.truth.columns[rows]
                d_truth = 10.0 * depth_cm(truth, rig)
                cols = {t.name: t.track(f.image, background=f.background).columns[rows] for t in tracker_list}
                for i, r in enumerate(rows):
                    rec = {"object": obj_name, "material": material, "mirror_angle_deg": float(theta), "row": int(r),
                           "incidence_deg": float(inc[i]), "fwhm_px": float(fwhm[r]), "width1090_px": float(w1090[r]),
                           "peak": float(peak[r]), "truth_px": float(truth[i]), "depth_truth_mm": float(d_truth[i])}
                    for name, c in cols.items():
                        rec[f"{name}_px"] = float(c[i])
                    records.append(rec)
            if progress:
                print(f"translucency: {obj_name}/{material}: {len(angles)} frames in {time.time() - t0:.1f} s",
                      file=sys.stderr)
    return records


def summarise(records: list[dict], width: int, bins=INCIDENCE_BINS_DEG) -> list[dict]:
    """Bin the per-row records by angle of incidence; one dict per (object, material, bin, tracker).

    ``bias_*`` is the mean error and ``spread_*`` its standard deviation over the reported rows of
    the bin; ``median_mm`` the median depth error and ``iqr_mm`` its interquartile range (robust to
    the few rows where a tracker jumps off the stripe); ``peak_rel`` the median stripe peak radiance
    relative to ``matte`` on the same object in the same bin (NaN without a ``matte`` reference).
    Depth errors use eq. 3 of the paper at the image size ``width`` (the rig's 16:15 aspect).
    """
    import scenes

    from bench.evaluate.triangulation import depth_cm

    rig = scenes.Rig().with_size(int(width), int(width) * 15 // 16)
    names = sorted({k[:-3] for r in records for k in r if k.endswith("_px") and k not in
                    ("fwhm_px", "width1090_px", "truth_px")})
    edges = np.asarray(bins, float)
    out = []
    keyed: dict = {}
    for r in records:
        b = int(np.clip(np.searchsorted(edges, r["incidence_deg"], side="right") - 1, 0, len(edges) - 2))
        keyed.setdefault((r["object"], r["material"], b), []).append(r)
    for (obj, mat, b), rows in sorted(keyed.items(), key=lambda kv: (kv[0][0], kv[0][2])):
        ref = keyed.get((obj, "matte", b))
        peak = np.nanmedian([r["peak"] for r in rows])
        peak_rel = peak / np.nanmedian([r["peak"] for r in ref]) if ref else np.nan
        truth = np.array([r["truth_px"] for r in rows])
        for name in names:
            cols = np.array([r[f"{name}_px"] for r in rows])
            ok = np.isfinite(cols)
            e_px = cols[ok] - truth[ok]
            e_mm = 10.0 * (depth_cm(cols[ok], rig) - depth_cm(truth[ok], rig))
            some = e_px.size > 0
            out.append({
                "object": obj, "material": mat, "incidence_lo_deg": float(edges[b]), "incidence_hi_deg": float(edges[b + 1]),
                "tracker": name, "rows": len(rows), "reported": float(ok.mean()),
                "fwhm_px": float(np.nanmedian([r["fwhm_px"] for r in rows])),
                "width1090_px": float(np.nanmedian([r["width1090_px"] for r in rows])),
                "peak_rel": float(peak_rel),
                "bias_px": float(e_px.mean()) if some else np.nan, "spread_px": float(e_px.std()) if some else np.nan,
                "bias_mm": float(e_mm.mean()) if some else np.nan, "spread_mm": float(e_mm.std()) if some else np.nan,
                "median_mm": float(np.median(e_mm)) if some else np.nan,
                "iqr_mm": float(np.subtract(*np.percentile(e_mm, [75, 25]))) if some else np.nan,
            })
    order = {m: i for i, m in enumerate(dict.fromkeys(r["material"] for r in records))}
    out.sort(key=lambda d: (d["object"], order[d["material"]], d["incidence_lo_deg"], d["tracker"]))
    return out


def render_noise(obj_name: str, material: str, spps, *, width: int = 512, height: int = 480, seed: int = 0,
                 tracker: str = "com_bg", sensor_draws: int = 8) -> list[dict]:
    """Monte Carlo noise of the stripe's centre against spp, beside the sensor's noise.

    At the middle mirror angle of the object's scan the laser pass is rendered at each spp with
    two seeds (``seed`` and ``seed + 1``, cache off). The *render noise* of the centre is
    ``std(c1 - c2) / sqrt(2)`` over the object's rows, where ``c`` is ``tracker``'s column on the
    noise-free expected image (radiance through the sensor's gain, no shot/read noise, no
    rounding). The *sensor noise* is the same statistic between ``sensor_draws`` pairs of sensor
    draws of the highest-spp render (their mean). ``mc_noise_mad_px`` and ``sensor_noise_mad_px`` are
    the same with the robust scale ``1.4826 MAD / sqrt(2)`` instead of the standard deviation: the
    typical row, which a few firefly rows do not dominate. ``s_per_frame`` is the wall time of the second
    render at that spp (both passes and the truth; the scene is already loaded), ``cpu_s_per_frame``
    its CPU time summed over threads (the fair measure on a shared machine).

    Returns
    -------
    list of dict
        One per spp, keys :data:`NOISE_FIELDS`.
    """
    import scenes
    import trackers

    t = trackers.make(tracker)
    out = []
    best = None
    s = scenes.make(obj_name, material=material, width=width, height=height, seed=seed, cache=False)
    a = s.default_angles()
    theta = float(a[len(a) // 2])
    for spp in sorted(spps):
        cols = []
        dt = []
        cpu = []
        for k in range(2):
            t0, c0 = time.time(), time.process_time()
            f = s.render(theta, spp=int(spp), seed=seed + k)
            dt.append(time.time() - t0)
            cpu.append(time.process_time() - c0)
            rows = np.where(f.truth.valid & f.truth.on_object)[0]
            sensor = s.sensor
            img = sensor.expected_dn(f.radiance)
            bg = sensor.expected_dn(f.radiance - f.laser_radiance)
            cols.append(t.track(img, background=bg).columns[rows])
            best = (s, f, rows)
        d = cols[0] - cols[1]
        d = d[np.isfinite(d)]
        out.append({"object": obj_name, "material": material, "spp": int(spp), "rows": int(d.size),
                    "mc_noise_px": float(np.std(d) / np.sqrt(2.0)) if d.size else np.nan,
                    "sensor_noise_px": np.nan, "mc_noise_mad_px": mad_scale(d) / np.sqrt(2.0),
                    "sensor_noise_mad_px": np.nan, "s_per_frame": float(dt[1]),
                    "cpu_s_per_frame": float(cpu[1])})
    s, f, rows = best
    rng = np.random.default_rng(seed)
    sens, sens_mad = [], []
    sensor = s.sensor
    ambient = f.radiance - f.laser_radiance
    for _ in range(sensor_draws):
        c = [t.track(sensor.capture(f.radiance, rng), background=sensor.capture(ambient, rng)).columns[rows]
             for _ in range(2)]
        d = c[0] - c[1]
        d = d[np.isfinite(d)]
        sens.append(np.std(d) / np.sqrt(2.0) if d.size else np.nan)
        sens_mad.append(mad_scale(d) / np.sqrt(2.0))
    for r in out:
        r["sensor_noise_px"] = float(np.nanmean(sens))
        r["sensor_noise_mad_px"] = float(np.nanmean(sens_mad))
    return out


def write_csv(rows: list[dict], path, fields=FIELDS) -> None:
    """Write ``rows`` with the columns ``fields``."""
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def plot(summary: list[dict], path, tracker: str = "com_bg") -> None:
    """Stripe width (10-90 % energy width) and ``tracker``'s median depth error ± half the IQR against the
    angle of incidence, and every tracker's median depth error: one row of panels per object, one line
    (bar) per material. matplotlib is imported here, Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    objs = list(dict.fromkeys(r["object"] for r in summary))
    mats = list(dict.fromkeys(r["material"] for r in summary))
    trs = list(dict.fromkeys(r["tracker"] for r in summary))
    fig, axes = plt.subplots(len(objs), 3, figsize=(13, 3.3 * len(objs)), squeeze=False)
    markers = "osD^v"
    for i, obj in enumerate(objs):
        for k, mat in enumerate(mats):
            rows = [r for r in summary if r["object"] == obj and r["material"] == mat and r["tracker"] == tracker]
            x = [0.5 * (r["incidence_lo_deg"] + r["incidence_hi_deg"]) for r in rows]
            axes[i][0].plot(x, [r["width1090_px"] for r in rows], marker=markers[k % 5], label=mat)
            axes[i][1].errorbar(x, [r["median_mm"] for r in rows], yerr=[0.5 * r["iqr_mm"] for r in rows],
                                marker=markers[k % 5], capsize=3, label=mat)
        # every tracker's median depth error, averaged over the bins below 75 deg (weighted by reported
        # rows); at grazing incidence the stripe ends at the silhouette and trackers jump to the backdrop
        for k, mat in enumerate(mats):
            vals = []
            for name in trs:
                rr = [r for r in summary if r["object"] == obj and r["material"] == mat and r["tracker"] == name
                      and r["incidence_hi_deg"] <= 75.0]
                w = np.array([r["rows"] * r["reported"] for r in rr], float)
                b = np.array([r["median_mm"] for r in rr], float)
                ok = np.isfinite(b) & (w > 0)
                vals.append(float(np.average(b[ok], weights=w[ok])) if ok.any() else np.nan)
            xs = np.arange(len(trs)) + (k - (len(mats) - 1) / 2) * 0.8 / len(mats)
            axes[i][2].bar(xs, vals, width=0.8 / len(mats), label=mat)
        axes[i][2].set_xticks(np.arange(len(trs)))
        axes[i][2].set_xticklabels(trs, rotation=30, fontsize=7)
        axes[i][0].set_ylabel(f"{obj}\nstripe 10-90 % width (px)", fontsize=9)
        axes[i][1].set_ylabel(f"{tracker} median depth error ± IQR/2 (mm)", fontsize=9)
        axes[i][2].set_ylabel("median depth error, incidence < 75° (mm)", fontsize=9)
        for ax in axes[i][:2]:
            ax.set_xlabel("angle of incidence (deg)", fontsize=9)
        for ax in axes[i]:
            ax.grid(True, alpha=0.3)
            ax.tick_params(labelsize=8)
        axes[i][1].axhline(0.0, color="k", lw=0.6)
        axes[i][2].axhline(0.0, color="k", lw=0.6)
    axes[0][0].legend(fontsize=8)
    axes[0][2].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)
    fig.suptitle("Subsurface scattering: stripe width and depth bias (positive = reported farther than the surface)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


#: The study's defaults.
DEFAULTS = {"out": "results/runs/translucency", "objects": ["plane", "sphere"],
            "materials": ["matte", "skin", "marble", "wax"], "angles": 5, "size": 256, "spp": 64, "seed": 0,
            "plot_tracker": "com_bg"}
MAX_ANGLES = 1000


def spp_list(name, text):
    from bench.config import ConfigError

    parts = [v.strip() for v in str(text).split(",") if v.strip()]
    if not parts:
        raise ConfigError(f"{name} must list positive integers, got {text!r}")
    return [spp_count(name, v) for v in parts]


def _objects():
    import scenes

    return scenes.available()


def _materials():
    import scenes

    return scenes.MATERIALS


def spp_count(name, text):
    from scenes import MAX_SIZE

    from bench.config.options import positive_int

    return positive_int(name, text, MAX_SIZE["spp"])


#: The checks of the study's option values, ``check(name, text) -> value`` raising
#: :class:`bench.config.ConfigError` (the command line's types: :mod:`bench.cli.studies`).
objects_value = names_check("object", _objects)
materials_value = names_check("material", _materials)


def study(*, out=DEFAULTS["out"], objects=DEFAULTS["objects"], materials=DEFAULTS["materials"],
          angles: int = DEFAULTS["angles"], size: int = DEFAULTS["size"], spp: int = DEFAULTS["spp"],
          seed: int = DEFAULTS["seed"], trackers=None, plot_tracker: str = DEFAULTS["plot_tracker"],
          spp_study=None, skip_study: bool = False, quiet: bool = False) -> int:
    """Run the study and write its tables and figure into ``out`` (``stripebench translucency``).

    Parameters
    ----------
    out : path
        Output folder (created).
    objects, materials : list of str
        The objects and materials rendered.
    angles : int
        Mirror angles per object.
    size : int
        Image width, px, a multiple of 16 (the height is 15/16 of it).
    spp : int
        Laser-pass samples per pixel.
    seed : int
        Seed of the renders and the noise.
    trackers : sequence of str or :class:`bench.config.TrackerSpec`, optional
        Plain tracker names (default: every sub-pixel tracker).
    plot_tracker : str
        Tracker of the bias panel (the first selected sub-pixel tracker if it is not selected).
    spp_study : list of int, optional
        Also measure the render noise against these spp on the first object, every material.
    skip_study : bool
        With ``spp_study``: only the render-noise study.
    quiet : bool
        No progress bars.

    Returns
    -------
    int
        0. Every bad value raises :class:`bench.config.ConfigError` before any work.
    """
    from bench.config import ConfigError
    from bench.config.options import plain_tracker_names

    if skip_study and not spp_study:
        raise ConfigError("--skip-study needs --spp-study")
    names = plain_tracker_names(trackers) if trackers else None
    if not _subpixel_trackers(names):
        raise ConfigError("--trackers: none of the selected trackers is a sub-pixel tracker")
    plot_tracker = plot_tracker if names is None or plot_tracker in names else _subpixel_trackers(names)[0].name
    width = size
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if not skip_study:
        records = run_study(objects, materials, n_angles=angles, width=width, height=width * 15 // 16,
                            spp=spp, seed=seed, tracker_names=names, progress=not quiet)
        summary = summarise(records, width)
        write_csv(summary, out / "translucency.csv")
        print(f"wrote {out / 'translucency.csv'} ({len(summary)} lines)")
        plot(summary, out / "translucency.png", plot_tracker)
        print(f"wrote {out / 'translucency.png'}")
        print(f"{'object':<7}{'material':<9}{'incid.':>8}{'FWHM px':>9}{'10-90':>7}{'peak':>6}  {plot_tracker} "
          f"depth error mm: mean (sd), median [IQR]")
        for r in summary:
            if r["tracker"] == plot_tracker:
                print(f"{r['object']:<7}{r['material']:<9}{r['incidence_lo_deg']:>4.0f}-{r['incidence_hi_deg']:<3.0f}"
                      f"{r['fwhm_px']:>9.2f}{r['width1090_px']:>7.2f}{r['peak_rel']:>6.2f}  {r['bias_mm']:+.3f} "
                      f"({r['spread_mm']:.3f}), {r['median_mm']:+.3f} [{r['iqr_mm']:.3f}] n={r['rows']}")
    if spp_study:
        noise = []
        for m in materials:
            noise += render_noise(objects[0], m, spp_study, width=width, height=width * 15 // 16,
                                  seed=seed, tracker=plot_tracker)
        write_csv(noise, out / "render_noise.csv", NOISE_FIELDS)
        print(f"wrote {out / 'render_noise.csv'}")
        for r in noise:
            print(f"{r['object']} {r['material']:<7} spp {r['spp']:>4}: render noise {r['mc_noise_px']:.4f} px "
                  f"(robust {r['mc_noise_mad_px']:.4f}), sensor noise {r['sensor_noise_px']:.4f} px "
                  f"(robust {r['sensor_noise_mad_px']:.4f}), {r['s_per_frame']:.2f} s/frame "
                  f"({r['cpu_s_per_frame']:.2f} CPU s)")
    return 0
