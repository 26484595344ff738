"""Curves of a sweep: metric against each swept key per tracker, and the sweep's report page.

:func:`curve_figure` and :func:`build_report` draw the curves and costs that
:mod:`bench.evaluate.curves` computes (its docstring says how a curve is made),
with matplotlib (Agg).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from bench.report.html import esc, page, png_file
from bench.store.files import atomic_write_text
from bench.report.figures import save, tracker_colour
from bench.evaluate.curves import CURVE_METRICS, PAPER_POINT, _paper_or_default, curves, per_unit_costs, reference_point

__all__ = ["reference_point", "curves", "per_unit_costs", "curve_figure", "build_report", "CURVE_METRICS",
           "PAPER_POINT"]

_LABELS = {"hit_rate": "hit rate (object rows, ±3 px)", "depth_rmse_mm": "depth RMSE on object (mm)",
           "depth_mae_mm": "depth MAE on object (mm)", "within_5mm": "fraction of samples within ±5 mm",
           "coverage": "coverage (object rows)", "outlier_rate": "outlier rate (> 3 px)"}


def _numeric(values) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def curve_figure(curve_records: list[dict], sweep_dict: dict, path, metrics=CURVE_METRICS, title: str = ""):
    """Draw the curves: rows = metrics, columns = experiments x swept keys; writes ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    keys = [k for k in sweep_dict if k != "repeats"]
    exps = list(dict.fromkeys(r["experiment"] for r in curve_records))
    trackers = list(dict.fromkeys(r["tracker"] for r in curve_records))
    cols = [(e, k) for e in exps for k in keys]
    fig, axes = plt.subplots(len(metrics), max(1, len(cols)), figsize=(3.6 * max(1, len(cols)), 2.6 * len(metrics)),
                             squeeze=False, constrained_layout=True)
    ref = reference_point(sweep_dict)
    for ci, (exp, key) in enumerate(cols):
        values = list(sweep_dict[key])
        numeric = _numeric(values)
        xs = values if numeric else list(range(len(values)))
        mark = _paper_or_default(key)
        for mi, m in enumerate(metrics):
            ax = axes[mi, ci]
            for ti, tr in enumerate(trackers):
                pts = {r["value"]: r for r in curve_records
                       if r["experiment"] == exp and r["key"] == key and r["tracker"] == tr and r["metric"] == m}
                y = np.array([pts[v]["mean"] if v in pts else np.nan for v in values], float)
                lo = np.array([pts[v]["low"] if v in pts else np.nan for v in values], float)
                hi = np.array([pts[v]["high"] if v in pts else np.nan for v in values], float)
                ax.plot(xs, y, color=tracker_colour(tr), marker="osv^Dp*h"[ti % 8], ms=4 if ti else 5, mfc="none",
                        ls=("-", "--", "-.", ":")[ti % 4], lw=1.2, label=tr)
                if np.isfinite(lo).any():
                    ax.fill_between(xs, lo, hi, color=tracker_colour(tr), alpha=0.18, lw=0)
            if numeric:
                pos = [v for v in values if v > 0]
                if pos and max(pos) / min(pos) >= 10:
                    if min(values) > 0:
                        ax.set_xscale("log")
                    else:
                        ax.set_xscale("symlog", linthresh=min(pos))
                if mark is not None and min(values) <= mark <= max(values):
                    ax.axvline(mark, color="k", ls="--", lw=0.8)
                    if mi == 0:
                        ax.annotate("paper" if key in ("ambient_lux", "laser_power_mw") else "default",
                                    (mark, 1.0), xycoords=("data", "axes fraction"), fontsize=7,
                                    ha="left", va="top", xytext=(2, -2), textcoords="offset points")
            else:
                ax.set_xticks(xs, [str(v) for v in values], rotation=30, fontsize=7)
            if mi == len(metrics) - 1:
                ax.set_xlabel(key)
            if ci == 0:
                ax.set_ylabel(_LABELS.get(m, m), fontsize=8)
            if mi == 0:
                held = ", ".join(f"{k}={ref[k]:g}" if isinstance(ref[k], float) else f"{k}={ref[k]}"
                                 for k in keys if k != key)
                ax.set_title(f"{exp}\n{held}" if held else exp, fontsize=8)
            ax.grid(alpha=0.3)
            ax.tick_params(labelsize=7)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="outside right upper", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=9)
    return save(fig, path, 110)




def build_report(sweep_dir) -> Path:
    """``figures/sweep.png`` and a self-contained ``report.html`` from a finished sweep folder."""
    sweep_dir = Path(sweep_dir)
    from bench.store.summary import read_summary
    from bench.store.sweepfiles import LAYOUT

    summary = read_summary(sweep_dir / LAYOUT["summary"], kind="sweep")
    sd = summary["sweep"]
    (sweep_dir / "figures").mkdir(exist_ok=True)
    n_rep = sd.get("repeats", 1)
    fig = curve_figure(summary["curves"], sd, sweep_dir / "figures" / "sweep.png",
                       title=f"{summary['config']['name']}: mean over {n_rep} repeat(s), band = 95 % t interval")
    rows = "".join(
        f"<tr><td>{esc(str(r['experiment']))}</td><td>{esc(r['key'])}</td>"
        f"<td>{esc(str(r['value']))}</td><td>{esc(r['tracker'])}</td><td>{r['metric']}</td>"
        f"<td>{r['mean']:.4g}</td><td>{r['low']:.4g}</td><td>{r['high']:.4g}</td><td>{r['n']}</td></tr>"
        for r in summary["curves"])
    costs = "".join(f"<li>{c['width']}x{c['height']}: {c['render_s_per_frame']:.3f} s per rendered frame "
                    f"({c['render_s_per_later_frame']:.3f} s after the first of each batch), "
                    f"{1e3 * c['eval_s_per_evaluation']:.1f} ms per frame x grid point x repeat "
                    f"({c['units']} unit(s))</li>" for c in summary["costs"])
    body = f"""<h1>Sweep: {esc(summary['config']['name'])}</h1>
<p>Grid: {esc(json.dumps(sd))}; seed {summary['seed']}; engine {esc(str(summary['engine'].get('engine')))};
wall {summary['wall_s']:.1f} s; git {esc(summary['git_revision'])}.
A repeat varies {esc(summary['repeat_varies'])}. Metrics on the object's rows
(the paper's operating point, 400 lux and 3 mW, is marked).</p>
{png_file(fig)}
<h2>Measured costs</h2><ul>{costs}</ul>
<h2>Curve data</h2><table><tr><th>experiment</th><th>key</th><th>value</th><th>tracker</th><th>metric</th>
<th>mean</th><th>low</th><th>high</th><th>n</th></tr>{rows}</table>
"""
    atomic_write_text(sweep_dir / "report.html", page(f"sweep {summary['config']['name']}", body,
                                                      css="tr:nth-child(even){background:#f3f3f3}"))
    return sweep_dir / "report.html"
