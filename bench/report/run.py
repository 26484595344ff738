"""The run report: figures from saved results and one self-contained HTML page.

``stripebench report RUN`` calls :func:`build_report` on a finished run folder;
it needs only the saved files (no rendering).

The page leads with the answer: per condition (the configuration's first
condition is the paper's), which tracker of each DP / baseline pair is more
precise by which statistic, in words, with intervals; then a tracker x
condition table of the robust figures, Fig. 10 with every sample, a gallery of
the frames where the trackers miss most, the paper's ratio tables, hit rates,
Fig. 7, Fig. 8/9 with error maps, and the full metrics.
"""

from __future__ import annotations

import html
import json
import sys
from pathlib import Path

import numpy as np

from bench.evaluate import readings
from bench.report.html import esc, interval, num, page, pct, png_img, rank_labels, signed
from bench.evaluate.metrics import hit_rate
from bench.evaluate.outcomes import PAPER_IMPROVEMENT, WITHIN_MM
from bench.evaluate.tables import false_points, restore_of, restored_points
from bench.report.detection import condition_groups, detection_glance, pr_curves
from bench.store.runfolder import load_run
from bench.store.files import atomic_write_text

__all__ = ["build_report", "make_figures", "verdict_sentence", "glance_table", "claims_html"]


def _readings(cfg: dict) -> dict[str, str | None]:
    """label -> its reading of the paper's method without DP (:func:`bench.evaluate.readings.reading_of`)."""
    return {(t if isinstance(t, str) else t["label"]): readings.reading_of(t, cfg.get("restore", "rows"))
            for t in cfg.get("trackers", [])}


def _restore_of(summary, label: str) -> str:
    """How ``label``'s missed rows were restored in this run (:func:`bench.evaluate.tables.restore_of` of the
    summary's ``restore_by_tracker``; a label it lacks: the run's ``restore``)."""
    by_label = summary.get("restore_by_tracker") or {}
    return restore_of(by_label, label) if label in by_label else summary.get("restore", "rows")


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








def _warn(msg: str) -> None:
    print(msg, file=sys.stderr)






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


def _cell_colour(x: float) -> str:
    if not np.isfinite(x):
        return "#ffffff"
    hue = 120.0 * float(np.clip(x, 0.0, 1.0))  # red (0) to green (1)
    return f"hsl({hue:.0f}, 70%, 85%)"


def glance_table(summary) -> str:
    """The tracker x condition table of the ±5 mm fraction (Wilson 95 % interval),
    median |error| and gross-error count; colour by the fraction, the best tracker
    of each condition marked with ★ (highest fraction, then lowest median);
    trackers ranked by their mean fraction over the conditions."""
    rob = {(r["group"], r["tracker"]): r for r in summary.get("robust", [])}
    groups = _groups(summary)
    if not groups or not rob:
        return ""
    labels, best = rank_labels(rob, list(dict.fromkeys(r["tracker"] for r in summary["robust"])),
                               [g for _, g, _ in groups], "within", "median_abs_mm")
    head = "".join(f"<th>{esc(t)}</th>" for t, _, _ in groups)
    cfg = summary.get("config", {})
    kinds = _readings(cfg) if cfg else {}
    rows = []
    for rank, lab in enumerate(labels, 1):
        cells = []
        for _, g, _ in groups:
            r = rob.get((g, lab))
            if r is None:
                cells.append("<td>–</td>")
                continue
            star = " ★" if best.get(g) == lab else ""
            txt = (f"<span class='w'><b>{pct(r['within'])}{star}</b> <small>{interval(r['within_low'], r['within_high'])}"
                   f"</small></span><br><small>{num(r['median_abs_mm'])} mm · {signed(r.get('median_mm'))} · "
                   f"{r['n_gross']} gross</small>")
            cells.append(f"<td style='background:{_cell_colour(r['within'])}'>{txt}</td>")
        note = readings.READINGS.get(kinds.get(lab) or "", "")
        restore = _restore_of(summary, lab)
        tip = f"{note}; restoration {restore}" if note else f"restoration {restore}"
        rows.append(f"<tr><td>{rank}</td><th title=\"{esc(tip)}\">{esc(lab)}</th>{''.join(cells)}</tr>")
    within = summary.get("within_mm", 5.0)
    own = [lab for lab in labels if _restore_of(summary, lab) != summary.get("restore", "rows")]
    restored = (f"restoration <code>{esc(summary.get('restore', 'rows'))}</code>"
                + "".join(f", <code>{esc(_restore_of(summary, x))}</code> for <code>{esc(x)}</code>" for x in own))
    return (f"<h2>At a glance: samples within ±{within:g} mm, per tracker and condition</h2><p class='note'>"
            f"Per cell: the fraction of the sample points whose depth error on the restored surface ({restored}) "
            f"is within ±{within:g} mm (the paper's Fig. 10 band; no depth counts as outside) with its Wilson 95 % "
            f"interval; below, the median |error|, the signed median error (bias: positive is farther from the "
            f"rig) and the gross errors (&gt; {summary.get('gross_mm', 50.0):g} mm). ★ best of the condition; "
            f"rows ranked by the mean fraction.</p>"
            f"<table class='glance'><colgroup><col style='width:3.2em'><col style='width:9.5em'></colgroup>"
            f"<tr><th>rank</th><th>tracker</th>{head}</tr>{''.join(rows)}</table>")


def _improvement_tables(summary) -> str:
    """Experiments x (DP, baseline) pairs, one table per statistic (the paper's ratio)."""
    imp = summary["improvement"]
    if not imp:
        return ""
    pairs = list(dict.fromkeys((i["dp"], i["baseline"]) for i in imp))
    groups = list(dict.fromkeys(i["group"] for i in imp))
    by = {(i["group"], i["dp"], i["baseline"], i["statistic"]): i for i in imp}
    head = "".join(f"<th>{html.escape(d)} vs {html.escape(b)}</th>" for d, b in pairs)
    out = []
    for stat, title in (("rmse", "RMSE"), ("mae", "MAE"), ("std", "standard deviation")):
        rows = []
        for g in groups:
            cells = []
            for d, b in pairs:
                i = by.get((g, d, b, stat))
                cells.append("<td>–</td>" if i is None else
                             f"<td><b>{pct(i['value'])}</b> [{pct(i['low'])}, {pct(i['high'])}]"
                             f" <small>n={i['n']}</small></td>")
            name = "pooled over unlike conditions" if g == "all" else g
            rows.append(f"<tr><td>{html.escape(name)}</td>{''.join(cells)}</tr>")
        out.append(f"<h3>by {title}</h3><table><tr><th>group</th>{head}</tr>{''.join(rows)}</table>")
    return ("<h2>The paper's statistic: 1 - S_DP / S_noDP</h2><p>Over the sample points' depth errors on the restored "
            "surfaces, S = RMSE, MAE or standard deviation, with a paired bootstrap 95 % confidence interval. The paper "
            f"reports about {int(100 * summary['paper_improvement'])} %. Negative: the method without DP was more "
            "precise. The ratio rests on the largest errors: read it beside the table above.</p>" + "".join(out))


def _hit_table(metrics) -> str:
    m = metrics[metrics["region"] == "object"]
    if m.empty or "hit_rate" not in m:
        return ""
    fmt = {"float_format": lambda v: f"{v:.2f}", "na_rep": "–", "border": 0}
    hit = m.pivot_table(index="experiment", columns="tracker", values="hit_rate", sort=False)
    cov = m.pivot_table(index="experiment", columns="tracker", values="coverage", sort=False)
    out = ("<h2>Hit rate and coverage on the object</h2><p>Hit rate: the object's lit rows where the tracker "
           "reports a column within 3 px of the truth (a missed row is a miss). Coverage: rows with any "
           "detection.</p><h3>hit rate</h3>" + hit.to_html(**fmt) + "<h3>coverage</h3>" + cov.to_html(**fmt))
    a = metrics[metrics["region"] == "all"]
    if "false_lock_rate" in a and a["false_lock_rate"].notna().any():
        lock = a[a["false_lock_rate"].notna()].pivot_table(index="experiment", columns="tracker",
                                                             values="false_lock_rate", sort=False)
        out += ("<h3>false-lock rate (shiny materials, every row)</h3><p>Among the rows where the tracker reports "
                "a column, the fraction within 3 px of a false stripe (the sheet mirrored by the object) and not "
                "within 3 px of the truth.</p>" + lock.to_html(**fmt))
    return out


def _sweeps(cfg) -> list[tuple[str, str, list[str]]]:
    """Experiments of one scene and material that differ in exactly one numeric
    override: (title, key, experiment keys) for each such family of 3 or more."""
    from bench.config import parse

    exps = parse(cfg, "summary.json", machine=False).experiments
    fams: dict = {}
    for e in exps:
        for k, v in e.overrides.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                rest = tuple(sorted((kk, repr(vv)) for kk, vv in e.overrides.items() if kk != k))
                fams.setdefault((e.scene, e.material, k, rest), []).append(e.key)
    return [(f"{s}/{m}", k, keys) for (s, m, k, _), keys in fams.items() if len(keys) >= 3]


FIGURE_WORKERS_MIN_JOBS = 8
"""The fewest 2-D figures worth drawing in worker processes (each worker's start and imports cost
about a second of CPU; a run of the ``paper`` profile has 47 figures, about 12 s of drawing)."""


def figure_workers(n_jobs: int, workers: int | None = None) -> int:
    """How many worker processes draw ``n_jobs`` 2-D figures: 0 (draw them in this process) or more.

    ``workers`` None (the default) takes every usable core when there are at least
    :data:`FIGURE_WORKERS_MIN_JOBS` figures and 2 cores, else 0; an integer is taken as given
    (capped at ``n_jobs``).

    Examples
    --------
    >>> figure_workers(3, 4), figure_workers(47, 0), figure_workers(47, 2)
    (3, 0, 2)
    """
    from bench.run.renderahead import usable_cores

    if workers is None:
        cores = usable_cores()
        workers = cores if cores >= 2 and n_jobs >= FIGURE_WORKERS_MIN_JOBS else 0
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise ValueError(f"`workers` must be an integer >= 0 or None, got {workers!r}")
    return min(workers, n_jobs)


def _draw(jobs: list, workers: int, meanwhile) -> list[Path]:
    """Run the figure ``jobs`` (``(function, args, kwargs)``, each writing one PNG and returning its
    path), in ``workers`` processes (0: here, in order), calling ``meanwhile()`` in this process while
    they draw; returns the paths in the jobs' order. A figure is a pure function of its arguments, so
    the files are the same bytes either way (tested)."""
    if workers == 0:
        paths = [f(*a, **k) for f, a, k in jobs]
        meanwhile()
        return paths
    import concurrent.futures
    import multiprocessing

    def here(why: BaseException) -> list[Path]:
        _warn(f"figures drawn in this process: the worker processes failed ({type(why).__name__}: {why})")
        return [f(*a, **k) for f, a, k in jobs]

    import os

    from trackers.processes import die_with_parent

    # spawn: a clean child (no Dr.Jit or Dask threads of a run forked mid-flight), started by this
    # process itself, so that the kernel kills it when this process dies, whatever the signal
    # (a forkserver's children outlive a killed parent, and keep its stdout open)
    ctx = multiprocessing.get_context("spawn")
    pool = None
    try:
        pool = concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=ctx,
                                                      initializer=die_with_parent, initargs=(os.getpid(),))
        futures = [pool.submit(f, *a, **k) for f, a, k in jobs]
    except OSError as exc:  # no worker process could start: everything here
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)
        paths = here(exc)
        meanwhile()
        return paths
    with pool:
        try:
            meanwhile()
            try:
                return [fut.result() for fut in futures]
            except concurrent.futures.process.BrokenProcessPool as exc:  # a worker died: draw them again here
                return here(exc)
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def _default_rig(scene: str, cfg: dict):
    """The rig of a run that did not save its own (summaries before it did): the scene's default at the
    run's frame size."""
    import scenes

    return scenes.make(scene, width=int(cfg["render"].get("width", 512)), height=int(cfg["render"].get("height", 480))).rig


def make_figures(run_dir, *, quiet: bool = False, data: dict | None = None,
                 workers: int | None = None) -> dict[str, list[Path]]:
    """Write every figure of a run into ``run_dir/figures``; returns them by
    section. ``data`` is the run's :func:`~bench.run.experiment.load_run` if the
    caller already has it. The 2-D figures are drawn in ``workers`` processes
    (:func:`figure_workers`; default: every usable core when there are enough figures) while
    this process draws the 3-D ones."""
    import pandas as pd

    from bench.report import figures
    from bench.config import parse
    from scenes.rig import Rig

    run_dir = Path(run_dir)
    data = load_run(run_dir, say=_warn) if data is None else data
    summary, metrics, samples = data["summary"], data["metrics"], data["samples"]
    cfg = summary["config"]
    # each experiment's rig as the run saved it (runs before it was saved: the scene's default rig)
    rigs = {s["experiment"]: Rig(**s["rig"]) for s in summary.get("scans", []) if isinstance(s.get("rig"), dict)}
    config = parse(cfg, "summary.json", machine=False)
    figdir = run_dir / "figures"
    figdir.mkdir(exist_ok=True)
    for old in figdir.glob("*.png"):  # figures of an earlier report must not linger
        old.unlink()
    out: dict[str, list[Path]] = {"tracking": [], "samples": [], "gallery": [], "bars": [], "curves": [],
                                  "shapes": [], "pr": []}
    jobs: list[tuple[str, tuple]] = []  # (section, (function, args, kwargs)): the 2-D figures, drawn below

    def later(section, function, *args, **kwargs):
        jobs.append((section, (function, args, kwargs)))

    fd = data["figdata"]
    if fd is not None:  # the cost field as the run saved it (None from runs before figdata format 3)
        later("tracking", figures.fig_tracking, fd.image, fd.cost_field, fd.columns,
              fd.truth_columns, figdir / "fig7_tracking.png",
              title=f"{fd.experiment} at mirror angle {fd.mirror_angle_deg:.2f} deg "
                    "(the frame where the trackers miss most)")
    stats = {(s["group"], s["dp"], s["baseline"], s["statistic"]): s for s in summary["improvement"]}
    rob = {(r["group"], r["tracker"]): r for r in summary.get("robust", [])}
    dp0 = cfg["dp"][0] if cfg["dp"] else None
    base0 = cfg["baselines"][0] if cfg["baselines"] else None
    if dp0 and base0 and len(samples):
        kinds = _readings(cfg)
        paper = next((b for b in cfg["baselines"] if kinds.get(b) == readings.PAPER_READING), None)
        filled = next((b for b in cfg["baselines"] if kinds.get(b) == "filled"), None)
        first = set(summary["conditions"][0]["experiments"]) if summary.get("conditions") else set()
        for key, g in samples.groupby("experiment", sort=False):
            g = g.reset_index(drop=True)
            # the paper's condition: the reading the paper describes beside the filled one
            bases = [paper, base0] if key in first and paper is not None and paper != base0 else [base0]
            st = {b: stats.get((key, dp0, b, "rmse")) for b in bases}
            r = {n: rob[(key, n)] for n in (dp0, *bases) if (key, n) in rob}
            und = g[f"filled_{filled}"].to_numpy(bool) if filled is not None and len(bases) > 1 else None
            later("samples", figures.fig_samples,
                  g, dp0, bases, figdir / f"fig10_{key}.png", title=f"{key}: {len(g)} samples", stat=st, robust=r,
                  within_mm=summary.get("within_mm", 5.0), undetectable=und,
                  readings={b: readings.READINGS[kinds[b]] for b in bases if kinds.get(b)})
    gal = data.get("gallery")
    if gal is not None:
        for k, g in enumerate(gal):
            tracks, truth = g.columns, g.truth_columns
            rate = {n: hit_rate(tracks[n], truth) for n in tracks}
            worst = ", ".join(f"{n} {rate[n]:.2f}" for n in sorted(rate, key=lambda n: rate[n])[:4])
            later("gallery", figures.fig_gallery, g.image, truth, tracks, figdir / f"gallery_{k:02d}.png",
                  title=f"{g.experiment}, frame {g.frame}: lowest hit rates {worst}")
    for k, (title, _, keys) in enumerate(condition_groups(summary)):
        curves = pr_curves(data["scans"], keys, list(config.trackers))
        if curves:
            later("pr", figures.fig_pr, curves, figdir / f"pr_{k:02d}.png",
                  title=f"{title}: precision-recall over rows ({len(keys)} scan(s))")
    if len(metrics):
        later("bars", figures.fig_bars, metrics, figdir / "bars_hit_rate.png", "hit_rate")
        for title, key, keys in _sweeps(cfg):
            m = metrics[(metrics["region"] == "object") & metrics["experiment"].isin(keys)]
            val = {e.key: e.overrides[key] for e in config.experiments if e.key in keys}
            t = pd.DataFrame({key: m["experiment"].map(val), "tracker": m["tracker"], "hit_rate": m["hit_rate"]})
            mark = {"ambient_lux": 400.0, "laser_power_mw": 3.0}.get(key)
            later("curves", figures.fig_curves, t, key, figdir / f"curve_{title.replace('/', '-')}_{key}.png",
                  title=f"{title}: hit rate on the object against {key}", mark=mark)

    def shapes():
        """3-D restored shapes (VTK, in this process): the first experiment of each scene."""
        done = set()
        # the first two DP settings and the first two baselines (each surface costs about 1 s of off-screen
        # rendering)
        show = list(cfg["dp"])[:2] + list(cfg["baselines"])[:2] or list(config.trackers)[:4]
        for exp in config.experiments:
            if exp.scene in done or exp.key not in data["scans"]:
                continue
            done.add(exp.scene)
            scan = data["scans"][exp.key]
            rig = rigs.get(exp.key) or _default_rig(exp.scene, cfg)
            names = [n for n in show if n in scan.columns]
            surf = {"ground truth": restored_points(scan, None, rig)[0]}
            errs, fps = {}, {}
            for n in names:
                surf[n], errs[n] = restored_points(scan, n, rig, _restore_of(summary, n))
                fps[n] = false_points(scan, n, rig)
            try:
                out["shapes"].append(figures.fig_shapes(surf, figdir / f"shape_{exp.key}.png", title=exp.key,
                                                        errors_mm=errs, false_points=fps))
            except Exception as exc:  # a missing OpenGL must not lose the rest of the report
                if not quiet:
                    print(f"stripebench: 3-D figure of {exp.key} skipped: {type(exc).__name__}: {exc}",
                          file=sys.stderr)

    paths = _draw([job for _, job in jobs], figure_workers(len(jobs), workers), shapes)
    for (section, _), path in zip(jobs, paths):
        out[section].append(path)
    return out


def _img(path: Path, width: str = "100%") -> str:
    return png_img(path.read_bytes(), path.stem, f"max-width:{width}")

def build_report(run_dir, *, quiet: bool = False) -> Path:
    """Write ``figures/*.png`` and ``report.html`` for a finished run."""
    run_dir = Path(run_dir)
    data = load_run(run_dir, say=_warn)
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
                     "</p>" + "".join(_img(p, "49%") for p in figs["pr"]))
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
                     + "".join(_img(p) for p in figs["samples"]))
    if figs["gallery"]:
        parts.append("<h2>Failure gallery</h2><p>Per experiment, the frames where the trackers fail most (mean "
                     "over trackers of the rows that fail: stripe rows not within 3 px, and stripe-less rows with a "
                     "report). Markers every 4th row, offset per tracker; the truth dashed red; every report on a "
                     "row with no stripe (a false 3-D point) in magenta.</p>"
                     + "".join(_img(p, "49%") for p in figs["gallery"]))
    if s.get("sim_to_real"):
        from bench.report.simreal import sim_to_real_html

        parts.append(sim_to_real_html(s["sim_to_real"]).replace(
            "<h2>Renders vs photographs</h2>",
            "<h2>Renders vs photographs</h2><p>Each tracker's hit rate (within 3 px) on the object rows of this "
            "run, averaged over its experiments, beside its mean hit rate over the photographs of the real set "
            f"<code>{html.escape(s['sim_to_real'].get('dataset', ''))}</code> (other people's rigs; references "
            "only where the stripe is visible, see docs/real.md).</p>"))
        if s["sim_to_real"].get("by_class"):
            from bench.report.simreal import sim_to_real_by_class_html

            parts.append(sim_to_real_by_class_html(s["sim_to_real"]["by_class"]))
    parts.append(_improvement_tables(s))
    parts.append(_hit_table(metrics))
    if figs["bars"]:
        parts.append("".join(_img(p) for p in figs["bars"]))
    if figs["curves"]:
        parts.append("<h2>Sweeps</h2>" + "".join(_img(p, "70%") for p in figs["curves"]))
    if figs["tracking"]:
        parts.append("<h2>Tracking one frame (Fig. 7)</h2>" + "".join(_img(p) for p in figs["tracking"]))
    if figs["shapes"]:
        parts.append("<h2>Restored shapes (Fig. 8, 9)</h2><p>The ground truth coloured by depth R, and each "
                     "tracker's restored surface coloured by its depth error (mm, saturating at ±10 mm); its false "
                     "3-D points (reports on rows with no stripe, triangulated as if they were the stripe) in "
                     "magenta.</p>"
                     + "".join(_img(p) for p in figs["shapes"]))
    cols = [c for c in ["experiment", "tracker", "region", "hit_rate", "coverage", "precision", "f1",
                        "false_report_rate", "n_false", "ap", "px_mae", "px_rmse", "px_p95",
                        "depth_mae_mm", "depth_rmse_mm", "depth_p95_mm", "outlier_rate",
                        "filled_fraction", "ms_per_frame", "failed_frames"] if c in metrics]
    table = metrics[cols].to_html(index=False, float_format=lambda v: f"{v:.3g}", na_rep="–", border=0)
    parts.append("<h2>Metrics</h2><p>Pixel errors against the ground-truth column of each lit row; depth errors "
                 "(mm) of R from eq. (3); coverage = detected / lit rows; hit rate = lit rows within 3 px / lit rows; "
                 "outliers = |error| &gt; 3 px among detected lit rows; precision = hits / reports; f1 over rows; "
                 "false-report rate = reports / rows with no stripe (<code>n_false</code> of them: false 3-D "
                 "points); ap = average precision of the tracker's score; region <i>object</i> keeps the rows "
                 "whose true point lies on the object (its stripe-less rows are not scored).</p>" + table)
    fails = [(sc["experiment"], n, c, sc["failure_messages"][n]) for sc in s["scans"]
             for n, c in sc["failures"].items() if c]
    if fails:
        parts.append("<h2>Tracker failures</h2><ul>" + "".join(
            f"<li><b>{html.escape(n)}</b> on {html.escape(e)}: {c} frame(s) failed: "
            f"{html.escape('; '.join(m))}</li>" for e, n, c, m in fails) + "</ul>")
    parts.append("<h2>Configuration</h2><pre>" + html.escape(json.dumps(cfg, indent=2)) + "</pre>")
    html_page = page("stripebench report", "\n".join(p for p in parts if p), css=(
        "ul.claims{font-size:14px;margin:0.3em 0;padding-left:1.2em}p.why,p.note{font-size:12px;color:#444;"
        "margin:0.3em 0}p.lead{margin:0.2em 0}table.glance{width:100%;table-layout:fixed}table.glance td{line-height:1.2;"
        "padding:2px 4px}table.glance span.w{white-space:nowrap}table.glance small{font-size:10px}"))
    path = run_dir / "report.html"
    atomic_write_text(path, html_page)
    return path
