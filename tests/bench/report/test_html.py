"""bench.report.html: the report toolkit."""

import math

from bench.report.html import esc, fixed, interval, num, page, pct, png_img, rank_labels, signed


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
