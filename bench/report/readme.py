"""The README's tables of a run, from its saved summary: ``stripebench tables RUN``.

Three tables and a provenance line, every number read from the run's ``summary.json``
(the committed paper run is ``results/paper/``):

- **within ±5 mm**: per condition (rows, configuration order, then the pooled row) and
  tracker (columns), the fraction of sample points within ±5 mm with its Wilson 95 %
  interval; then the RMSE ratio ``1 - S_DP / S_noDP`` of chosen DP labels against the
  first baseline with its paired bootstrap interval. Bold: a fraction whose interval
  separates from the first baseline's, a ratio whose interval excludes 0
  (:func:`bench.evaluate.tables.within_winner`, :func:`~bench.evaluate.tables.ratio_winner`);
  the pooled row is not tested;
- **detection**: per condition and tracker, F1 over rows / the false-report rate;
- **the paper's claim** per reading of its method without DP, as the report's headline
  gives it (:func:`bench.evaluate.readings.claims_of`);
- **provenance**: the configuration, seed, git revision, renderer (Mitsuba variant and LLVM
  target), machine (CPU, cores) and the ``metrics.csv`` sha256.

A run's committed copy (``stripebench tables RUN --save DIR``) is its ``metrics.csv`` and
:func:`tables_summary`: the summary cut to what the tables read (a paper run's summary is about
2 MB, mostly per-experiment statistics the tables do not show).

Pure: dicts in, text out (markdown or aligned plain text).
"""

from __future__ import annotations

from bench.evaluate import readings
from bench.evaluate.formats import MISSING, fixed, interval, pct, signed_interval, signed_pct
from bench.evaluate.tables import ratio_winner, within_winner

__all__ = ["stat_groups", "default_trackers", "default_ratios", "within_table", "detection_table", "claims_table",
           "provenance_line", "render", "readme_tables", "tables_summary", "POOLED", "COPY_KEYS"]

#: The pooled row's title (an average of unlike conditions, not a condition).
POOLED = "pooled over unlike conditions"


def stat_groups(summary) -> list[tuple[str, str]]:
    """(title, statistics group) per condition in configuration order, then the pooled group ``all``
    when the run has more than one condition."""
    groups = {r["group"] for r in summary.get("robust", [])}
    out = []
    for c in summary.get("conditions", []):
        g = f"condition:{c['condition']}"
        out.append((c["condition"], g if g in groups else c["experiments"][0]))
    if len(out) > 1 and "all" in groups:
        out.append((POOLED, "all"))
    return out


def default_trackers(summary) -> list[str]:
    """The trackers the tables show by default: the baselines that are readings of the paper's method
    without DP (every baseline when none is), then the DP labels, then a scored submission."""
    cfg = summary.get("config", {})
    kinds = {(t if isinstance(t, str) else t["label"]): readings.reading_of(t, cfg.get("restore", "rows"))
             for t in cfg.get("trackers", [])}
    bases = list(cfg.get("baselines", []))
    sub = (summary.get("submission") or {}).get("label")
    return list(dict.fromkeys([*([b for b in bases if kinds.get(b)] or bases), *cfg.get("dp", []),
                               *([sub] if sub else [])]))


def default_ratios(summary) -> list[str]:
    """The DP labels whose ratio against the first baseline the ±5 mm table shows by default: the first two."""
    return list(summary.get("config", {}).get("dp", []))[:2]


def _bold(text: str, on: bool) -> str:
    return f"**{text}**" if on else text


def within_table(summary, trackers, ratios) -> tuple[list[str], list[list[str]]]:
    """The ±5 mm table: head and rows (cells marked ``**bold**``, see the module docstring).

    Examples
    --------
    >>> r = lambda g, t, w, lo, hi: {"group": g, "tracker": t, "within": w, "within_low": lo, "within_high": hi}
    >>> s = {"config": {"baselines": ["b"], "dp": ["d"]}, "conditions": [{"condition": "c", "experiments": ["e"]}],
    ...      "robust": [r("e", "b", 0.7, 0.6, 0.8), r("e", "d", 0.95, 0.9, 0.98)],
    ...      "improvement": [{"group": "e", "dp": "d", "baseline": "b", "statistic": "rmse", "value": 0.4,
    ...                       "low": 0.1, "high": 0.6}]}
    >>> within_table(s, ["b", "d"], ["d"])
    (['condition', 'b', 'd', 'ratio d'], [['c', '70 [60, 80]', '**95 [90, 98]**', '**+40 % [+10, +60]**']])
    """
    rob = {(r["group"], r["tracker"]): r for r in summary.get("robust", [])}
    imp = {(i["group"], i["dp"], i["baseline"]): i for i in summary.get("improvement", []) if i["statistic"] == "rmse"}
    bases = summary.get("config", {}).get("baselines", [])
    base = bases[0] if bases else None
    head = ["condition", *trackers, *(f"ratio {d}" for d in ratios)]
    rows = []
    for title, g in stat_groups(summary):
        tested = g != "all"
        row = [title]
        for t in trackers:
            r = rob.get((g, t))
            if r is None:
                row.append(MISSING)
                continue
            cell = f"{pct(r['within']).removesuffix(' %')} {interval(r['within_low'], r['within_high'])}"
            rb = rob.get((g, base))
            row.append(_bold(cell, tested and t != base and rb is not None and within_winner(t, r, base, rb) != "tie"))
        for d in ratios:
            i = imp.get((g, d, base))
            if i is None:
                row.append(MISSING)
                continue
            cell = f"{signed_pct(i['value'])} {signed_interval(i['low'], i['high'])}"
            if i.get("n_missing_dp") or i.get("n_missing_baseline"):
                cell += f" over {i['n']} of {i['n_samples']}"
            row.append(_bold(cell, tested and ratio_winner(d, base, i) != "tie"))
        rows.append(row)
    return head, rows


def detection_table(summary, trackers) -> tuple[list[str], list[list[str]]]:
    """The detection table: per condition (and pooled) and tracker, ``F1 / false-report rate``.

    Examples
    --------
    >>> s = {"conditions": [{"condition": "c", "experiments": ["e"]}], "detection": [
    ...     {"group": "condition:c", "tracker": "d", "f1": 0.834, "false_report_rate": 0.021}]}
    >>> detection_table(s, ["d", "x"])
    (['condition', 'd', 'x'], [['c', '0.83 / 2 %', '–']])
    """
    det = {(r["group"], r["tracker"]): r for r in summary.get("detection", [])}
    groups = [(c["condition"], f"condition:{c['condition']}") for c in summary.get("conditions", [])]
    if len(groups) > 1:
        groups.append((POOLED, "all"))
    rows = []
    for title, g in groups:
        if not any(k[0] == g for k in det):
            continue
        row = [title]
        for t in trackers:
            r = det.get((g, t))
            row.append(MISSING if r is None else f"{fixed(r.get('f1'), '.2f')} / {pct(r.get('false_report_rate'))}")
        rows.append(row)
    return ["condition", *trackers], rows


def claims_table(summary) -> tuple[list[str], list[list[str]]]:
    """The paper's claim per reading of its method without DP (``summary["paper_claims"]``), with each
    part's verdict (:func:`bench.evaluate.readings.claims_of`)."""
    within = summary.get("within_mm", 5.0)
    claim = summary.get("paper_improvement", readings.PAPER_IMPROVEMENT)
    head = ['"without DP" is', f"its ±{within:g} mm, %", f"DP's ±{within:g} mm, %", "RMSE ratio",
            f"most within ±{within:g} mm with DP", "DP more precise", f"the {pct(claim)} improvement"]
    rows = []
    for e in summary.get("paper_claims") or []:
        f, c = e["figures"], readings.claims_of(e, claim)
        who = f"`{e['baseline']}`" + (f" ({e['reading']})" if e["reading"] else "")
        if e.get("paper_reading"):
            who += " — the paper's reading"
        ratio = f"{signed_pct(f['ratio_value'])} {signed_interval(f['ratio_low'], f['ratio_high'])}"
        if f.get("n_missing_dp") or f.get("n_missing_baseline"):
            ratio += f" over {f['ratio_n']} of {f['n_samples']}"
        rows.append([who,
                     f"{pct(f['baseline_within']).removesuffix(' %')} "
                     f"{interval(f['baseline_within_low'], f['baseline_within_high'])}",
                     f"{pct(f['dp_within']).removesuffix(' %')} {interval(f['dp_within_low'], f['dp_within_high'])} "
                     f"(`{e['dp']}`)",
                     ratio, c["most_within"], c["more_precise"], c["improvement"]])
    return head, rows


def provenance_line(summary, metrics_sha256: str) -> str:
    """Where the tables come from: configuration, seed, git revision, renderer, machine, ``metrics.csv`` sha256.

    Examples
    --------
    >>> s = {"config": {"name": "paper"}, "seed": 0, "git_revision": "abc", "renderer": "llvm_ad_mono x86-64-v3/8",
    ...      "machine": {"cpu": "AMD EPYC", "cores": 2, "system": "Linux", "arch": "x86_64"}}
    >>> provenance_line(s, "f" * 64).split("; ")[1:3]
    ['rendered by `llvm_ad_mono x86-64-v3/8`', 'machine: AMD EPYC (2 cores, Linux x86_64)']
    """
    m = summary.get("machine")
    where = (f"{m.get('cpu', 'unknown')} ({m.get('cores', '?')} cores, {m.get('system', '?')} {m.get('arch', '?')})"
             if isinstance(m, dict) else "not recorded by this run")
    renderer = summary.get("renderer") or ", ".join(summary.get("variants", [])) or "not recorded"
    return (f"Run of the configuration `{summary.get('config', {}).get('name', '?')}`, seed {summary.get('seed', '?')}, "
            f"at git `{summary.get('git_revision', 'unknown')}`; rendered by `{renderer}`; machine: {where}; "
            f"`metrics.csv` sha256 `{metrics_sha256}`.")


def render(head, rows, *, markdown: bool = True) -> str:
    """A table as markdown (``| a | b |``) or as aligned plain text (``**bold**`` becomes ``x*``).

    Examples
    --------
    >>> print(render(["a", "bb"], [["1", "**2**"]]))
    | a | bb |
    | --- | --- |
    | 1 | **2** |
    >>> print(render(["a", "bb"], [["1", "**2**"]], markdown=False))
    a  bb
    1  2*
    """
    if markdown:
        return "\n".join(["| " + " | ".join(head) + " |", "| " + " | ".join("---" for _ in head) + " |",
                          *("| " + " | ".join(r) + " |" for r in rows)])
    plain = [list(head)] + [[c[2:-2] + "*" if c.startswith("**") and c.endswith("**") else c for c in r] for r in rows]
    widths = [max(len(r[k]) for r in plain) for k in range(len(head))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in plain)


def readme_tables(summary, metrics_sha256: str, *, trackers=None, ratios=None, markdown: bool = True) -> str:
    """The three tables with a line of explanation each and the provenance line (see the module docstring).

    Parameters
    ----------
    summary : dict
        The run's ``summary.json``.
    metrics_sha256 : str
        The sha256 of the run's ``metrics.csv``.
    trackers : list of str, optional
        The trackers shown (default :func:`default_trackers`).
    ratios : list of str, optional
        The DP labels whose RMSE ratio against the first baseline is shown (default :func:`default_ratios`).
    markdown : bool
        Markdown tables (ready to paste) or aligned plain text.
    """
    trackers = default_trackers(summary) if trackers is None else list(trackers)
    ratios = default_ratios(summary) if ratios is None else list(ratios)
    bases = summary.get("config", {}).get("baselines", [])
    base = f"`{bases[0]}`" if bases else "the first baseline"
    mark = "Bold" if markdown else "*"
    within = summary.get("within_mm", 5.0)
    parts = [f"Within ±{within:g} mm, % [Wilson 95 % interval], per condition; then the RMSE ratio "
             f"1 - RMSE_DP / RMSE_noDP against {base} with its paired bootstrap 95 % interval. {mark}: the interval "
             f"separates from {base}'s or, for a ratio, excludes 0 (the pooled row is not tested).",
             render(*within_table(summary, trackers, ratios), markdown=markdown)]
    head, rows = detection_table(summary, trackers)
    if rows:
        parts += ["Detection over rows: F1 / false-report rate per condition (every row of every frame is a hit, "
                  "wrong, missed, false report or quiet; docs/detection.md).", render(head, rows, markdown=markdown)]
    head, rows = claims_table(summary)
    if rows:
        parts += ["The paper's claim in its condition, per reading of its method without DP, as the report's "
                  "headline gives it (docs/statistics.md).", render(head, rows, markdown=markdown)]
    parts.append(provenance_line(summary, metrics_sha256))
    return "\n\n".join(parts)


#: The summary fields a committed copy keeps (:func:`tables_summary`): the tables' inputs, the provenance and
#: the fields every run summary must have (:data:`bench.store.summary.REQUIRED`).
COPY_KEYS = ("format", "kind", "config", "config_source", "seed", "versions", "git_revision", "machine",
             "metrics_sha256", "run_dir", "variants", "renderer", "scans", "improvement", "paper_improvement",
             "restore", "restore_by_tracker", "robust", "within_mm", "gross_mm", "conditions", "paper_claims",
             "detection", "wall_s", "submission")


def tables_summary(summary, metrics_sha256: str) -> dict:
    """The summary a committed copy keeps: :data:`COPY_KEYS`, the robust figures and RMSE ratios of the
    tables' groups only (:func:`stat_groups`), the detection figures of the conditions and ``all``, and
    ``metrics_sha256`` (the copy's ``metrics.csv``). :func:`readme_tables` gives the same text from it as
    from the whole summary.

    Examples
    --------
    >>> s = {"kind": "run", "verdicts": [1], "conditions": [{"condition": "c", "experiments": ["e"]}],
    ...      "robust": [{"group": "e", "tracker": "t"}, {"group": "x", "tracker": "t"}], "improvement": [],
    ...      "detection": []}
    >>> c = tables_summary(s, "ab")
    >>> "verdicts" in c, c["robust"], c["metrics_sha256"]
    (False, [{'group': 'e', 'tracker': 't'}], 'ab')
    """
    groups = {g for _, g in stat_groups(summary)} | {"all"}
    det_groups = {f"condition:{c['condition']}" for c in summary.get("conditions", [])} | {"all"}
    out = {k: summary[k] for k in COPY_KEYS if k in summary}
    out["robust"] = [r for r in summary.get("robust", []) if r["group"] in groups]
    out["improvement"] = [i for i in summary.get("improvement", []) if i["group"] in groups
                          and i["statistic"] == "rmse"]
    out["detection"] = [r for r in summary.get("detection", []) if r["group"] in det_groups]
    out["metrics_sha256"] = metrics_sha256
    return out
