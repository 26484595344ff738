"""Figures of a run (matplotlib with the Agg backend; pyvista off-screen for 3-D).

Every function takes arrays or tables and a path and writes one PNG.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["fig_tracking", "fig_samples", "fig_bars", "fig_shapes", "TRACKER_COLOURS"]

TRACKER_COLOURS = {"threshold": "#ffd700", "centroid": "#1f77b4", "dp4": "#2ca02c", "dp8": "#17becf"}
_FALLBACK = ["#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#ff7f0e"]


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _colour(name: str, k: int) -> str:
    return TRACKER_COLOURS.get(name, _FALLBACK[k % len(_FALLBACK)])


def fig_tracking(image, cost_field, tracks: dict, truth_columns, path, title: str = "") -> Path:
    """The paper's Fig. 7: (a) the frame, (b) the DP accumulated cost field,
    (c) the tracks over the frame with the ground truth."""
    plt = _plt()
    H, W = image.shape
    fig, ax = plt.subplots(1, 3, figsize=(13.5, 4.6), constrained_layout=True)
    ax[0].imshow(image, cmap="gray", vmin=0, vmax=255)
    ax[0].set_title("(a) frame (8-bit)")
    im = ax[1].imshow(cost_field, cmap="jet")
    fig.colorbar(im, ax=ax[1], shrink=0.8, label="accumulated cost")
    ax[1].set_title("(b) DP accumulated cost (4-conn.)")
    ax[2].imshow(image, cmap="gray", vmin=0, vmax=255)
    rows = np.arange(H)
    for k, (name, cols) in enumerate(sorted(tracks.items())):
        ax[2].plot(cols, rows, color=_colour(name, k), lw=1.2, label=name)
    ax[2].plot(truth_columns, rows, color="#ff2020", lw=1.0, ls=(0, (3, 3)), label="ground truth")
    ax[2].legend(loc="lower right", fontsize=7, framealpha=0.8)
    ax[2].set_title("(c) tracks")
    for a in ax:
        a.set_xlabel("column (px)")
        a.set_ylabel("row (px)")
    if title:
        fig.suptitle(title)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def fig_samples(samples, dp: str, baseline: str, path, title: str = "", stat: dict | None = None) -> Path:
    """The paper's Fig. 10: depth error (mm) of each sample point, with DP
    (green diamonds) and without (black circles), the +-5 mm band and zero."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8.0, 4.2), constrained_layout=True)
    x = np.arange(len(samples))
    ax.axhspan(-5, 5, color="#cfe8cf", alpha=0.6, label="±5 mm")
    ax.axhline(0, color="0.3", lw=0.8)
    ax.plot(x, samples[f"error_mm_{baseline}"], "o", mfc="none", mec="black", ms=5, label=f"without DP ({baseline})")
    ax.plot(x, samples[f"error_mm_{dp}"], "D", color="#2ca02c", ms=4, label=f"with DP ({dp})")
    both = np.concatenate([samples[f"error_mm_{dp}"].to_numpy(float), samples[f"error_mm_{baseline}"].to_numpy(float)])
    both = both[np.isfinite(both)]
    lim = max(10.0, float(np.percentile(np.abs(both), 98)) * 1.15) if both.size else 10.0
    ax.set_ylim(-lim, lim)
    ax.set_xlabel("sample")
    ax.set_ylabel("depth error (mm)")
    text = title
    if stat is not None and np.isfinite(stat.get("value", np.nan)):
        text += (f"\nimprovement 1 - RMSE_DP/RMSE_noDP = {100 * stat['value']:.0f} % "
                 f"[{100 * stat['low']:.0f}, {100 * stat['high']:.0f}] (95 % CI); paper: 30 %")
    ax.set_title(text, fontsize=9)
    ax.legend(loc="upper right", fontsize=8)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def fig_bars(metrics, scene: str, path) -> Path:
    """Per material: depth RMSE on the object and coverage, one bar per tracker."""
    plt = _plt()
    m = metrics[(metrics["scene"] == scene)]
    mats = list(dict.fromkeys(m["material"]))
    names = sorted(m["tracker"].unique())
    fig, ax = plt.subplots(1, 2, figsize=(11, 3.8), constrained_layout=True)
    width = 0.8 / max(len(names), 1)
    x = np.arange(len(mats))
    for k, name in enumerate(names):
        obj = m[(m["tracker"] == name) & (m["region"] == "object")].set_index("material").reindex(mats)
        allr = m[(m["tracker"] == name) & (m["region"] == "all")].set_index("material").reindex(mats)
        ax[0].bar(x + k * width, obj["depth_rmse_mm"], width, color=_colour(name, k), label=name)
        ax[1].bar(x + k * width, allr["coverage"], width, color=_colour(name, k), label=name)
    for a, label in zip(ax, ("depth RMSE on the object (mm)", "coverage (lit rows detected)")):
        a.set_xticks(x + 0.4 - width / 2, mats)
        a.set_ylabel(label)
    rmse = m.loc[m["region"] == "object", "depth_rmse_mm"].to_numpy(float)
    if np.any(np.isfinite(rmse) & (rmse > 0)):
        ax[0].set_yscale("log")
    ax[1].set_ylim(0, 1.05)
    ax[1].legend(fontsize=8, loc="lower left")
    fig.suptitle(f"{scene}: accuracy and coverage per material")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Path(path)


def _quads(points):
    """PolyData faces for the (F, H) grid of points where all 4 corners exist."""
    F, H, _ = points.shape
    ok = np.isfinite(points).all(axis=-1)
    idx = np.arange(F * H).reshape(F, H)
    q = ok[:-1, :-1] & ok[1:, :-1] & ok[:-1, 1:] & ok[1:, 1:]
    f, r = np.nonzero(q)
    faces = np.stack([np.full(f.size, 4), idx[f, r], idx[f + 1, r], idx[f + 1, r + 1], idx[f, r + 1]], axis=1)
    return faces.ravel()


def fig_shapes(surfaces: dict, path, title: str = "", camera_cm=(0.0, 0.0, 0.0)) -> Path:
    """Restored 3-D surfaces side by side, coloured by depth R (cm), seen
    from the rig's side. ``surfaces`` maps a label to an (F, H, 3) grid of
    points (cm, NaN where missing); quads with a missing corner are left out.
    The first surface (the ground truth) sets the view and the colour range,
    so a tracker's wrong depths saturate the colour map."""
    import pyvista as pv

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
    plotter = pv.Plotter(off_screen=True, shape=(1, len(labels)), window_size=(300 * len(labels), 340), border=False)
    for k, (label, g) in enumerate(zip(labels, grids)):
        plotter.subplot(0, k)
        pts = np.nan_to_num(g.reshape(-1, 3))
        faces = _quads(g)
        if faces.size:
            mesh = pv.PolyData(pts, faces=faces)
            mesh["R (cm)"] = np.hypot(pts[:, 0], pts[:, 1])
            plotter.add_mesh(mesh, scalars="R (cm)", cmap="jet", clim=clim, show_scalar_bar=k == len(labels) - 1,
                             scalar_bar_args={"title": "R (cm)", "vertical": True, "position_x": 0.82})
        plotter.add_text(label, font_size=10)
        plotter.camera_position = [tuple(eye), tuple(centre), (0.0, 0.0, 1.0)]
        plotter.reset_camera_clipping_range()
    plotter.screenshot(str(path))
    plotter.close()
    return Path(path)
