"""The run report: figures from saved results and one self-contained HTML page.

``stripebench report RUN`` calls :func:`build_report` on a finished run folder;
it needs only the saved files (no rendering).
"""

from __future__ import annotations

import base64
import html
import json
import sys
from pathlib import Path

import numpy as np

from .runfolder import load_run
from .runio import atomic_write_text
from .scan import ScanResult

__all__ = ["build_report", "make_figures"]


def _restored_points(arrays, name: str | None, rig) -> np.ndarray:
    """(F, H, 3) points of the ground truth (``name=None``) or of a tracker's
    restored surface (missing rows filled from neighbours)."""
    from .restore import fill_depth_map
    from .triangulation import cylindrical_to_cartesian, depth_cm

    scan = ScanResult.from_arrays("", arrays)
    F, H = scan.truth_columns.shape
    if name is None:
        pts = scan.truth_points_cm.copy()
        pts[~scan.on_object] = np.nan
        return pts
    r, _ = fill_depth_map(depth_cm(scan.columns[name], rig))
    rows = np.broadcast_to(np.arange(H, dtype=float), (F, H))
    f = rig.focal_mm / 10.0
    z = (rig.pz_mm(rows) / 10.0) * (rig.d_m_cm + r * np.cos(np.radians(rig.zeta_deg))) / f
    phi = 2.0 * scan.angles[:, None] - rig.zeta_deg
    pts = cylindrical_to_cartesian(r, phi, z)
    # show the object: the cells whose true point is on the object (and a margin of one)
    on = scan.on_object.copy()
    on[1:] |= scan.on_object[:-1]
    on[:-1] |= scan.on_object[1:]
    on[:, 1:] |= scan.on_object[:, :-1]
    on[:, :-1] |= scan.on_object[:, 1:]
    pts[~on] = np.nan
    return pts


def make_figures(run_dir, *, quiet: bool = False, data: dict | None = None) -> dict[str, list[Path]]:
    """Write every figure of a run into ``run_dir/figures``; returns them by
    section. ``data`` is the run's :func:`~bench.experiment.load_run` if the
    caller already has it."""
    import scenes

    from . import figures

    run_dir = Path(run_dir)
    data = load_run(run_dir, say=_warn) if data is None else data
    summary, metrics, samples = data["summary"], data["metrics"], data["samples"]
    cfg = summary["config"]
    figdir = run_dir / "figures"
    figdir.mkdir(exist_ok=True)
    out: dict[str, list[Path]] = {"tracking": [], "samples": [], "bars": [], "shapes": []}
    fd = data["figdata"]
    if fd is not None:
        from trackers.dp import accumulated_cost

        cols = {str(n): fd[f"columns/{n}"] for n in fd["trackers"]}
        p = figures.fig_tracking(fd["image"], accumulated_cost(fd["image"], connectivity=4), cols,
                                 fd["truth_columns"], figdir / "fig7_tracking.png",
                                 title=f"{fd['experiment']} at mirror angle {float(fd['mirror_angle_deg']):.2f} deg")
        out["tracking"].append(p)
    stats = {(s["group"], s["dp"], s["baseline"], s["statistic"]): s for s in summary["improvement"]}
    dp0 = cfg["dp"][0] if cfg["dp"] else None
    base0 = cfg["baselines"][0] if cfg["baselines"] else None
    if dp0 and base0 and len(samples):
        for key, g in samples.groupby("experiment", sort=False):
            st = stats.get((key, dp0, base0, "rmse"))
            out["samples"].append(figures.fig_samples(g.reset_index(drop=True), dp0, base0,
                                                      figdir / f"fig10_{key}.png", title=f"{key}: {len(g)} samples",
                                                      stat=st))
    for scene in dict.fromkeys(metrics["scene"]):
        out["bars"].append(figures.fig_bars(metrics, scene, figdir / f"bars_{scene}.png"))
    # 3-D restored shapes: the first experiment of each scene
    done = set()
    scan_keys = [sc.get("experiment") for sc in summary["scans"]]  # the experiments' keys, in config order
    for i, exp in enumerate(cfg["experiments"]):
        if exp["scene"] in done:
            continue
        done.add(exp["scene"])
        key = scan_keys[i] if i < len(scan_keys) else None
        if key not in data["scans"]:
            continue
        arrays = data["scans"][key]
        rig = scenes.make(exp["scene"], width=int(cfg["render"].get("width", 512)),
                          height=int(cfg["render"].get("height", 480))).rig
        names = [str(n) for n in arrays["trackers"]]
        surf = {"ground truth": _restored_points(arrays, None, rig)}
        for n in names:
            surf[n] = _restored_points(arrays, n, rig)
        try:
            out["shapes"].append(figures.fig_shapes(surf, figdir / f"shape_{key}.png", title=key))
        except Exception as exc:  # a missing OpenGL must not lose the rest of the report
            if not quiet:
                print(f"stripebench: 3-D figure of {key} skipped: {type(exc).__name__}: {exc}", file=sys.stderr)
    return out


def _warn(msg: str) -> None:
    print(msg, file=sys.stderr)


def _img(path: Path) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{html.escape(path.stem)}" style="max-width:100%">'


def _fmt(v, pct=False):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "–"
    return f"{100 * v:.0f} %" if pct else f"{v:.3g}"


def _improvement_tables(summary) -> str:
    """Experiments x (DP, baseline) pairs, one table per statistic."""
    imp = summary["improvement"]
    pairs = list(dict.fromkeys((i["dp"], i["baseline"]) for i in imp))
    groups = list(dict.fromkeys(i["group"] for i in imp))
    by = {(i["group"], i["dp"], i["baseline"], i["statistic"]): i for i in imp}
    head = "".join(f"<th>{html.escape(d)} vs {html.escape(b)}</th>" for d, b in pairs)
    out = []
    head_stat = by.get(("all", pairs[0][0], pairs[0][1], "rmse")) if pairs else None
    if head_stat is not None:
        out.append(f"<p><b>Headline</b>: over all {head_stat['n']} sample points, {pairs[0][0]} is "
                   f"{_fmt(head_stat['value'], True)} more precise than {pairs[0][1]} by RMSE "
                   f"(95 % CI [{_fmt(head_stat['low'], True)}, {_fmt(head_stat['high'], True)}]); "
                   f"the paper reports about {int(100 * summary['paper_improvement'])} %.</p>")
    for stat, title in (("rmse", "RMSE"), ("mae", "MAE"), ("std", "standard deviation")):
        rows = []
        for g in groups:
            cells = []
            for d, b in pairs:
                i = by.get((g, d, b, stat))
                cells.append("<td>–</td>" if i is None else
                             f"<td><b>{_fmt(i['value'], True)}</b> [{_fmt(i['low'], True)}, {_fmt(i['high'], True)}]"
                             f" <small>n={i['n']}</small></td>")
            rows.append(f"<tr><td>{html.escape(g)}</td>{''.join(cells)}</tr>")
        out.append(f"<h3>by {title}</h3><table><tr><th>experiment</th>{head}</tr>{''.join(rows)}</table>")
    return "".join(out)


def _coverage_table(metrics) -> str:
    m = metrics[metrics["region"] == "object"]
    if m.empty:
        return ""
    cov = m.pivot_table(index="experiment", columns="tracker", values="coverage", sort=False)
    rmse = m.pivot_table(index="experiment", columns="tracker", values="depth_rmse_mm", sort=False)
    fmt = {"float_format": lambda v: f"{v:.3g}", "na_rep": "–", "border": 0}
    return ("<h2>Coverage and depth RMSE on the object</h2><p>Coverage: rows with a detection among the object's "
            "lit rows. Depth RMSE (mm) over the detected rows (before any filling).</p><h3>coverage</h3>"
            + cov.to_html(**fmt) + "<h3>depth RMSE (mm)</h3>" + rmse.to_html(**fmt))


def build_report(run_dir, *, quiet: bool = False) -> Path:
    """Write ``figures/*.png`` and ``report.html`` for a finished run."""
    run_dir = Path(run_dir)
    data = load_run(run_dir, say=_warn)
    figs = make_figures(run_dir, quiet=quiet, data=data)
    s, metrics = data["summary"], data["metrics"]
    cfg = s["config"]
    parts = [f"<h1>stripebench run <code>{html.escape(run_dir.name)}</code></h1>",
             f"<p>Configuration <code>{html.escape(cfg['name'])}</code> ({html.escape(s.get('config_source', ''))}), "
             f"seed {s['seed']}, git {html.escape(s['git_revision'])}, Mitsuba variant(s) "
             f"{html.escape(', '.join(s['variants']))}, wall time {s['wall_s']:.0f} s. "
             f"Versions: {html.escape(', '.join(f'{k} {v}' for k, v in s['versions'].items()))}.</p>"]
    parts.append("<h2>Precision improvement (the paper's Fig. 10 statistic)</h2>"
                 "<p><code>1 - S_DP / S_noDP</code> over the sample points' depth errors on the restored surfaces, "
                 "S = RMSE, MAE or standard deviation, with a paired bootstrap 95 % confidence interval "
                 f"({cfg['n_boot']} resamples). The paper reports about {int(100 * s['paper_improvement'])} %. "
                 "Negative values mean the method without DP was more precise.</p>")
    parts.append(_improvement_tables(s))
    parts.append(_coverage_table(metrics))
    if figs["samples"]:
        parts.append("<h2>Sample errors (Fig. 10)</h2>" + "".join(_img(p) for p in figs["samples"]))
    if figs["tracking"]:
        parts.append("<h2>Tracking one frame (Fig. 7)</h2>" + "".join(_img(p) for p in figs["tracking"]))
    if figs["shapes"]:
        parts.append("<h2>Restored shapes (Fig. 8, 9)</h2><p>Ground truth and each tracker's restored surface "
                     "(rows it missed filled from their neighbours), coloured by depth R.</p>"
                     + "".join(_img(p) for p in figs["shapes"]))
    if figs["bars"]:
        parts.append("<h2>Accuracy and coverage per material</h2>" + "".join(_img(p) for p in figs["bars"]))
    cols = ["experiment", "tracker", "region", "px_mae", "px_rmse", "px_p95", "depth_mae_mm", "depth_rmse_mm",
            "depth_p95_mm", "coverage", "outlier_rate", "false_detections", "filled_fraction", "ms_per_frame",
            "failed_frames"]
    table = metrics[cols].to_html(index=False, float_format=lambda v: f"{v:.3g}", na_rep="–", border=0)
    parts.append("<h2>Metrics</h2><p>Pixel errors against the ground-truth column of each lit row; depth errors "
                 "(mm) of R from eq. (3); coverage = detected / lit rows; outliers = |error| &gt; 3 px among "
                 "detected lit rows; false detections = detected / unlit rows; region <i>object</i> keeps the "
                 "rows whose true point lies on the object.</p>" + table)
    fails = [(sc["experiment"], n, c, sc["failure_messages"][n]) for sc in s["scans"]
             for n, c in sc["failures"].items() if c]
    if fails:
        parts.append("<h2>Tracker failures</h2><ul>" + "".join(
            f"<li><b>{html.escape(n)}</b> on {html.escape(e)}: {c} frame(s) failed: "
            f"{html.escape('; '.join(m))}</li>" for e, n, c, m in fails) + "</ul>")
    parts.append("<h2>Configuration</h2><pre>" + html.escape(json.dumps(cfg, indent=2)) + "</pre>")
    page = ("<!doctype html><html><head><meta charset='utf-8'><title>stripebench report</title><style>"
            "body{font-family:system-ui,sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}"
            "table{border-collapse:collapse;font-size:12px;margin:1em 0}td,th{border:1px solid #ccc;padding:2px 6px;"
            "text-align:right}th{background:#f0f0f0}code{background:#f4f4f4}</style></head><body>"
            + "\n".join(parts) + "</body></html>")
    path = run_dir / "report.html"
    atomic_write_text(path, page)
    return path
