"""Detection in a run's report: both halves of it per tracker and condition, and precision-recall curves.

Every row is a hit, wrong, missed, false (a report where there is no stripe: a false
3-D point) or quiet (:mod:`bench.evaluate.outcomes`). The run's summary holds each
condition's figures with intervals over frames (``detection``); the curves are read
from the run's checkpoints. Built from saved runs only.
"""

from __future__ import annotations

import numpy as np

from bench.report.html import interval, pct, ranked_table

__all__ = ["detection_glance", "pr_curves", "condition_groups"]


def condition_groups(summary) -> list[tuple[str, str, list[str]]]:
    """(title, detection group, experiment keys) per condition, in configuration order."""
    return [(c["condition"], f"condition:{c['condition']}", list(c["experiments"]))
            for c in summary.get("conditions", [])]


def detection_glance(summary) -> str:
    """The tracker x condition table of detection: F1 over rows with its interval over frames, the
    false-report rate, AP and the false 3-D points per scan; coloured by F1, ★ the best F1 of each
    condition, trackers ranked by their mean F1 over the conditions. Empty without a ``detection``
    table (a run written before detection was scored).

    Examples
    --------
    >>> s = {"conditions": [{"condition": "c", "experiments": ["e"]}], "detection": [
    ...     {"group": "condition:c", "tracker": "a", "f1": 0.9, "f1_lo": 0.8, "f1_hi": 0.95, "ap": 0.9,
    ...      "false_report_rate": 0.05, "false_points_per_scan": 3.0, "ap_constant": False}]}
    >>> "90 %" in detection_glance(s) and "3 false points" in detection_glance(s)
    True
    """
    det = {(r["group"], r["tracker"]): r for r in summary.get("detection", [])}
    groups = [g for g in condition_groups(summary) if any(k[0] == g[1] for k in det)]
    if not groups:
        return ""

    def cell(r, star):
        ap = pct(r.get("ap")) + (" <small>(one point)</small>" if r.get("ap_constant") else "")
        return (f"<span class='w'><b>F1 {pct(r.get('f1'))}{star}</b> <small>{interval(r.get('f1_lo'), r.get('f1_hi'))}"
                f"</small></span><br><small>false reports {pct(r.get('false_report_rate'))} · AP {ap} · "
                f"{r.get('false_points_per_scan', float('nan')):.0f} false points/scan</small>")

    table = ranked_table(det, list(dict.fromkeys(r["tracker"] for r in summary["detection"])),
                         [(t, g) for t, g, _ in groups], "f1", cell)
    return ("<h2>At a glance: detection, both halves, per tracker and condition</h2><p class='note'>Every row of "
            "every frame is a hit (a column within 3 px of the truth), wrong (further off), missed (a stripe row "
            "with nothing reported), false (a column on a row with no stripe: past an edge, in shadow, on a "
            "mirror or a void; each is a 3-D point where there is no surface) or quiet. Per cell: F1 over rows "
            "(precision = hits / reports, recall = hits / stripe rows) with its 95 % bootstrap interval over "
            "frames; the false-report rate (false / stripe-less rows); AP, the average precision of the "
            "tracker's own score ranking its reports (threshold-free; \"one point\" where every report has the "
            "same score); and the false 3-D points per scan. ★ best F1 of the condition; rows ranked by the "
            "mean F1.</p>" + table)


def pr_curves(scans: dict, keys, labels=None) -> dict:
    """Each tracker's precision-recall curve over the rows of the scans ``keys`` (pooled), with its
    operating point (every report taken): label -> ``{recall, precision, point: (recall, precision),
    ap, constant}``.

    Parameters
    ----------
    scans : dict
        experiment key -> :class:`bench.store.checkpoint.ScanResult` (a loaded run's ``scans``).
    keys : sequence of str
        The experiments pooled.
    labels : sequence of str, optional
        The trackers (default every tracker of the first scan).
    """
    from bench.evaluate.outcomes import detection_figures, outcome_counts
    from bench.evaluate.ranking import average_precision, pr_curve
    from bench.evaluate.tables import detection_rows

    rows = [detection_rows(scans[k]) for k in keys if k in scans]
    if not rows:
        return {}
    out = {}
    for lab in (labels or list(rows[0])):
        if not all(lab in r for r in rows):
            continue
        codes = np.concatenate([r[lab][0].ravel() for r in rows])
        scores = np.concatenate([r[lab][1].ravel() for r in rows])
        c = pr_curve(scores, codes)
        f = detection_figures(outcome_counts(codes))
        out[lab] = {"recall": c["recall"], "precision": c["precision"], "point": (f["recall"], f["precision"]),
                    "ap": average_precision(scores, codes)["ap"], "constant": c["constant"]}
    return out
