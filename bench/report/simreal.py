"""The sim-to-real section of a report (HTML), from a :func:`bench.evaluate.simreal.sim_to_real` result."""

from __future__ import annotations

import math

from bench.evaluate.formats import fixed
from bench.report.html import esc
from bench.evaluate.simreal import sim_to_real_sentences

__all__ = ["sim_to_real_html", "sim_to_real_by_class_html"]


def sim_to_real_html(result: dict) -> str:
    """An HTML fragment: the sentences and the table of :func:`sim_to_real`."""
    rows = "".join(f"<tr><td>{esc(t['tracker'])}</td><td>{t['synthetic']:.3f}</td><td>{t['real']:.3f}</td>"
                   f"<td>{t['delta']:+.3f}</td><td>{t['rank_synthetic']:g}</td><td>{t['rank_real']:g}</td></tr>"
                   for t in result["table"])
    text = "".join(f"<p>{esc(s)}</p>" for s in sim_to_real_sentences(result))
    return (f"<section class='sim-to-real'><h2>Renders vs photographs</h2>{text}<table><tr><th>tracker</th>"
            f"<th>synthetic hit rate</th><th>real hit rate</th><th>real - synthetic</th><th>rank (synthetic)</th>"
            f"<th>rank (real)</th></tr>{rows}</table>{_detection_html(result.get('detection') or {})}</section>")


_DETECTION_NAMES = {"f1": "F1 over rows", "false_report_rate": "false-report rate"}


def _detection_html(detection: dict) -> str:
    """Both halves of detection, renders against photographs: F1 and the false-report rate per tracker
    (every row of the run's frames; every row of the photographs with a known state)."""
    if not detection:
        return ""
    trackers = list(dict.fromkeys(t["tracker"] for r in detection.values() for t in r["table"]))
    by = {k: {t["tracker"]: t for t in r["table"]} for k, r in detection.items()}
    head = "".join(f"<th>{_DETECTION_NAMES.get(k, k)}<br>synthetic / real</th>" for k in detection)
    body = "".join(f"<tr><td>{esc(n)}</td>" + "".join(
        f"<td>{fixed(by[k][n]['synthetic'])} / {fixed(by[k][n]['real'])}</td>" if n in by[k] else "<td>–</td>"
        for k in detection) + "</tr>" for n in trackers)
    rho = "; ".join(f"{_DETECTION_NAMES.get(k, k)}: Spearman's rho {fixed(r['spearman_rho'], '.2f')}"
                    for k, r in detection.items())
    return (f"<p>Both halves of detection (a report on a row with no stripe is a false one): {esc(rho)}."
            f"</p><table><tr><th>tracker</th>{head}</tr>{body}</table>")




def sim_to_real_by_class_html(by_class: dict) -> str:
    """An HTML fragment from :func:`bench.evaluate.simreal.sim_to_real_by_class`:
    per class the photographs and Spearman's rho, a tracker x class table of
    synthetic / real hit rates, the overall rho and each tracker's mean
    ``|synthetic - real|``. Empty when no class has both renders and photographs."""
    matched = by_class.get("matched", [])
    if not matched:
        return ""
    cls_rows = "".join(
        f"<tr><td>{esc(c['condition'])}</td><td>{'yes' if c['rendered'] else 'no'}</td><td>{c['n_photographs']}</td>"
        f"<td>{esc(', '.join(c['photographs']))}</td><td>{c['n']}</td><td>{fixed(c['spearman_rho'], '.2f')}</td></tr>"
        for c in by_class["classes"])
    rates = {c["condition"]: {t["tracker"]: t for t in c["table"]} for c in by_class["classes"] if c["condition"] in matched}
    overall = {t["tracker"]: t for t in by_class["overall"]["table"]}
    trackers = [t["tracker"] for t in by_class["overall"]["table"]]
    head = "".join(f"<th>{esc(c)}<br>synthetic / real</th>" for c in matched)
    body = "".join(
        f"<tr><td>{esc(k)}</td>" + "".join(
            f"<td>{fixed(rates[c][k]['synthetic'])} / {fixed(rates[c][k]['real'])}</td>" if k in rates[c] else "<td>–</td>"
            for c in matched)
        + f"<td>{fixed(overall[k]['synthetic'])} / {fixed(overall[k]['real'])}</td>"
        f"<td>{fixed(by_class['mean_abs_delta'].get(k, float('nan')))}</td></tr>" for k in trackers)
    o = by_class["overall"]
    rho = ("too few trackers with distinct rates for a rank correlation" if math.isnan(o["spearman_rho"])
           else f"Spearman's rho = {o['spearman_rho']:.2f} across {o['n']} trackers")
    return (f"<section class='sim-to-real-by-class'><h3>Matched by class of condition</h3><p>Each experiment's "
            f"<code>condition</code> against the photographs whose manifest <code>condition</code> is the same; "
            f"matched classes: {esc(', '.join(matched))}. Over the matched classes (each class weighs the same): "
            f"{esc(rho)}.</p><table><tr><th>class</th><th>rendered</th><th>photographs</th><th>names</th>"
            f"<th>trackers</th><th>Spearman's rho</th></tr>{cls_rows}</table>"
            f"<table><tr><th>tracker</th>{head}<th>matched classes, mean<br>synthetic / real</th>"
            f"<th>mean |synthetic - real|</th></tr>{body}</table></section>")
