"""bench.report.html: the report toolkit."""

import math

from bench.report.html import (esc, fixed, fraction_colour, interval, num, page, pct, png_img, rank_labels,
                               ranked_table, signed)


def test_escaping_is_safe_in_text_and_attributes():
    hostile = "x\" onerror='alert(1)' <script>"
    out = esc(hostile)
    assert "<" not in out and ">" not in out and '"' not in out and "'" not in out
    assert "<script>" not in png_img(b"x", hostile) and "<script>" not in page(hostile, "")


def test_formatters_write_missing_values_alike():
    for f in (pct, num, signed, fixed):
        assert f(None) == f(float("nan")) == f(math.inf) == "–"
    assert interval(0.5, None) == "[–]" and interval(0.25, 0.75) == "[25, 75]"


def test_rank_labels_orders_by_mean_and_marks_each_groups_best():
    t = {("a", "x"): {"w": 0.9, "m": 2.0}, ("a", "y"): {"w": 0.9, "m": 1.0}, ("b", "x"): {"w": 0.2, "m": 1.0},
         ("b", "y"): {"w": float("nan"), "m": 1.0}, ("a", "z"): {"w": float("nan"), "m": 0.0}}
    ordered, best = rank_labels(t, ["x", "y", "z"], ["a", "b"], "w", "m")
    assert ordered == ["y", "x", "z"]  # y: mean 0.9 (its NaN skipped), x: 0.55, z: no finite value
    assert best == {"a": "y", "b": "x"}  # a: a tie on w broken by the lower m


def test_ranked_table_escapes_titles_labels_and_tips_and_marks_gaps():
    hostile = "<script>'"
    t = {("g", hostile): {"w": 0.8}, ("g", "y"): {"w": float("nan")}}
    out = ranked_table(t, [hostile, "y"], [(hostile, "g"), ("other", "h")], "w",
                       lambda r, star: f"{pct(r['w'])}{star}", tip=lambda lab: f"tip {lab}")
    assert "<script>" not in out and out.count("&lt;script&gt;&#x27;") == 3  # title, label, its tip
    rows = out.split("<tr>")[2:]
    assert rows[0].startswith("<td>1</td><th title=\"tip &lt;script&gt;&#x27;\">") and "80 % ★" in rows[0]
    assert rows[1].endswith("<td style='background:#ffffff'>–</td><td>–</td></tr></table>")  # NaN; no row in h
    assert fraction_colour(float("nan")) == fraction_colour(None) == "#ffffff" and fraction_colour(2.0).startswith("hsl(120")
