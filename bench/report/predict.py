"""The page of ``stripebench predict``: predicted figures per tracker and the photograph / moved-stripe contact sheet.

Built from the result of :func:`bench.run.predict.run_predict` with the report toolkit
(:mod:`bench.report.html`); writes ``report.html`` beside the prediction's CSV files.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from bench.evaluate.conditions import describe
from bench.report.html import esc, interval, page, pct, png_img, table

__all__ = ["thumbnail", "build_predict_report"]

#: The height of a contact-sheet picture (px).
THUMB_H = 180




def thumbnail(image, height: int = THUMB_H) -> np.ndarray:
    """An 8-bit picture of ``image`` (grey or RGB, any dtype), scaled by whole pixels (nearest) to about ``height`` rows.

    Examples
    --------
    >>> thumbnail(np.zeros((60, 64)), height=120).shape
    (120, 128, 3)
    """
    a = np.asarray(image, dtype=np.float64)
    if a.ndim == 2:
        a = np.repeat(a[..., None], 3, axis=2)
    top = float(a.max()) if a.size else 1.0
    scale = 255.0 / top if top > 255.0 else 1.0
    a = np.clip(a * scale, 0, 255)
    H = a.shape[0]
    if H > height:
        step = int(math.ceil(H / height))
        a = a[::step, ::step]
    elif H < height:
        k = max(1, height // H)
        a = a.repeat(k, axis=0).repeat(k, axis=1)
    return a.round().astype(np.uint8)


def _png(img) -> bytes:
    import imageio.v3 as iio

    return iio.imwrite("<bytes>", thumbnail(img), extension=".png")


def _iv(row, key) -> str:
    """A stated figure with its interval and, where it is not the method's own, its source."""
    from bench.evaluate.predict_loro import SOURCES

    src = row[f"{key}_source"]
    label = "" if src == SOURCES["method"] else f" <small>({esc(src)})</small>"
    lo, hi = row[f"{key}_lo"], row[f"{key}_hi"]
    return f"{pct(row[key])} {interval(lo, hi) if math.isfinite(lo) else ''}{label}"


def _agreement(v: dict) -> list[str]:
    out = []
    for k in ("hit_rate", "f1"):
        rho, diff = v[k]["spearman_rho"], v[k]["mean_abs_diff"]
        out += ["–" if math.isnan(rho) else f"{rho:.3f}", "–" if math.isnan(diff) else f"{diff:.3f}"]
    return out


def _best(rows: list) -> str:
    if not rows:
        return "–"
    p = max(rows, key=lambda r: (r["synthetic"], r["tracker"]))
    m = max(rows, key=lambda r: (r["real"], r["tracker"]))
    return f"{p['tracker']} / {m['tracker']}"


def build_predict_report(result: dict) -> Path:
    """Write ``report.html`` into the prediction's folder; returns its path.

    ``result`` is :func:`bench.run.predict.run_predict`'s return value, with ``comparison``
    (:func:`bench.evaluate.prediction.compare_with_real`), ``comparison_rigs`` and ``comparison_photos``
    (:func:`bench.evaluate.prediction.compare_by_group`) added by ``stripebench real --predict``.
    """
    from bench.evaluate.pixels import rotate_image
    from bench.store.files import atomic_write_text

    out = Path(result["out"])
    pred = result["predicted"]
    n_in = sum(1 for m in result["made"].values() if m.answered)
    n_all = len(result["made"])
    calib = result.get("calibration")
    pick = result.get("pick") or {}
    how = "with their own stripe moved (two frames each) and in place"
    level = f"{calib['level']:.0%} intervals calibrated leave one rig out on the shipped set" if calib else \
        "no calibration: the method's own figures, without intervals"
    parts = [f"<h1>Predicted: {esc(result['settings']['folder'])}</h1>",
             f"<p>{n_in} of {n_all} photographs {how}; figures pooled over their rows; {level} "
             "(docs/predict.md). F1 over rows; false-report rate: stripe-less rows given a column; hit rate: stripe "
             "rows found within the hit rule.</p>"]
    if pick.get("tracker"):
        tied = ", ".join(pick["tied"]) or "none"
        reg = pick.get("loro_regret")
        judged = (f" Judged leave one rig out, the pick's mean regret is {reg['method']:.3f} F1 (the null's pick: "
                  f"{reg['null']:.3f})." if reg else "")
        parts.append(f"<p><b>Use <code>{esc(pick['tracker'])}</code></b>: the best in {pick['chance']:.0%} of draws "
                     f"of these photographs with a shipped rig's errors; tied with it: {esc(tied)}.{judged}</p>")
    rows = [[esc(("* " if r["pick"] else "= " if r["tied"] else "") + r["tracker"]), _iv(r, "f1"),
             _iv(r, "false_report_rate"), _iv(r, "hit_rate"), f"{r['chance_best']:.0%}", esc(r["n_photos"])]
            for r in pred.to_dict("records")]
    parts.append("<h2>Stated figures</h2>" + table(["tracker", "F1", "false-report rate", "hit rate",
                                                    "chance it is best", "photographs"], rows))
    cmp = result.get("comparison")
    if cmp:  # stripebench real --predict
        f1 = {r["tracker"]: r for r in cmp["f1"]["table"]}
        crow = [[esc(r["tracker"]), pct(r["synthetic"]), pct(r["real"]),
                 pct(f1[r["tracker"]]["synthetic"]) if r["tracker"] in f1 else "–",
                 pct(f1[r["tracker"]]["real"]) if r["tracker"] in f1 else "–"] for r in cmp["hit_rate"]["table"]]
        parts.append("<h2>Predicted beside measured (the matched photographs, rows pooled)</h2>"
                     + table(["tracker", "hit rate predicted", "measured", "F1 predicted", "measured"], crow)
                     + "<p>" + "; ".join(
                         f"{esc(k)}: Spearman &rho; {cmp[k]['spearman_rho']:.3f} (p = {cmp[k]['spearman_p']:.2g}, "
                         f"n = {cmp[k]['n']}), mean |predicted &minus; measured| {cmp[k]['mean_abs_diff']:.3f}"
                         for k in ("hit_rate", "f1")) + "</p>")
    for key, what in (("comparison_rigs", "rig"), ("comparison_photos", "photograph")):
        groups = result.get(key)
        if groups:  # stripebench real --predict
            parts.append(f"<h2>Per {what} (rows of its photographs pooled on both sides)</h2>" + table(
                [what, "photographs", "hit rate &rho;", "mean |diff|", "F1 &rho;", "mean |diff|",
                 "best tracker predicted / measured (F1)"],
                [[esc(g), esc(len(v["photographs"])), *_agreement(v), esc(_best(v["f1"]["table"]))]
                 for g, v in groups.items()]))
    bad = [(n, m) for n, m in result["made"].items() if m.out_of_range]
    if bad:
        from bench.evaluate.stripe import why_left_out

        s = result["predict_settings"]
        parts.append("<h2>Not predicted at their own size</h2><ul>" + "".join(
            f"<li><code>{esc(n)}</code>: {esc(why_left_out(m.out_of_range, width_px=m.width_px, settings=s))}: "
            + (f"predicted shrunk by {m.shrink} (a coarse answer, for trackers run on the shrunk photograph)"
               if m.answered else "left out") + "</li>"
            for n, m in bad) + "</ul>")
    what = "its stripe moved"
    parts.append(f"<h2>Contact sheet: photograph and {what}</h2>")
    cells = []
    for ph in result["photos"]:
        m = result["made"][ph.name]
        photo = ph.original if ph.original.ndim == 3 else ph.frame
        if ph.original.ndim == 3:
            photo = rotate_image(ph.original, ph.rotate_deg)
        left = png_img(_png(photo), ph.name) + f"<br><small>{esc(describe(result['conditions'][ph.name]))}</small>"
        if not m.answered:
            right = f"<b>out of range</b>: {esc(', '.join(m.out_of_range))}"
        else:
            img = result["frames"][ph.name][0][0]
            right = (png_img(_png(img), f"{ph.name} stripe moved") + f"<br><small>{esc(describe(m.conditions))}</small>"
                     f"<br><small>its own stripe moved by {m.shift_px:+d} px (and by {m.shift_back_px:+d} px); "
                     f"distance {m.distance:.2f}</small>")
        cells.append([f"<code>{esc(ph.name)}</code>", left, right])
    parts.append(table(["photograph", "photo", what], cells).replace("text-align:right", ""))
    path = out / "report.html"
    atomic_write_text(path, page(f"stripebench predict: {result['settings']['folder']}", "".join(parts),
                                 css="td{text-align:left;vertical-align:top;max-width:420px}"))
    return path
