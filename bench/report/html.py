"""The report toolkit: the one HTML page shell of every report (run, real run, sweep, leaderboard),
escaping, tables, embedded or linked images, folded blocks and scroll boxes, the at-a-glance ranking, and the
number formatters (re-exported from their home, :mod:`bench.evaluate.formats`).

Every string that comes from a configuration, a data set, a file name or a
tracker goes through :func:`esc`, which also escapes quotes, so it is safe in
text and in attribute values alike.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

from bench.evaluate.formats import MISSING, fixed, interval, num, pct, signed

__all__ = ["esc", "page", "pct", "interval", "num", "signed", "fixed", "png_img", "png_file", "png_link", "folded",
           "scroll", "table", "frame_table", "fraction_colour", "rank_labels", "ranked_table", "BASE_CSS"]

#: The style every page shares; a page adds its own rules after it.
BASE_CSS = ("body{font-family:system-ui,sans-serif;max-width:1370px;margin:0.6em auto;padding:0 0.6em;color:#222}"
            "h1{font-size:1.4em;margin:0.3em 0}h2{font-size:1.15em;margin:0.9em 0 0.3em}"
            "table{border-collapse:collapse;font-size:12px;margin:0.5em 0}td,th{border:1px solid #ccc;"
            "padding:3px 6px;text-align:right}th{background:#f0f0f0}code{background:#f4f4f4}li{margin:0.3em 0}"
            "details{margin:0.3em 0}summary{cursor:pointer}div.scroll{max-width:100%;overflow-x:auto}"
            "div.scroll.tall{max-height:70vh;overflow-y:auto}")


def esc(value) -> str:
    """``html.escape(str(value), quote=True)``: safe in text and in attribute values.

    Examples
    --------
    >>> esc("x' onload='alert(3)")
    'x&#x27; onload=&#x27;alert(3)'
    """
    return html.escape(str(value), quote=True)


def png_img(data: bytes, alt: str, style: str = "max-width:100%") -> str:
    """An ``<img>`` holding the PNG ``data`` itself (a page that needs no other file).

    Examples
    --------
    >>> png_img(b"abc", "a<b")
    '<img src="data:image/png;base64,YWJj" alt="a&lt;b" style="max-width:100%">'
    """
    return f'<img src="data:image/png;base64,{base64.b64encode(data).decode("ascii")}" alt="{esc(alt)}" style="{esc(style)}">'


def png_file(path, width: str = "100%") -> str:
    """:func:`png_img` of the PNG file ``path`` (alt text: its name without the suffix), at most ``width`` wide.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d) / "fig7.png"
    ...     _ = p.write_bytes(b"abc")
    ...     png_file(p, "49%")
    '<img src="data:image/png;base64,YWJj" alt="fig7" style="max-width:49%">'
    """
    path = Path(path)
    return png_img(path.read_bytes(), path.stem, f"max-width:{width}")


def png_link(path, base, width: str = "100%") -> str:
    """A PNG file shown by reference, not embedded: an ``<img>`` of ``path`` relative to the folder ``base``
    (the page's own), loaded lazily, inside a link to the file (full size), at most ``width`` wide.

    Examples
    --------
    >>> png_link("/run/figures/fig7.png", "/run", "49%")
    '<a href="figures/fig7.png"><img src="figures/fig7.png" alt="fig7" loading="lazy" style="max-width:49%"></a>'
    """
    rel = Path(path).relative_to(Path(base)).as_posix()
    return (f'<a href="{esc(rel)}"><img src="{esc(rel)}" alt="{esc(Path(path).stem)}" loading="lazy" '
            f'style="max-width:{esc(width)}"></a>')


def folded(summary: str, body: str, *, open_: bool = False) -> str:
    """A ``<details>`` block: ``summary`` (HTML) shown, ``body`` (HTML) folded until opened.

    Examples
    --------
    >>> folded("<b>more</b>", "<p>x</p>")
    '<details><summary><b>more</b></summary><p>x</p></details>'
    """
    return f"<details{' open' if open_ else ''}><summary>{summary}</summary>{body}</details>"


def scroll(body: str, *, tall: bool = False) -> str:
    """``body`` (HTML, e.g. a wide table) in a box that scrolls sideways instead of widening the page;
    ``tall``: also at most 70 % of the window high, scrolling down.

    Examples
    --------
    >>> scroll("<table></table>")
    "<div class='scroll'><table></table></div>"
    """
    return f"<div class='scroll{' tall' if tall else ''}'>{body}</div>"


def table(head, rows) -> str:
    """A ``<table>``: one header row, then one row per item of ``rows``.

    Parameters
    ----------
    head : iterable of str
        The header cells' HTML (escaped by the caller), each put in a ``<th>``.
    rows : iterable of iterable of str
        Each row's cells' HTML (escaped by the caller), each put in a ``<td>``.

    Examples
    --------
    >>> table(["tracker", "hit rate"], [[esc("a<b"), fixed(0.5)], ["c", MISSING]])
    '<table><tr><th>tracker</th><th>hit rate</th></tr><tr><td>a&lt;b</td><td>0.500</td></tr><tr><td>c</td><td>–</td></tr></table>'
    """
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
    return "<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + f"</tr>{body}</table>"


def frame_table(frame, fmt: str = ".3g", *, index: bool = True) -> str:
    """A pandas DataFrame as an HTML table: numbers by ``format(v, fmt)``, a missing one as ``–``, no border.

    Examples
    --------
    >>> import pandas as pd
    >>> "<td>0.33</td>" in frame_table(pd.DataFrame({"x": [1 / 3]}), ".2f", index=False)
    True
    """
    return frame.to_html(index=index, float_format=lambda v: format(v, fmt), na_rep=MISSING, border=0)


def fraction_colour(x) -> str:
    """A cell's background for a fraction: red (0) to green (1); white where it is missing.

    Examples
    --------
    >>> fraction_colour(1.0), fraction_colour(0.25), fraction_colour(None)
    ('hsl(120, 70%, 85%)', 'hsl(30, 70%, 85%)', '#ffffff')
    """
    if x is None or not math.isfinite(x):
        return "#ffffff"
    return f"hsl({120.0 * min(max(float(x), 0.0), 1.0):.0f}, 70%, 85%)"


def page(title: str, body: str, *, css: str = "") -> str:
    """A self-contained page: the shared shell around ``body`` (already HTML), titled ``title`` (escaped).

    Examples
    --------
    >>> page("<run>", "<p>hi</p>").startswith("<!doctype html><html><head><meta charset='utf-8'><title>&lt;run&gt;")
    True
    """
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{esc(title)}</title>"
            f"<style>{BASE_CSS}{css}</style></head><body>{body}</body></html>")


def rank_labels(table: dict, labels: list, groups: list, value: str, tiebreak: str | None = None):
    """The order of ``labels`` in an at-a-glance table and each group's best label.

    Parameters
    ----------
    table : dict
        ``(group, label) -> row`` (a dict holding ``value`` and ``tiebreak``).
    labels, groups : list
    value : str
        The figure ranked by (higher is better).
    tiebreak : str, optional
        Between equal ``value`` in a group, the lower of this wins (NaN loses).

    Returns
    -------
    ordered : list
        ``labels`` by their mean ``value`` over ``groups``, best first (no finite value: last).
    best : dict
        group -> the label with the highest ``value`` there (then the lowest ``tiebreak``, then
        the first in ``ordered``).

    Examples
    --------
    >>> t = {("a", "x"): {"f": 0.9}, ("a", "y"): {"f": 0.8}, ("b", "y"): {"f": 1.0}}
    >>> rank_labels(t, ["x", "y"], ["a", "b"], "f")
    (['x', 'y'], {'a': 'x', 'b': 'y'})
    """
    def finite(v) -> bool:
        return isinstance(v, (int, float)) and math.isfinite(v)

    mean = {}
    for lab in labels:
        vals = [table[(g, lab)][value] for g in groups if (g, lab) in table and finite(table[(g, lab)][value])]
        mean[lab] = sum(vals) / len(vals) if vals else float("nan")
    ordered = sorted(labels, key=lambda lab: -mean[lab] if finite(mean[lab]) else 1.0)
    best = {}
    for g in groups:
        cand = [lab for lab in ordered if (g, lab) in table and finite(table[(g, lab)][value])]
        if cand:
            def key(lab, g=g):
                r = table[(g, lab)]
                t = r[tiebreak] if tiebreak is not None else 0.0
                return (r[value], -t if finite(t) else -math.inf)

            best[g] = max(cand, key=key)
    return ordered, best


def ranked_table(table: dict, labels: list, groups: list, value: str, cell, *, tiebreak: str | None = None,
                 tip=None) -> str:
    """An at-a-glance table: one row per label, ranked (:func:`rank_labels`), one cell per group,
    coloured by ``value`` (:func:`fraction_colour`).

    Parameters
    ----------
    table : dict
        ``(group, label) -> row``, as :func:`rank_labels` takes it.
    labels : list
    groups : list of (str, str)
        (column title, group) per column, in order; the title is escaped here.
    value, tiebreak : str
        As :func:`rank_labels`.
    cell : callable
        ``cell(row, star)``: the HTML inside a cell; ``star`` is ``" ★"`` for the best label of the
        group, else ``""``. A label without a row in a group has ``–``.
    tip : callable, optional
        ``tip(label)``: a tooltip on the label (escaped here).

    Examples
    --------
    >>> t = {("a", "x"): {"f": 0.5}, ("a", "y"): {"f": 1.0}}
    >>> out = ranked_table(t, ["x", "y"], [("A", "a")], "f", lambda r, star: f"{pct(r['f'])}{star}")
    >>> out.split("</colgroup>")[1]
    "<tr><th>rank</th><th>tracker</th><th>A</th></tr><tr><td>1</td><th>y</th><td style='background:hsl(120, 70%, 85%)'>100 % ★</td></tr><tr><td>2</td><th>x</th><td style='background:hsl(60, 70%, 85%)'>50 %</td></tr></table>"
    """
    ordered, best = rank_labels(table, labels, [g for _, g in groups], value, tiebreak)
    rows = []
    for rank, lab in enumerate(ordered, 1):
        cells = []
        for _, g in groups:
            r = table.get((g, lab))
            if r is None:
                cells.append("<td>–</td>")
                continue
            star = " ★" if best.get(g) == lab else ""
            cells.append(f"<td style='background:{fraction_colour(r.get(value))}'>{cell(r, star)}</td>")
        title = "" if tip is None else f' title="{esc(tip(lab))}"'
        rows.append(f"<tr><td>{rank}</td><th{title}>{esc(lab)}</th>{''.join(cells)}</tr>")
    head = "".join(f"<th>{esc(t)}</th>" for t, _ in groups)
    return ("<table class='glance'><colgroup><col style='width:3.2em'><col style='width:9.5em'></colgroup>"
            f"<tr><th>rank</th><th>tracker</th>{head}</tr>{''.join(rows)}</table>")
