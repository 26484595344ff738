"""Per-image metrics and the sim-to-real comparison (bench.evaluate.simreal), and their HTML section."""

import numpy as np
import pytest

from bench.evaluate import simreal
from bench.report.simreal import sim_to_real_by_class_html, sim_to_real_html


# ---------------------------------------------------------------------------------------------------- metrics


def test_image_metrics_against_hand_computed_values():
    cols = [10.0, 14.0, np.nan, 3.0, 20.5, 7.0]
    ref = [11.0, 10.0, 5.0, np.nan, 20.0, 10.0]
    m = simreal.image_metrics(cols, ref, tol_px=3.0)
    # reference rows 0, 1, 2, 4, 5: errors 1, 4, miss, 0.5, 3 (3 is a hit: |error| <= tol)
    assert m["n_ref"] == 5
    assert m["hit_rate"] == pytest.approx(3 / 5)
    assert m["mae_px"] == pytest.approx((1 + 0.5 + 3) / 3)
    assert m["coverage"] == pytest.approx(4 / 5)
    # row 3 has no reference 1 row from a stripe row: unknown by the fallback rule, so its report is not false
    assert "false_detections" not in m and m["n_unknown"] == 1 and m["n_false"] == 0
    assert np.isnan(m["false_report_rate"])
    far = simreal.image_metrics([10.0] * 20, [10.0] + [np.nan] * 19)  # rows 15-19 are 15 or more rows away: none
    assert far["n_false"] == 5 and far["false_report_rate"] == 1.0 and far["n_unknown"] == 14
    m = simreal.image_metrics(cols, ref, tol_px=0.5)
    assert m["hit_rate"] == pytest.approx(1 / 5) and m["mae_px"] == pytest.approx(0.5)
    empty = simreal.image_metrics([np.nan, np.nan], [np.nan, np.nan])
    assert np.isnan(empty["hit_rate"]) and np.isnan(empty["mae_px"]) and empty["n_false"] == 0
    with pytest.raises(ValueError, match="`tol_px` must be a finite number >= 0"):
        simreal.image_metrics(cols, ref, tol_px=-1)


# ---------------------------------------------------------------------------------------------------- sim-to-real


def test_sim_to_real_rank_correlation_by_hand():
    syn = {"a": 0.9, "b": 0.8, "c": 0.7, "d": 0.6, "only_synthetic": 0.5}
    rea = {"a": 0.5, "b": 0.6, "c": 0.4, "d": 0.3, "only_real": 0.1}
    r = simreal.sim_to_real(syn, rea)
    # ranks (1 = best): synthetic a1 b2 c3 d4, real b1 a2 c3 d4; rho = 1 - 6 * 2 / (4 * 15) = 0.8
    assert r["n"] == 4 and r["spearman_rho"] == pytest.approx(0.8)
    assert [t["tracker"] for t in r["table"]] == ["b", "a", "c", "d"]
    assert r["table"][0]["delta"] == pytest.approx(-0.2) and r["table"][0]["rank_real"] == 1.0
    text = simreal.sim_to_real_sentences(r)
    assert text[0] == "Synthetic and real rankings of 4 trackers agree (Spearman's rho = 0.80)."
    # every real rate lies more than 0.10 below its synthetic one (deltas -0.4, -0.2, -0.3, -0.3)
    assert text[1] == ("The renders over-predict b (synthetic 0.80, real 0.60), a (synthetic 0.90, real 0.50), "
                       "c (synthetic 0.70, real 0.40), d (synthetic 0.60, real 0.30).")
    assert len(text) == 2
    html = sim_to_real_html(r)
    assert html.count("<tr>") == 5 and "Spearman" in html


def test_sim_to_real_under_prediction_and_too_few_trackers():
    r = simreal.sim_to_real({"a": 0.2, "b": 0.3}, {"a": 0.6, "b": 0.35})
    assert r["n"] == 2 and np.isnan(r["spearman_rho"])
    text = simreal.sim_to_real_sentences(r)
    assert text[0].startswith("Too few trackers") and text[1] == "The renders under-predict a (synthetic 0.20, real 0.60)."
    with pytest.raises(ValueError, match=r"`real_hit_rates\['a'\]` must be a hit rate in \[0, 1\], got 1.5"):
        simreal.sim_to_real({"a": 0.2}, {"a": 1.5})


# ---------------------------------------------------------------------------------------------------- by class


def test_class_real_hit_rates_average_the_photographs_of_a_class():
    per_image = {"p1": {"a": 0.2, "b": 0.4}, "p2": {"a": 0.6, "b": float("nan")}, "p3": {"a": 1.0}, "p4": {"a": 0.3}}
    r = simreal.class_real_hit_rates(per_image, {"p1": "x", "p2": "x", "p3": "y", "p4": ""})
    assert set(r) == {"x", "y"}  # p4 has no class and is left out
    assert r["x"]["photographs"] == ["p1", "p2"]
    assert r["x"]["hit_rates"]["a"] == pytest.approx(0.4) and r["x"]["hit_rates"]["b"] == pytest.approx(0.4)  # NaN skipped
    assert r["y"] == {"photographs": ["p3"], "hit_rates": {"a": 1.0}}
    with pytest.raises(ValueError, match="`image_class` must be a dict, got list"):
        simreal.class_real_hit_rates(per_image, [])


def test_sim_to_real_by_class_by_hand():
    syn = {"x": {"a": 0.9, "b": 0.7, "c": 0.5},   # rendered and photographed
           "y": {"a": 0.2, "b": 0.6, "c": 0.4},   # rendered and photographed
           "z": {"a": 0.1, "b": 0.1, "c": 0.1}}   # rendered, no photograph
    per_image = {"p1": {"a": 0.8, "b": 0.6, "c": 0.1}, "p2": {"a": 0.6, "b": 0.2, "c": 0.3},
                 "q1": {"a": 0.5, "b": 0.3, "c": 0.4}, "o1": {"a": 0.0, "b": 1.0, "c": 0.5}}
    cls = {"p1": "x", "p2": "x", "q1": "y", "o1": "other"}
    r = simreal.sim_to_real_by_class(syn, per_image, cls)
    assert r["matched"] == ["x", "y"]
    by = {c["condition"]: c for c in r["classes"]}
    assert [c["condition"] for c in r["classes"]] == ["other", "x", "y", "z"]
    assert (by["z"]["rendered"], by["z"]["n_photographs"], by["z"]["n"]) == (True, 0, 0)
    assert (by["other"]["rendered"], by["other"]["n_photographs"]) == (False, 1) and np.isnan(by["other"]["spearman_rho"])
    # class x: real = means of p1, p2 = a 0.7, b 0.4, c 0.2; synthetic a 0.9, b 0.7, c 0.5: same order, rho 1
    x = {t["tracker"]: t for t in by["x"]["table"]}
    assert x["a"]["real"] == pytest.approx(0.7) and x["b"]["real"] == pytest.approx(0.4) and x["c"]["real"] == pytest.approx(0.2)
    assert by["x"]["spearman_rho"] == pytest.approx(1.0) and by["x"]["photographs"] == ["p1", "p2"]
    # class y: synthetic ranks b1 c2 a3, real (q1) a1 c2 b3: d = 2, 0, 2 -> rho = 1 - 6 * 8 / (3 * 8) = -1
    assert by["y"]["spearman_rho"] == pytest.approx(-1.0)
    # overall: per tracker the mean over x and y: synthetic a 0.55, b 0.65, c 0.45; real a 0.6, b 0.35, c 0.3
    # ranks synthetic b1 a2 c3, real a1 b2 c3: d = 1, 1, 0 -> rho = 1 - 6 * 2 / 24 = 0.5
    o = {t["tracker"]: t for t in r["overall"]["table"]}
    assert o["a"]["synthetic"] == pytest.approx(0.55) and o["b"]["real"] == pytest.approx(0.35)
    assert r["overall"]["spearman_rho"] == pytest.approx(0.5) and r["overall"]["n"] == 3
    # mean |synthetic - real| over x, y: a (0.2 + 0.3) / 2, b (0.3 + 0.3) / 2, c (0.3 + 0.0) / 2
    assert r["mean_abs_delta"] == pytest.approx({"a": 0.25, "b": 0.3, "c": 0.15})
    html = sim_to_real_by_class_html(r)
    assert "rho = 0.50 across 3 trackers" in html and "p1, p2" in html and html.count("<tr>") == 5 + 4


def test_sim_to_real_by_class_without_a_match_or_with_few_trackers():
    r = simreal.sim_to_real_by_class({"x": {"a": 0.5}}, {"p": {"a": 0.4}}, {"p": "y"})
    assert r["matched"] == [] and r["overall"]["n"] == 0 and r["mean_abs_delta"] == {}
    assert sim_to_real_by_class_html(r) == ""  # nothing matched: no section
    r = simreal.sim_to_real_by_class({"x": {"a": 0.5, "b": 0.2}}, {"p": {"a": 0.4, "b": 0.1}}, {"p": "x"})
    assert r["matched"] == ["x"] and np.isnan(r["classes"][0]["spearman_rho"])  # two trackers: no rho
    assert r["mean_abs_delta"] == pytest.approx({"a": 0.1, "b": 0.1})
    assert "too few trackers" in sim_to_real_by_class_html(r)
    with pytest.raises(ValueError, match="`synthetic_by_class` must be a dict"):
        simreal.sim_to_real_by_class([], {}, {})
