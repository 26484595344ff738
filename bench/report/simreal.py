"""The sim-to-real section of a report (HTML), from a :func:`bench.evaluate.simreal.sim_to_real` result."""

from __future__ import annotations

import math

from bench.report.html import esc, fixed, table
from bench.evaluate.simreal import FIGURES, sim_to_real_headline
from bench.evaluate.stripe import why_left_out

__all__ = ["sim_to_real_html", "sim_to_real_by_class_html", "predicted_html"]


def sim_to_real_html(result: dict) -> str:
    """An HTML fragment: the sentences of both halves (:func:`bench.evaluate.simreal.sim_to_real_headline`),
    the hit rates' table of :func:`sim_to_real` and the detection table (F1, false-report rate)."""
    rows = [[esc(t["tracker"]), f"{t['synthetic']:.3f}", f"{t['real']:.3f}", f"{t['delta']:+.3f}",
             f"{t['rank_synthetic']:g}", f"{t['rank_real']:g}"] for t in result["table"]]
    text = "".join(f"<p>{esc(s)}</p>" for s in sim_to_real_headline(result))
    head = ["tracker", "synthetic hit rate", "real hit rate", "real - synthetic", "rank (synthetic)", "rank (real)"]
    return (f"<section class='sim-to-real'><h2>Renders vs photographs</h2>{text}{table(head, rows)}"
            f"{_detection_html(result.get('detection') or {})}</section>")


_DETECTION_NAMES = FIGURES


def _detection_html(detection: dict) -> str:
    """Both halves of detection, renders against photographs: F1 and the false-report rate per tracker
    (every row of the run's frames; every row of the photographs with a known state)."""
    if not detection:
        return ""
    trackers = list(dict.fromkeys(t["tracker"] for r in detection.values() for t in r["table"]))
    by = {k: {t["tracker"]: t for t in r["table"]} for k, r in detection.items()}
    head = ["tracker"] + [f"{_DETECTION_NAMES.get(k, k)}<br>synthetic / real" for k in detection]
    body = [[esc(n)] + [f"{fixed(by[k][n]['synthetic'])} / {fixed(by[k][n]['real'])}" if n in by[k] else "–"
                        for k in detection] for n in trackers]
    rho = "; ".join(f"{_DETECTION_NAMES.get(k, k)}: Spearman's rho {fixed(r['spearman_rho'], '.3f')}"
                    for k, r in detection.items())
    return (f"<p>Both halves of detection (a report on a row with no stripe is a false one): {esc(rho)}."
            "</p>" + table(head, body))


def sim_to_real_by_class_html(by_class: dict, figure: str = "hit_rate") -> str:
    """An HTML fragment from :func:`bench.evaluate.simreal.sim_to_real_by_class` of one figure
    (``figure``, a key of :data:`bench.evaluate.simreal.FIGURES`):
    per class the photographs and Spearman's rho, a tracker x class table of
    synthetic / real figures, the overall rho and each tracker's mean
    ``|synthetic - real|``. Empty when no class has both renders and photographs."""
    matched = by_class.get("matched", [])
    if not matched:
        return ""
    name = FIGURES.get(figure, figure)
    cls_rows = [[esc(c["condition"]), "yes" if c["rendered"] else "no", c["n_photographs"],
                 esc(", ".join(c["photographs"])), c["n"], fixed(c["spearman_rho"], ".2f")] for c in by_class["classes"]]
    rates = {c["condition"]: {t["tracker"]: t for t in c["table"]} for c in by_class["classes"] if c["condition"] in matched}
    overall = {t["tracker"]: t for t in by_class["overall"]["table"]}
    trackers = [t["tracker"] for t in by_class["overall"]["table"]]
    head = (["tracker"] + [f"{esc(c)}<br>synthetic / real" for c in matched]
            + ["matched classes, mean<br>synthetic / real", "mean |synthetic - real|"])
    body = [[esc(k)] + [f"{fixed(rates[c][k]['synthetic'])} / {fixed(rates[c][k]['real'])}" if k in rates[c] else "–"
                        for c in matched]
            + [f"{fixed(overall[k]['synthetic'])} / {fixed(overall[k]['real'])}",
               fixed(by_class["mean_abs_delta"].get(k, float("nan")))] for k in trackers]
    o = by_class["overall"]
    rho = ("too few trackers with distinct rates for a rank correlation" if math.isnan(o["spearman_rho"])
           else f"Spearman's rho = {o['spearman_rho']:.2f} across {o['n']} trackers")
    return (f"<section class='sim-to-real-by-class'><h3>Matched by class of condition: {esc(name)}</h3><p>Each "
            f"experiment's "
            f"<code>condition</code> against the photographs whose manifest <code>condition</code> is the same; "
            f"matched classes: {esc(', '.join(matched))}. Over the matched classes (each class weighs the same): "
            f"{esc(rho)}.</p>"
            + table(["class", "rendered", "photographs", "names", "trackers", "Spearman's rho"], cls_rows)
            + table(head, body) + "</section>")


def predicted_html(doc: dict) -> str:
    """An HTML fragment from the ``doc`` of :func:`bench.run.real.predict_real`: each tracker's hit rate
    and F1 predicted for the photographs (from frames made of them, docs/predict.md) beside the measured
    ones on the same photographs' rows, pooled and per rig, with Spearman's rho and the mean |difference|."""
    f1 = {t["tracker"]: t for t in doc["f1"]["table"]}
    body = [[esc(t["tracker"]), fixed(t["synthetic"]), fixed(t["real"]),
             fixed(f1[t["tracker"]]["synthetic"]) if t["tracker"] in f1 else "–",
             fixed(f1[t["tracker"]]["real"]) if t["tracker"] in f1 else "–"] for t in doc["hit_rate"]["table"]]

    def agree(d):
        return [f"{fixed(d[k]['spearman_rho'], '.3f')} / {fixed(d[k]['mean_abs_diff'])}" for k in ("hit_rate", "f1")]

    def repeat(v):
        rr = v.get("measured_reliability")
        if not rr:
            return "–"
        return f"{fixed(rr['hit_rate']['split_half_rho'], '.2f')} / {fixed(rr['f1']['split_half_rho'], '.2f')}"

    def span(v):
        ri = v.get("rank_interval")
        if not ri:
            return "–"
        return " / ".join(f"{fixed(ri[k]['interval'][0], '.2f')} to {fixed(ri[k]['interval'][1], '.2f')}"
                          for k in ("hit_rate", "f1"))

    rigs = [[esc(g), len(v["photographs"]), *agree(v), span(v), repeat(v)] for g, v in doc.get("rigs", {}).items()]
    why = doc.get("why") or {}
    left = doc.get("out_of_range") or {}
    shrunk = doc.get("shrunk") or {}

    def reason(n, codes=()):  # the one wording of why (bench.evaluate.stripe.why_left_out), as the prediction said it
        return why.get(n) or why_left_out(codes)

    out = "".join([
        f" Predicted shrunk (a coarse answer): {esc('; '.join(f'{n} by {k} ({reason(n)})' for n, k in shrunk.items()))}."
        if shrunk else "",
        f" Left out: {esc('; '.join(f'{n} ({reason(n, c)})' for n, c in left.items()))}." if left else ""])
    return ("<section class='sim-to-real-predicted'><h3>Predicted beside measured, photograph by photograph</h3>"
            f"<p>The same trackers' figures predicted for {len(doc['photographs'])} of the photographs from frames "
            f"made of each (<code>{esc(doc.get('frames', ''))}</code>: the photograph with its own stripe moved to a "
            "known place, and itself with its stripe where the estimate puts it, docs/predict.md) beside the figures "
            "measured on the same photographs' rows. Unlike the "
            f"means above, both sides are the same photographs.{out}</p>"
            + table(["tracker", "hit rate predicted", "measured", "F1 predicted", "measured"], body)
            + f"<p>All photographs: hit rate Spearman's rho / mean |predicted &minus; measured| "
              f"{' ; F1 '.join(agree(doc))}"
              + ("" if not doc.get("rank_interval") else
                 f"; the rho over 95 % of the photograph sets resampled with replacement (hit rate / F1): {span(doc)}")
            + ".</p>"
            + table(["rig", "photographs", "hit rate rho / mean |diff|", "F1 rho / mean |diff|",
                     "rho, 95 % of resampled sets (hit rate / F1)", "measured ranks repeat (hit rate / F1)"], rigs)
            + _reliability_html(doc.get("measured_reliability"))
            + "</section>")


def _reliability_html(rel) -> str:
    """A sentence on how repeatable the measured ranks are (:func:`bench.evaluate.prediction.rank_reliability`)."""
    if not rel:
        return ""
    cells = "; ".join(f"{esc(k.replace('_', ' '))} {fixed(v['split_half_rho'], '.2f')} "
                      f"(all photographs: {fixed(v['full_set'], '.2f')})" for k, v in rel.items())
    return ("<p>How repeatable the measured ranks are (Spearman's rho between the figures measured on random halves "
            f"of the photographs, median; stepped up to all of them): {cells}. A prediction of the trackers' true "
            "figures would correlate with these ranks by about the square root of the second figure; where the first "
            "is 0 or below (the second then '–'), the measured ranks do not repeat from one half of the photographs "
            "to the other.</p>")
