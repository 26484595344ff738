"""The run report: one self-contained HTML page of a run's saved results, its sentences and tables.

``stripebench report RUN`` calls :func:`build_report` on a finished run folder;
it needs only the saved files (no rendering). Its figures are
:func:`bench.report.runfigures.make_figures`; its toolkit (escaping, tables, images,
formatters) is :mod:`bench.report.html`.

The page leads with the answer: per condition (the configuration's first
condition is the paper's), which tracker of each DP / baseline pair is more
precise by which statistic, in words, with intervals; then a tracker x
condition table of the robust figures, Fig. 10 with every sample, a gallery of
the frames where the trackers miss most, the paper's ratio tables, hit rates,
Fig. 7, Fig. 8/9 with error maps, and the full metrics.
"""

from __future__ import annotations

import json
from pathlib import Path

from bench.evaluate import readings
from bench.report.html import (esc, frame_table, interval, num, page, pct, png_file, rank_labels, ranked_table,
                               signed, table)
from bench.evaluate.outcomes import PAPER_IMPROVEMENT, WITHIN_MM
from bench.report.detection import detection_glance
from bench.report.runfigures import make_figures, tracker_readings, tracker_restore, warn
from bench.store.runfolder import load_run
from bench.store.files import atomic_write_text

__all__ = ["build_report", "make_figures", "verdict_sentence", "glance_table", "claims_html"]


def _groups(summary) -> list[tuple[str, str, list[str]]]:
    """(title, statistics group, experiment keys) per condition, in configuration order."""
    groups = {r["group"] for r in summary.get("robust", [])}
    out = []
    for c in summary.get("conditions", []):
        g = f"condition:{c['condition']}"
        if g not in groups:
            g = c["experiments"][0]
        out.append((c["condition"], g, c["experiments"]))
    return out

def verdict_sentence(v: dict, within_mm: float = 5.0) -> str:
    """One plain sentence on a :func:`bench.evaluate.tables.verdicts` entry.

    Examples
    --------
    >>> f = {"n": 10, "within": 0.9, "within_low": 0.6, "within_high": 0.98, "median_abs_mm": 0.5, "n_gross": 0}
    >>> g = {"n": 10, "within": 0.2, "within_low": 0.06, "within_high": 0.5, "median_abs_mm": 9.0, "n_gross": 4}
    >>> r = {"value": 0.4, "low": 0.1, "high": 0.6}
    >>> verdict_sentence({"dp": "dp4", "baseline": "threshold", "within": "dp4", "rmse": "dp4",
    ...                   "dp_figures": f, "baseline_figures": g, "ratio": r}).split(" (")[0]
    'dp4 is more precise than threshold by both the ±5 mm fraction and the RMSE ratio'
    """
    d, b = esc(v["dp"]), esc(v["baseline"])
    fd, fb, r = v["dp_figures"], v["baseline_figures"], v["ratio"]
    within = (f"{pct(fd['within'])} [{pct(fd['within_low'])}, {pct(fd['within_high'])}] of the samples within "
              f"±{within_mm:g} mm against {pct(fb['within'])} [{pct(fb['within_low'])}, {pct(fb['within_high'])}]")
    ratio = ("RMSE ratio 1 - S_DP/S_noDP " + (f"{pct(r['value'])} [{pct(r['low'])}, {pct(r['high'])}]"
                                               if r is not None else "–"))
    if r is not None and (r.get("n_missing_dp") or r.get("n_missing_baseline")):
        ratio += (f" over the {r['n']} of {r['n_samples']} pairs where both have a depth ({b} has none at "
                  f"{r['n_missing_baseline']}, {d} at {r['n_missing_dp']})")
    extra = (f"median |error| {num(fd['median_abs_mm'], ' mm')} against {num(fb['median_abs_mm'], ' mm')}; "
             f"gross errors (&gt; 50 mm) {fd['n_gross']} against {fb['n_gross']}")
    w, m = esc(v["within"]), esc(v["rmse"])
    if w == m and w != "tie":
        other = b if w == d else d
        head = f"{w} is more precise than {other} by both the ±{within_mm:g} mm fraction and the RMSE ratio"
    elif w == "tie" and m == "tie":
        head = f"neither {d} nor {b} is more precise: the intervals of both statistics overlap"
    elif w == "tie":
        head = f"{m} is more precise by the RMSE ratio, but the ±{within_mm:g} mm fractions' intervals overlap"
    elif m == "tie":
        head = f"{w} is more precise by the ±{within_mm:g} mm fraction, but the RMSE ratio's interval includes 0"
    else:
        head = f"the statistics disagree: {w} wins by the ±{within_mm:g} mm fraction, {m} by the RMSE ratio"
    return f"{head} ({d}: {within}; {ratio}; {extra})."


_CLAIM_MARK = {"reproduced": "✔ reproduced", "exceeded": "▲ exceeded", "not reproduced": "✘ not reproduced",
               "contradicted": "✘ contradicted", "mixed": "± mixed", "not shown": "– not shown",
               "undecided": "– undecided", "undefined": "– undefined"}


def _claim_line(c: dict, within_mm: float, paper_improvement: float) -> str:
    """One headline sentence (HTML, escaped) on a :func:`bench.evaluate.readings.paper_claims` entry."""
    f, k = c["figures"], c["claims"]
    d, b = esc(c["dp"]), esc(c["baseline"])
    pairs = ""
    if f.get("n_missing_dp") or f.get("n_missing_baseline"):
        pairs = (f" over the {f['ratio_n']} of {f['n_samples']} pairs where both have a depth ({b}: none at "
                 f"{f['n_missing_baseline']})")
    who = f"<b><code>{b}</code></b>" + (f" ({esc(c['description'])})" if c["reading"] else "")
    if c["paper_reading"]:
        who += ", <i>the reading the paper's text supports</i>"
    return (f"{who}: most samples within ±{within_mm:g} mm with DP <b>{_CLAIM_MARK[k['most_within']]}</b> "
            f"({d} {pct(f['dp_within'])} {interval(f['dp_within_low'], f['dp_within_high'])} against "
            f"{pct(f['baseline_within'])} {interval(f['baseline_within_low'], f['baseline_within_high'])}); "
            f"DP more precise <b>{_CLAIM_MARK[k['more_precise']]}</b>; the {pct(paper_improvement)} improvement "
            f"<b>{_CLAIM_MARK[k['improvement']]}</b> (RMSE ratio {pct(f['ratio_value'])} "
            f"{interval(f['ratio_low'], f['ratio_high'])}{pairs}).")


def claims_html(summary) -> str:
    """The report's headline: the paper's claim in its own condition, one sentence per
    reading of its method without DP (``summary["paper_claims"]``,
    :func:`bench.evaluate.readings.paper_claims`), and which reading the paper's text supports.

    Examples
    --------
    >>> claims_html({}) == ""
    True
    """
    from bench.evaluate.readings import PAPER_WHY

    claims = summary.get("paper_claims") or []
    if not claims:
        return ""
    c0 = claims[0]
    within, imp = summary.get("within_mm", WITHIN_MM), summary.get("paper_improvement", PAPER_IMPROVEMENT)
    title = next((c["condition"] for c in summary.get("conditions", [])), c0["group"])
    items = "".join(f"<li>{_claim_line(c, within, imp)}</li>" for c in claims)
    why = ""
    paper = next((c for c in claims if c["paper_reading"]), None)
    if paper is not None:
        why = (f"<details class='why'><summary>Why <code>{esc(paper['baseline'])}</code> is the reading the "
               f"paper's text supports</summary><p>{esc(PAPER_WHY[:1].upper() + PAPER_WHY[1:])}.</p>"
               "<ul>" + "".join(f"<li>{esc(c['sentence'])}</li>" for c in claims) + "</ul></details>")
    if title.lower().startswith("the paper's condition: "):
        title = title[len("the paper's condition: "):]
    return (f"<h2>Is the paper's claim reproduced?</h2><p class='lead'>In the paper's condition ({esc(title)}; "
            f"{esc(', '.join(c0['experiments']))}; {c0['figures']['n']} sample points; DP = "
            f"<code>{esc(c0['dp'])}</code>), per reading of its \"method without DP\", with 95 % intervals:</p>"
            f"<ul class='claims'>{items}</ul>" + why)


def _verdicts_folded(summary) -> str:
    """The verdicts in words, folded per condition (``<details>``), the other baselines folded inside."""
    verdicts = summary.get("verdicts", [])
    if not verdicts:
        return ("<p>No DP tracker or no baseline was chosen (<code>dp</code>, <code>baselines</code>), so the "
                "report compares no pair; see the table above.</p>")
    within = summary.get("within_mm", 5.0)
    base0 = summary["config"]["baselines"][0] if summary["config"].get("baselines") else None
    by_group: dict[str, list[dict]] = {}
    for v in verdicts:
        by_group.setdefault(v["group"], []).append(v)

    def items(vs):
        main = [v for v in vs if v["baseline"] == base0]
        rest = [v for v in vs if v["baseline"] != base0]
        out = "<ul>" + "".join(f"<li>{verdict_sentence(v, within)}</li>" for v in main) + "</ul>"
        if rest:
            out += ("<details><summary>against the other baselines</summary><ul>"
                    + "".join(f"<li>{verdict_sentence(v, within)}</li>" for v in rest) + "</ul></details>")
        return out

    parts = []
    for k, (title, group, keys) in enumerate(_groups(summary)):
        vs = by_group.get(group, [])
        if not vs:
            continue
        n = vs[0]["dp_figures"]["n"]
        lead = "" if title.lower().startswith("the paper's condition") else (
            "The paper's condition: " if k == 0 else "Condition: ")
        shown = title if lead else title[:1].upper() + title[1:]
        parts.append(f"<details><summary><b>{lead}{esc(shown)}</b> <small>({esc(', '.join(keys))}; {n} sample "
                     f"points)</small></summary>" + items(vs) + "</details>")
    pooled = by_group.get("all", [])
    if pooled and len(_groups(summary)) > 1:
        parts.append("<details><summary><b>Pooled over unlike conditions</b> <small>(an average of different "
                     "effects, not a condition)</small></summary>" + items(pooled) + "</details>")
    return "".join(parts)


def glance_table(summary) -> str:
    """The tracker x condition table of the ±5 mm fraction (Wilson 95 % interval),
    median |error| and gross-error count; colour by the fraction, the best tracker
    of each condition marked with ★ (highest fraction, then lowest median);
    trackers ranked by their mean fraction over the conditions."""
    rob = {(r["group"], r["tracker"]): r for r in summary.get("robust", [])}
    groups = _groups(summary)
    if not groups or not rob:
        return ""
    trackers = list(dict.fromkeys(r["tracker"] for r in summary["robust"]))
    cfg = summary.get("config", {})
    kinds = tracker_readings(cfg) if cfg else {}

    def cell(r, star):
        return (f"<span class='w'><b>{pct(r['within'])}{star}</b> <small>{interval(r['within_low'], r['within_high'])}"
                f"</small></span><br><small>{num(r['median_abs_mm'])} mm · {signed(r.get('median_mm'))} · "
                f"{r['n_gross']} gross</small>")

    def tip(lab):
        note = readings.READINGS.get(kinds.get(lab) or "", "")
        restore = tracker_restore(summary, lab)
        return f"{note}; restoration {restore}" if note else f"restoration {restore}"

    grid = ranked_table(rob, trackers, [(t, g) for t, g, _ in groups], "within", cell, tiebreak="median_abs_mm",
                        tip=tip)
    within = summary.get("within_mm", 5.0)
    labels, _ = rank_labels(rob, trackers, [g for _, g, _ in groups], "within", "median_abs_mm")
    own = [lab for lab in labels if tracker_restore(summary, lab) != summary.get("restore", "rows")]
    restored = (f"restoration <code>{esc(summary.get('restore', 'rows'))}</code>"
                + "".join(f", <code>{esc(tracker_restore(summary, x))}</code> for <code>{esc(x)}</code>" for x in own))
    return (f"<h2>At a glance: samples within ±{within:g} mm, per tracker and condition</h2><p class='note'>"
            f"Per cell: the fraction of the sample points whose depth error on the restored surface ({restored}) "
            f"is within ±{within:g} mm (the paper's Fig. 10 band; no depth counts as outside) with its Wilson 95 % "
            f"interval; below, the median |error|, the signed median error (bias: positive is farther from the "
            f"rig) and the gross errors (&gt; {summary.get('gross_mm', 50.0):g} mm). ★ best of the condition; "
            f"rows ranked by the mean fraction.</p>" + grid)


def _improvement_tables(summary) -> str:
    """Experiments x (DP, baseline) pairs, one table per statistic (the paper's ratio)."""
    imp = summary["improvement"]
    if not imp:
        return ""
    pairs = list(dict.fromkeys((i["dp"], i["baseline"]) for i in imp))
    groups = list(dict.fromkeys(i["group"] for i in imp))
    by = {(i["group"], i["dp"], i["baseline"], i["statistic"]): i for i in imp}
    head = ["group"] + [f"{esc(d)} vs {esc(b)}" for d, b in pairs]

    def cell(i):
        return "–" if i is None else f"<b>{pct(i['value'])}</b> [{pct(i['low'])}, {pct(i['high'])}] <small>n={i['n']}</small>"

    out = []
    for stat, title in (("rmse", "RMSE"), ("mae", "MAE"), ("std", "standard deviation")):
        rows = [[esc("pooled over unlike conditions" if g == "all" else g)]
                + [cell(by.get((g, d, b, stat))) for d, b in pairs] for g in groups]
        out.append(f"<h3>by {title}</h3>" + table(head, rows))
    return ("<h2>The paper's statistic: 1 - S_DP / S_noDP</h2><p>Over the sample points' depth errors on the restored "
            "surfaces, S = RMSE, MAE or standard deviation, with a paired bootstrap 95 % confidence interval. The paper "
            f"reports about {int(100 * summary['paper_improvement'])} %. Negative: the method without DP was more "
            "precise. The ratio rests on the largest errors: read it beside the table above.</p>" + "".join(out))


def _hit_table(metrics) -> str:
    """Both halves per experiment: the stripe half on the object (hit rate, coverage), and F1 and the
    false-report rate over every row (region ``all``: the object region cannot see a false report)."""
    m = metrics[metrics["region"] == "object"]
    if m.empty or "hit_rate" not in m:
        return ""
    hit = m.pivot_table(index="experiment", columns="tracker", values="hit_rate", sort=False)
    cov = m.pivot_table(index="experiment", columns="tracker", values="coverage", sort=False)
    a = metrics[metrics["region"] == "all"]
    out = ("<h2>Both halves per experiment</h2><p>Hit rate: the object's lit rows where the tracker "
           "reports a column within 3 px of the truth (a missed row is a miss). Coverage: rows with any "
           "detection. Both are the stripe half: a report where there is no stripe moves neither. F1 and the "
           "false-report rate are over every row of the frames (a report on a row with no stripe is a false one)."
           "</p><h3>hit rate (object rows)</h3>" + frame_table(hit, ".2f") + "<h3>coverage (object rows)</h3>"
           + frame_table(cov, ".2f"))
    for key, title in (("f1", "F1 (every row)"), ("false_report_rate", "false-report rate (every row)")):
        if key in a and a[key].notna().any():
            out += f"<h3>{title}</h3>" + frame_table(
                a.pivot_table(index="experiment", columns="tracker", values=key, sort=False, dropna=False), ".2f")
    if "false_lock_rate" in a and a["false_lock_rate"].notna().any():
        lock = a[a["false_lock_rate"].notna()].pivot_table(index="experiment", columns="tracker",
                                                             values="false_lock_rate", sort=False)
        out += ("<h3>false-lock rate (shiny materials, every row)</h3><p>Among the rows where the tracker reports "
                "a column, the fraction within 3 px of a false stripe (the sheet mirrored by the object) and not "
                "within 3 px of the truth.</p>" + frame_table(lock, ".2f"))
    return out


def build_report(run_dir, *, quiet: bool = False) -> Path:
    """Write ``figures/*.png`` and ``report.html`` for a finished run."""
    run_dir = Path(run_dir)
    data = load_run(run_dir, say=warn)
    figs = make_figures(run_dir, quiet=quiet, data=data)
    s, metrics = data["summary"], data["metrics"]
    cfg = s["config"]
    own = {k: v for k, v in s.get("restore_by_tracker", {}).items() if v != s.get("restore", "rows")}
    parts = [f"<h1>stripebench run <code>{esc(run_dir.name)}</code></h1>", claims_html(s), glance_table(s),
             detection_glance(s)]
    if figs["pr"]:
        parts.append("<h2>Precision and recall over rows, per condition</h2><p>Each tracker's reports taken in "
                     "the order of its own score (its per-row confidence): precision (reports that are hits) "
                     "against recall (stripe rows hit), the dot its operating point (every report it makes). A "
                     "curve above and to the right ranks better; recall ends where the tracker stops reporting."
                     "</p>" + "".join(png_file(p, "49%") for p in figs["pr"]))
    parts.append("<h2>Which tracker is more precise, per condition</h2><p>A statistic decides only when its 95 % "
                 "intervals do: the ±5 mm fractions' Wilson intervals must not overlap; the RMSE ratio's bootstrap "
                 "interval must exclude 0. Open a condition to read its verdicts.</p>" + _verdicts_folded(s))
    parts.append(f"<h2>This run</h2><p>Configuration <code>{esc(cfg['name'])}</code> "
                 f"({esc(s.get('config_source', ''))}), seed {s['seed']}, git {esc(s['git_revision'])}, Mitsuba "
                 f"variant(s) {esc(', '.join(s['variants']))}, wall time {s['wall_s']:.0f} s, restoration "
                 f"<code>{esc(s.get('restore', 'rows'))}</code>"
                 + "".join(f", <code>{esc(k)}</code>: <code>{esc(v)}</code>" for k, v in own.items())
                 + f". Versions: {esc(', '.join(f'{k} {v}' for k, v in s['versions'].items()))}.</p>")
    if figs["samples"]:
        parts.append("<h2>Every sample (Fig. 10)</h2><p>Depth error of each sample point with and without DP; the "
                     "axis is linear within ±10 mm and logarithmic beyond, so no error is hidden (beyond "
                     "±1000 mm points sit at the edge, marked and counted).</p>"
                     + "".join(png_file(p) for p in figs["samples"]))
    if figs["gallery"]:
        parts.append("<h2>Failure gallery</h2><p>Per experiment, the frames where the trackers fail most (mean "
                     "over trackers of the rows that fail: stripe rows not within 3 px, and stripe-less rows with a "
                     "report). Markers every 4th row, offset per tracker; the truth dashed red; every report on a "
                     "row with no stripe (a false 3-D point) in magenta.</p>"
                     + "".join(png_file(p, "49%") for p in figs["gallery"]))
    if s.get("sim_to_real"):
        from bench.report.simreal import sim_to_real_html

        parts.append(sim_to_real_html(s["sim_to_real"]).replace(
            "<h2>Renders vs photographs</h2>",
            "<h2>Renders vs photographs</h2><p>Both halves: each tracker's hit rate (within 3 px) on the object's "
            "stripe rows of this run, averaged over its experiments, beside its mean hit rate over the photographs "
            f"of the real set <code>{esc(s['sim_to_real'].get('dataset', ''))}</code> (other people's rigs; "
            "references only where the stripe is visible, see docs/real.md), and its F1 over rows and false-report "
            "rate over every row of the renders beside those over the photographs' rows of known state.</p>"))
        if s["sim_to_real"].get("predicted"):
            from bench.report.simreal import predicted_html

            parts.append(predicted_html(s["sim_to_real"]["predicted"]))
        if s["sim_to_real"].get("by_class"):
            from bench.report.simreal import sim_to_real_by_class_html

            parts.append(sim_to_real_by_class_html(s["sim_to_real"]["by_class"]))
            for k, v in (s["sim_to_real"].get("by_class_detection") or {}).items():
                parts.append(sim_to_real_by_class_html(v, k))
    parts.append(_improvement_tables(s))
    parts.append(_hit_table(metrics))
    if figs["bars"]:
        parts.append("".join(png_file(p) for p in figs["bars"]))
    if figs["curves"]:
        parts.append("<h2>Sweeps</h2>" + "".join(png_file(p, "70%") for p in figs["curves"]))
    if figs["tracking"]:
        parts.append("<h2>Tracking one frame (Fig. 7)</h2>" + "".join(png_file(p) for p in figs["tracking"]))
    if figs["shapes"]:
        parts.append("<h2>Restored shapes (Fig. 8, 9)</h2><p>The ground truth coloured by depth R, and each "
                     "tracker's restored surface coloured by its depth error (mm, saturating at ±10 mm); its false "
                     "3-D points (reports on rows with no stripe, triangulated as if they were the stripe) in "
                     "magenta.</p>"
                     + "".join(png_file(p) for p in figs["shapes"]))
    cols = [c for c in ["experiment", "tracker", "region", "hit_rate", "coverage", "precision", "f1",
                        "false_report_rate", "n_false", "ap", "px_mae", "px_rmse", "px_p95",
                        "depth_mae_mm", "depth_rmse_mm", "depth_p95_mm", "outlier_rate",
                        "filled_fraction", "ms_per_frame", "failed_frames"] if c in metrics]
    full = frame_table(metrics[cols], ".3g", index=False)
    parts.append("<h2>Metrics</h2><p>Pixel errors against the ground-truth column of each lit row; depth errors "
                 "(mm) of R from eq. (3); coverage = detected / lit rows; hit rate = lit rows within 3 px / lit rows; "
                 "outliers = |error| &gt; 3 px among detected lit rows; precision = hits / reports; f1 over rows; "
                 "false-report rate = reports / rows with no stripe (<code>n_false</code> of them: false 3-D "
                 "points); ap = average precision of the tracker's score. Region <i>all</i> scores every row of the "
                 "frames; region <i>object</i> keeps the rows whose true point lies on the object, every other row "
                 "unknown, so no report there can be false: its precision, F1, false-report rate, AP and "
                 "false detections are blank (the stripe half only).</p>" + full)
    fails = [(sc["experiment"], n, c, sc["failure_messages"][n]) for sc in s["scans"]
             for n, c in sc["failures"].items() if c]
    if fails:
        parts.append("<h2>Tracker failures</h2><ul>" + "".join(
            f"<li><b>{esc(n)}</b> on {esc(e)}: {c} frame(s) failed: "
            f"{esc('; '.join(m))}</li>" for e, n, c, m in fails) + "</ul>")
    parts.append("<h2>Configuration</h2><pre>" + esc(json.dumps(cfg, indent=2)) + "</pre>")
    html_page = page("stripebench report", "\n".join(p for p in parts if p), css=(
        "ul.claims{font-size:14px;margin:0.3em 0;padding-left:1.2em}p.why,p.note{font-size:12px;color:#444;"
        "margin:0.3em 0}p.lead{margin:0.2em 0}table.glance{width:100%;table-layout:fixed}table.glance td{line-height:1.2;"
        "padding:2px 4px}table.glance span.w{white-space:nowrap}table.glance small{font-size:10px}"))
    path = run_dir / "report.html"
    atomic_write_text(path, html_page)
    return path
