"""The report toolkit: the one HTML page shell of every report (run, real run, sweep, leaderboard),
escaping, embedded images, the at-a-glance ranking, and the number formatters (re-exported from
their home, :mod:`bench.evaluate.formats`).

Every string that comes from a configuration, a data set, a file name or a
tracker goes through :func:`esc`, which also escapes quotes, so it is safe in
text and in attribute values alike.
"""

from __future__ import annotations

import base64
import html

from bench.evaluate.formats import fixed, interval, num, pct, signed

__all__ = ["esc", "page", "pct", "interval", "num", "signed", "fixed", "png_img", "rank_labels", "BASE_CSS"]

#: The style every page shares; a page adds its own rules after it.
BASE_CSS = ("body{font-family:system-ui,sans-serif;max-width:1370px;margin:0.6em auto;padding:0 0.6em;color:#222}"
            "h1{font-size:1.4em;margin:0.3em 0}h2{font-size:1.15em;margin:0.9em 0 0.3em}"
            "table{border-collapse:collapse;font-size:12px;margin:0.5em 0}td,th{border:1px solid #ccc;"
            "padding:3px 6px;text-align:right}th{background:#f0f0f0}code{background:#f4f4f4}li{margin:0.3em 0}"
            "details{margin:0.3em 0}summary{cursor:pointer}")


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
    import math

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
