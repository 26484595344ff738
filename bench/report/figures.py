"""Figures of a run (matplotlib with the Agg backend; pyvista off-screen for 3-D).

Every function takes arrays or tables and a path and writes one PNG.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bench.evaluate.outcomes import WITHIN_MM, within
from bench.report.palette import TRACKER_COLOURS, tracker_colour  # noqa: F401  (the one palette)

__all__ = ["fig_tracking", "fig_samples", "fig_bars", "fig_curves", "fig_gallery", "fig_shapes", "tracker_colour",
           "clip_for_plot", "TRACKER_COLOURS", "SAMPLE_CAP_MM", "FALSE_COLOUR", "fig_pr"]

# One colour per tracker label, the same in every run and figure.
_MARKERS = ["o", "s", "D", "^", "v", "<", ">", "P", "X", "*", "h", "p"]
SAMPLE_CAP_MM = 1000.0  # Fig. 10's axis ends here; larger errors are drawn at the edge, marked and counted


def _marker(label: str) -> str:
    import hashlib

    return _MARKERS[int(hashlib.sha1(label.encode()).hexdigest(), 16) % len(_MARKERS)]


PNG = {"pil_kwargs": {"compress_level": 1}}
"""``savefig`` options of the report's PNGs: zlib level 1 (about 2x faster to write than matplotlib's
default here, and the files came out smaller)."""


def save(fig, path, dpi: int) -> Path:
    """Write ``fig`` as the PNG ``path`` and close it; an OS error (a full disk) names the file."""
    plt = _plt()
    try:
        fig.savefig(path, dpi=dpi, **PNG)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    finally:
        plt.close(fig)
    return Path(path)


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _draw_tracks(ax, tracks: dict, truth_columns, step: int = 4) -> None:
    """Each tracker's detections as markers on every ``step``-th row (offset per
    tracker so markers do not hide each other), the truth as a thin dashed line."""
    rows = np.arange(len(truth_columns))
    ax.plot(truth_columns, rows, color="#ff2020", lw=1.0, ls=(0, (3, 2)), label="ground truth", zorder=3)
    for k, (name, cols) in enumerate(sorted(tracks.items())):
        sel = rows[(rows + k) % step == 0]
        ax.plot(np.asarray(cols)[sel], sel, ls="none", marker=_marker(name), ms=3.5, mew=0.8, mfc="none",
                color=tracker_colour(name), label=name, zorder=4)


def fig_tracking(image, cost_field, tracks: dict, truth_columns, path, title: str = "") -> Path:
    """The paper's Fig. 7: (a) the frame, (b) the DP accumulated cost field,
    (c) each tracker's detections (markers) over the frame with the ground truth."""
    plt = _plt()
    fig, ax = plt.subplots(1, 3, figsize=(15, 5.0), constrained_layout=True)
    ax[0].imshow(image, cmap="gray", vmin=0, vmax=255)
    ax[0].set_title("(a) frame (8-bit)")
    if cost_field is not None:
        im = ax[1].imshow(cost_field, cmap="jet")
        fig.colorbar(im, ax=ax[1], shrink=0.8, label="accumulated cost")
    else:  # a run saved before the cost field was (figdata format 3): the report does not recompute it
        ax[1].text(0.5, 0.5, "not saved by this run\n(rerun it to draw the cost field)", ha="center", va="center",
                   transform=ax[1].transAxes)
    ax[1].set_title("(b) DP accumulated cost (4-conn.)")
    ax[2].imshow(image, cmap="gray", vmin=0, vmax=255)
    _draw_tracks(ax[2], tracks, truth_columns)
    ax[2].legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=7, framealpha=0.8)
    ax[2].set_title("(c) detections (markers, every 4th row)")
    for a in ax:
        a.set_xlabel("column (px)")
        a.set_ylabel("row (px)")
    if title:
        fig.suptitle(title)
    return save(fig, path, 90)


#: The colour of false reports (a column on a row with no stripe: a false 3-D point) in every figure.
FALSE_COLOUR = "#ff00ff"


def fig_gallery(image, truth_columns, tracks: dict, path, title: str = "") -> Path:
    """One failure-gallery frame: the image with the truth and each tracker's
    detections as markers, large enough to read at report size; every report on a
    row with no stripe (NaN truth: a false 3-D point) in :data:`FALSE_COLOUR`, with
    the tracker's marker shape."""
    plt = _plt()
    H, W = image.shape
    fig, ax = plt.subplots(figsize=(9.0, 9.0 * H / W * 0.9))
    fig.subplots_adjust(left=0.08, right=0.80, bottom=0.09, top=0.94)  # fixed: the legend sits right of it
    ax.imshow(image, cmap="gray", vmin=0, vmax=max(int(np.max(image)), 1))
    _draw_tracks(ax, tracks, truth_columns)
    none = np.isnan(np.asarray(truth_columns, dtype=np.float64))
    first = True
    for name, cols in sorted(tracks.items()):
        c = np.asarray(cols, dtype=np.float64)
        rows = np.flatnonzero(none & ~np.isnan(c))
        if rows.size:
            ax.plot(c[rows], rows, ls="none", marker=_marker(name), ms=3.0, mew=0.7, mfc="none", color=FALSE_COLOUR,
                    label="false reports (no stripe in the row)" if first else None, zorder=5)
            first = False
    ax.set_xlim(-0.5, W - 0.5)
    ax.set_ylim(H - 0.5, -0.5)
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8, framealpha=0.8)
    ax.set_xlabel("column (px)")
    ax.set_ylabel("row (px)")
    ax.set_title(title, fontsize=9)
    return save(fig, path, 80)


def clip_for_plot(errors, cap: float = SAMPLE_CAP_MM):
    """Errors as drawn in Fig. 10: values beyond ``±cap`` are put at the edge.

    Returns
    -------
    y : ndarray
        The value drawn (NaN stays NaN: no value at that sample).
    clipped : ndarray of bool
        True where ``|error| > cap``.
    missing : ndarray of bool
        True where there is no value.

    Examples
    --------
    >>> y, c, m = clip_for_plot([1.0, -2500.0, np.nan], cap=1000.0)
    >>> y.tolist(), c.tolist(), m.tolist()
    ([1.0, -1000.0, nan], [False, True, False], [False, False, True])
    """
    e = np.asarray(errors, dtype=np.float64)
    missing = np.isnan(e)
    clipped = ~missing & (np.abs(e) > cap)
    y = np.where(clipped, np.sign(e) * cap, e)
    return y, clipped, missing


def fig_samples(samples, dp: str, baseline, path, title: str = "", stat=None, robust: dict | None = None,
                within_mm: float = WITHIN_MM, undetectable=None, readings: dict | None = None) -> Path:
    """The paper's Fig. 10 with every sample shown: depth error (mm) of each sample
    point with DP (green diamonds) and without (black circles), the ±5 mm band.

    The axis is linear within ±10 mm and logarithmic beyond (symlog) up to
    :data:`SAMPLE_CAP_MM`; errors beyond are drawn at the edge as triangles and
    counted in the legend; samples with no value (nothing restored there) are
    drawn as crosses on the zero line and counted.

    Parameters
    ----------
    samples : pandas.DataFrame
        The experiment's sample rows (``error_mm_<label>`` columns, mm).
    dp : str
        The DP label.
    baseline : str or sequence of str
        The label(s) without DP: one panel each, side by side (e.g. two readings of the paper's method).
    stat : dict, or dict of baseline -> dict, optional
        The RMSE ratio entry of each pair (a single dict for a single baseline), shown in the title.
    robust : dict, optional
        label -> its :func:`bench.evaluate.stats.robust_summary` figures, shown in the title.
    undetectable : array_like of bool, shape (n_samples,), optional
        Samples where the threshold detects no stripe: a baseline's circles there are drawn filled
        and counted (the paper: "those black points with big errors are points with laser light
        undetectable").
    readings : dict, optional
        baseline -> a short description shown in its panel's title.
    """
    plt = _plt()
    bases = [baseline] if isinstance(baseline, str) else list(baseline)
    stats = {baseline: stat} if isinstance(baseline, str) else dict(stat or {})
    fig, axes = plt.subplots(1, len(bases), figsize=(9.0 if len(bases) == 1 else 7.0 * len(bases), 4.8),
                             constrained_layout=True, sharey=True, squeeze=False)
    x = np.arange(len(samples))
    und = None if undetectable is None else np.asarray(undetectable, bool)
    for ax, base in zip(axes[0], bases):
        ax.axhspan(-within_mm, within_mm, color="#cfe8cf", alpha=0.7, label=f"±{within_mm:g} mm")
        ax.axhline(0, color="0.3", lw=0.8)
        for name, style in ((base, dict(marker="o", mfc="none", mec="black", ms=5, color="black")),
                            (dp, dict(marker="D", color="#2ca02c", ms=4))):
            y, clipped, missing = clip_for_plot(samples[f"error_mm_{name}"].to_numpy(float))
            who = "without DP" if name == base else "with DP"
            ax.plot(x[~clipped], y[~clipped], ls="none", label=f"{who} ({name})", **style)
            if name == base and und is not None and (und & ~missing).any():
                sel = und & ~missing
                far = sel & ~within(samples[f"error_mm_{name}"].to_numpy(float), within_mm)
                ax.plot(x[sel], y[sel], ls="none", marker="o", ms=5, color="black",
                        label=f"{name} where the threshold detects no stripe: {int(sel.sum())}, "
                              f"{int(far.sum())} outside ±{within_mm:g} mm")
            if clipped.any():
                ax.plot(x[clipped], y[clipped], ls="none", marker="^" if name == dp else "v", ms=7,
                        color=style.get("color", "black"), mfc="none" if name == base else None,
                        label=f"{name}: {int(clipped.sum())} beyond ±{SAMPLE_CAP_MM:g} mm (at the edge)")
            if missing.any():
                ax.plot(x[missing], np.zeros(int(missing.sum())), ls="none", marker="x", ms=6,
                        color=style.get("color", "black"), label=f"{name}: {int(missing.sum())} with no value")
        ax.set_yscale("symlog", linthresh=10.0, linscale=1.0)
        ax.set_ylim(-SAMPLE_CAP_MM * 1.3, SAMPLE_CAP_MM * 1.3)
        ax.set_xlabel("sample")
        lines = [title] if title else []
        if readings and readings.get(base):
            lines.append(f"without DP: {base} ({readings[base]})")
        if robust:
            parts = []
            for name in (dp, base):
                r = robust.get(name)
                if r is not None and r["n"]:
                    parts.append(f"{name}: {100 * r['within']:.0f} % within ±{within_mm:g} mm "
                                 f"[{100 * r['within_low']:.0f}, {100 * r['within_high']:.0f}], median "
                                 f"{r['median_abs_mm']:.2g} mm, {r['n_gross']} gross")
            lines += parts if len(bases) > 1 else ["; ".join(parts)]
        st = stats.get(base)
        if st is not None and np.isfinite(st.get("value", np.nan)):
            pairs = "" if st.get("n", 0) == st.get("n_samples", st.get("n", 0)) else f", {st['n']} pairs"
            lines.append(f"1 - RMSE_DP/RMSE_noDP = {100 * st['value']:.0f} % "
                         f"[{100 * st['low']:.0f}, {100 * st['high']:.0f}] (95 % CI{pairs}); paper: 30 %")
        ax.set_title("\n".join(lines), fontsize=8)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0) if len(bases) == 1 else (0.0, -0.13), fontsize=7,
                  ncol=1 if len(bases) == 1 else 2)
    axes[0][0].set_ylabel("depth error (mm), symlog beyond ±10")
    return save(fig, path, 90)


def fig_bars(metrics, path, metric: str = "hit_rate", title: str = "", region: str = "object") -> Path:
    """One bar per tracker and experiment of a metric of one region (linear axis): ``object`` for the stripe
    half on the object (hit rate, coverage), ``all`` for figures that price false reports too (F1, the
    false-report rate: every row, :data:`bench.evaluate.tables.OBJECT_BLIND`).

    Experiments are identified by their key (two experiments of one scene and
    material, e.g. a lux sweep, are two groups of bars)."""
    plt = _plt()
    m = metrics[metrics["region"] == region]
    exps = list(dict.fromkeys(m["experiment"]))
    names = sorted(m["tracker"].unique())
    fig, ax = plt.subplots(figsize=(max(8.0, 0.9 * len(exps) + 3), 4.0), constrained_layout=True)
    width = 0.8 / max(len(names), 1)
    x = np.arange(len(exps))
    table = (m.pivot_table(index="experiment", columns="tracker", values=metric, sort=False, dropna=False)
             .reindex(index=exps, columns=names))
    for k, name in enumerate(names):
        ax.bar(x + k * width, table[name].to_numpy(float), width, color=tracker_colour(name), label=name)
    ax.set_xticks(x + 0.4 - width / 2, exps, rotation=30, ha="right", fontsize=8)
    where = "object rows" if region == "object" else "every row"
    ax.set_ylabel(f"{metric} ({where})")
    if metric in ("hit_rate", "coverage", "f1", "precision", "recall", "false_report_rate"):
        ax.set_ylim(0, 1.02)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    ax.set_title(title or f"{metric} on the {'object' if region == 'object' else 'frame'}, per experiment")
    return save(fig, path, 90)


def fig_curves(table, key: str, path, metric: str = "hit_rate", title: str = "", mark=None) -> Path:
    """A metric against one swept setting, one line per tracker.

    ``table`` has columns ``key``, ``tracker``, ``metric`` and optionally
    ``low``/``high`` (an interval drawn as a band); ``mark`` is a value of ``key``
    to mark with a vertical line (e.g. the paper's 400 lux)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 4.0), constrained_layout=True)
    for name, g in table.groupby("tracker", sort=True):
        g = g.sort_values(key)
        ax.plot(g[key], g[metric], marker=_marker(name), color=tracker_colour(name), label=name, ms=4)
        if {"low", "high"} <= set(g.columns):
            ax.fill_between(g[key], g["low"], g["high"], color=tracker_colour(name), alpha=0.15)
    if mark is not None:
        ax.axvline(mark, color="0.4", ls=":", lw=1)
    ax.set_xlabel(key)
    ax.set_ylabel(metric)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    ax.set_title(title, fontsize=9)
    return save(fig, path, 90)


def fig_pr(curves: dict, path, title: str = "") -> Path:
    """One condition's precision-recall curves over rows: per tracker, precision against recall as its
    reports are taken in order of its score (:func:`bench.evaluate.ranking.pr_curve`), its operating
    point (every report) as a dot, AP in the legend; a tracker whose reports all score alike is its dot."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for name in sorted(curves, key=lambda n: -np.nan_to_num(curves[n]["ap"], nan=-1.0)):
        c = curves[name]
        col = tracker_colour(name)
        if not c["constant"] and len(c["recall"]):
            ax.step(np.r_[0.0, c["recall"]], np.r_[c["precision"][0], c["precision"]], where="post", color=col,
                    lw=1.0)
        r, p = c["point"]
        ap = "–" if not np.isfinite(c["ap"]) else f"{c['ap']:.2f}"
        ax.plot([r], [p], marker=_marker(name), ms=5, color=col, ls="none",
                label=f"{name} (AP {ap}{', one point' if c['constant'] else ''})")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, 1.02)
    ax.set_xlabel("recall (stripe rows hit)")
    ax.set_ylabel("precision (reports that are hits)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc="lower left", ncol=2, framealpha=0.8)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return save(fig, path, 90)


def _quads(points):
    """PolyData faces for the (F, H) grid of points where all 4 corners exist."""
    F, H, _ = points.shape
    ok = np.isfinite(points).all(axis=-1)
    idx = np.arange(F * H).reshape(F, H)
    q = ok[:-1, :-1] & ok[1:, :-1] & ok[:-1, 1:] & ok[1:, 1:]
    f, r = np.nonzero(q)
    faces = np.stack([np.full(f.size, 4), idx[f, r], idx[f + 1, r], idx[f + 1, r + 1], idx[f, r + 1]], axis=1)
    return faces.ravel()


def _quiet_vtk() -> None:
    """No VTK warnings on the terminal (e.g. "bad X server connection" off-screen)."""
    try:
        from vtkmodules.vtkCommonCore import vtkObject

        vtkObject.GlobalWarningDisplayOff()
    except Exception:  # pragma: no cover - VTK layout differs
        pass


ERROR_CLIM_MM = 10.0  # the error maps of Fig. 8/9 saturate at ±this


def fig_shapes(surfaces: dict, path, title: str = "", camera_cm=(0.0, 0.0, 0.0), errors_mm: dict | None = None,
               columns: int = 3, false_points: dict | None = None) -> Path:
    """Restored 3-D surfaces, seen from the rig's side, in a grid of panels.

    ``surfaces`` maps a label to an (F, H, 3) grid of points (cm, NaN where
    missing); quads with a missing corner are left out. The first surface (the
    ground truth) sets the view and is coloured by depth R (cm). Every other
    surface is coloured by its depth error (mm) from ``errors_mm[label]`` (F, H),
    on a diverging map saturating at ±:data:`ERROR_CLIM_MM` (or by R when no
    error is given). ``columns`` panels per row, 400 x 360 px each. ``false_points[label]``
    (N, 3) cm are the tracker's false 3-D points (reports on rows with no stripe), drawn in
    :data:`FALSE_COLOUR` and counted in the panel's title.
    """
    import pyvista as pv

    _quiet_vtk()
    pv.OFF_SCREEN = True
    labels = list(surfaces)
    grids = [np.asarray(surfaces[k], float) for k in labels]
    ref = grids[0][np.isfinite(grids[0]).all(-1)]
    if ref.size == 0:
        raise ValueError("no surface points to draw")
    r_ref = np.hypot(ref[:, 0], ref[:, 1])
    clim = (float(np.percentile(r_ref, 1)), float(np.percentile(r_ref, 99)))
    centre = 0.5 * (ref.min(axis=0) + ref.max(axis=0))
    extent = float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0)))
    view = np.asarray(camera_cm, float) - centre
    view[2] = 0.0
    view /= np.linalg.norm(view)
    eye = centre + 2.6 * extent * view + np.array([0.0, 0.0, 0.25 * extent])
    ncol = min(columns, len(labels))
    nrow = -(-len(labels) // ncol)
    plotter = pv.Plotter(off_screen=True, shape=(nrow, ncol), window_size=(400 * ncol, 360 * nrow), border=False)
    errors_mm = errors_mm or {}
    for k, (label, g) in enumerate(zip(labels, grids)):
        plotter.subplot(k // ncol, k % ncol)
        pts = np.nan_to_num(g.reshape(-1, 3))
        faces = _quads(g)
        err = errors_mm.get(label)
        if faces.size:
            mesh = pv.PolyData(pts, faces=faces)
            if err is not None:
                mesh["error (mm)"] = np.nan_to_num(np.asarray(err, float).reshape(-1))
                plotter.add_mesh(mesh, scalars="error (mm)", cmap="RdBu_r", clim=(-ERROR_CLIM_MM, ERROR_CLIM_MM),
                                 show_scalar_bar=True,
                                 scalar_bar_args={"title": f"{label} (mm)", "vertical": True,
                                                  "position_x": 0.80, "n_labels": 5, "fmt": "%.0f"})
            else:
                mesh["R (cm)"] = np.hypot(pts[:, 0], pts[:, 1])
                plotter.add_mesh(mesh, scalars="R (cm)", cmap="jet", clim=clim, show_scalar_bar=True,
                                 scalar_bar_args={"title": "R (cm)", "vertical": True, "position_x": 0.84})
        fp = np.asarray((false_points or {}).get(label, np.zeros((0, 3))), float).reshape(-1, 3)
        fp = fp[np.isfinite(fp).all(axis=1)]
        if fp.size:
            plotter.add_mesh(pv.PolyData(fp), color=FALSE_COLOUR, point_size=4.0, render_points_as_spheres=True)
        text = label if err is None else f"{label}: depth error"
        plotter.add_text(text + (f"; {len(fp)} false points" if fp.size else ""), font_size=11)
        plotter.camera_position = [tuple(eye), tuple(centre), (0.0, 0.0, 1.0)]
        plotter.reset_camera_clipping_range()
    try:
        plotter.screenshot(str(path))
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    finally:
        plotter.close()
    return Path(path)
