"""The paper's "method without DP" read three ways, and its claim tested per reading."""

import numpy as np
import pandas as pd
import pytest

from bench.evaluate.readings import (PAPER_READING, claim_verdicts, claims_of, headline_group, headline_lines,
                                    improvement_verdict, paper_claims, reading_of)


@pytest.mark.parametrize("setting, run_restore, kind", [
    ("threshold", "rows", "filled"),
    ("threshold", "none", "gaps"),
    ({"label": "g", "name": "threshold", "restore": "none"}, "rows", "gaps"),
    ({"label": "g", "name": "threshold", "restore": "rows"}, "none", "filled"),
    ({"label": "a", "name": "threshold", "params": {"threshold": -1.0}}, "rows", "argmax"),
    ({"label": "a", "name": "threshold", "params": {"threshold": -1.0}, "restore": "none"}, "rows", "argmax"),
    ({"label": "t", "name": "threshold", "params": {"threshold": 0.0}}, "rows", None),  # drops all-black rows
    ({"label": "t", "name": "threshold", "params": {"k_sigma": 3.0}}, "rows", "filled"),
    ("centroid", "rows", None),
    ("dp4", "none", None),
])
def test_reading_of_a_setting(setting, run_restore, kind):
    assert reading_of(setting, run_restore) == kind


def _fig(w, lo, hi, n=100):
    return {"n": n, "within": w, "within_low": lo, "within_high": hi, "median_abs_mm": 0.3, "n_gross": 0}


def _v(within, rmse, dp=(0.95, 0.9, 0.98), base=(0.7, 0.6, 0.78)):
    return {"group": "condition:p", "dp": "d", "baseline": "b", "within": within, "rmse": rmse,
            "dp_figures": _fig(*dp), "baseline_figures": _fig(*base)}


@pytest.mark.parametrize("within, rmse, ratio, dp, want", [
    ("d", "d", (0.35, 0.25, 0.45), (0.95, 0.9, 0.98), ("reproduced", "reproduced", "reproduced")),
    ("d", "d", (0.86, 0.03, 0.94), (0.95, 0.9, 0.98), ("reproduced", "reproduced", "not determined")),
    ("d", "tie", (0.6, 0.35, 0.8), (0.95, 0.9, 0.98), ("reproduced", "reproduced", "exceeded")),
    ("tie", "b", (-1.0, -2.5, -0.2), (0.95, 0.9, 0.98), ("reproduced", "contradicted", "not reproduced")),
    ("d", "b", (-0.1, -0.3, -0.01), (0.55, 0.45, 0.65), ("undecided", "mixed", "not reproduced")),
    ("tie", "tie", (np.nan, np.nan, np.nan), (0.3, 0.2, 0.4), ("not reproduced", "not shown", "undefined")),
    ("tie", "tie", (0.1, -0.2, 0.3), (0.9, 0.8, 0.95), ("reproduced", "not shown", "not determined")),  # 30 % inside
    ("tie", "tie", (0.2, 0.1, 0.35), (0.9, 0.8, 0.95), ("reproduced", "not shown", "reproduced")),
])
def test_claim_verdicts_follow_the_intervals(within, rmse, ratio, dp, want):
    r = dict(zip(("value", "low", "high"), ratio))
    got = claim_verdicts(_v(within, rmse, dp=dp), r, 0.30)
    assert (got["most_within"], got["more_precise"], got["improvement"]) == want


@pytest.mark.parametrize("low, high, want", [
    (0.03, 0.94, "not determined"),  # holds 30 %, 91 points wide: one gross error can make it
    (-0.16, 0.92, "not determined"),
    (0.0, 0.30, "not determined"),  # exactly as wide as the claim
    (0.01, 0.30, "reproduced"),  # narrower than the claim: also excludes no improvement
    (0.22, 0.41, "reproduced"),
    (0.31, 0.99, "exceeded"),  # wide, but all of it above the claim
    (-0.39, -0.08, "not reproduced"),
    (-0.02, 0.28, "not reproduced"),
    (np.nan, 0.5, "undefined"),
])
def test_the_improvement_verdict_says_not_determined_where_the_interval_is_as_wide_as_the_claim(low, high, want):
    assert improvement_verdict(low, high, 0.30) == want


def test_the_width_that_still_decides_is_a_parameter():
    assert improvement_verdict(0.1, 0.5, 0.30) == "not determined"
    assert improvement_verdict(0.1, 0.5, 0.30, max_width=0.5) == "reproduced"
    assert improvement_verdict(0.25, 0.33, 0.20) == "exceeded"  # the claim is a parameter too


def test_every_view_takes_the_improvement_verdict_again_from_the_interval():
    entry = {"claims": {"most_within": "reproduced", "more_precise": "reproduced", "improvement": "reproduced"},
             "figures": {"ratio_low": 0.03, "ratio_high": 0.94}}
    assert claims_of(entry) == {"most_within": "reproduced", "more_precise": "reproduced",
                                "improvement": "not determined"}
    entry["figures"] = {"ratio_low": 0.2, "ratio_high": 0.4}
    assert claims_of(entry)["improvement"] == "reproduced" and claims_of(entry, 0.5)["improvement"] == "not reproduced"


def test_headline_group_is_the_first_condition():
    robust = [{"group": "condition:p"}, {"group": "x"}]
    assert headline_group(robust, [{"condition": "p", "experiments": ["a", "b"]},
                                   {"condition": "x", "experiments": ["x"]}]) == ("condition:p", ["a", "b"])
    assert headline_group([{"group": "a"}], [{"condition": "p", "experiments": ["a"]}]) == ("a", ["a"])
    assert headline_group(robust, []) is None


def test_paper_claims_one_entry_per_reading_with_the_undetectable_count():
    config = {"restore": "rows", "dp": ["dp4"], "baselines": ["threshold", "gaps", "argmax", "centroid"],
              "trackers": ["threshold", "dp4", "centroid", {"label": "gaps", "name": "threshold", "restore": "none"},
                       {"label": "argmax", "name": "threshold", "params": {"threshold": -1.0}}]}
    # 6 samples in the paper's condition: threshold misses samples 3, 4, 5 (filled there)
    samples = pd.DataFrame({
        "experiment": ["p1", "p1", "p1", "p2", "p2", "p2", "other"],
        "error_mm_dp4": [0.1, 0.2, -0.1, 0.3, 1.0, 0.2, 0.0],
        "error_mm_threshold": [0.1, 0.1, 0.1, 0.5, 7.0, 0.4, 0.0],
        "filled_threshold": [False, False, False, True, True, True, True],
        "error_mm_gaps": [0.1, 0.1, 0.1, np.nan, np.nan, np.nan, np.nan],
        "error_mm_argmax": [0.1, 0.1, 8.0, 40.0, -300.0, 0.4, 0.0],
    })
    robust, verdicts, improvement = [], [], []
    for b in config["baselines"]:
        robust.append({"group": "condition:p", "tracker": b})
        verdicts.append(_v("tie", "tie") | {"dp": "dp4", "baseline": b})
        improvement.append({"group": "condition:p", "dp": "dp4", "baseline": b, "statistic": "rmse", "value": 0.5,
                            "low": 0.1, "high": 0.9, "n": 3 if b == "gaps" else 6, "n_samples": 6, "n_missing_dp": 0,
                            "n_missing_baseline": 3 if b == "gaps" else 0})
    conditions = [{"condition": "p", "experiments": ["p1", "p2"]}, {"condition": "o", "experiments": ["other"]}]
    got = paper_claims(config, robust, improvement, verdicts, conditions, samples)
    assert [(c["baseline"], c["reading"]) for c in got] == [("threshold", "filled"), ("gaps", "gaps"),
                                                            ("argmax", "argmax")]  # centroid is no reading
    by = {c["baseline"]: c for c in got}
    assert [c["baseline"] for c in got if c["paper_reading"]] == [b for b, c in by.items() if c["reading"] == PAPER_READING]
    assert (by["threshold"]["outside"], by["threshold"]["outside_undetectable"]) == (1, 1)  # sample 4 only
    assert (by["gaps"]["outside"], by["gaps"]["outside_undetectable"]) == (3, 3)  # no depth counts as outside
    assert (by["argmax"]["outside"], by["argmax"]["outside_undetectable"]) == (3, 2)  # samples 2, 3, 4
    assert by["gaps"]["figures"]["n_missing_baseline"] == 3 and "over the 3 of 6 pairs" in by["gaps"]["sentence"]
    assert by["argmax"]["claims"] == {"most_within": "reproduced", "more_precise": "not shown",
                                      "improvement": "not determined"}  # +50 % [+10, +90] holds 30 %, 80 wide
    assert "the 30 % improvement: not determined (the interval is as wide as the 30 % claimed)" in by["argmax"][
        "sentence"]
    lines = headline_lines({"paper_claims": got, "conditions": [
        {"condition": "the paper's condition: p", "experiments": ["p1", "p2"]}], "paper_improvement": 0.30})
    assert lines[0].startswith("The paper's claim in its condition (p; p1, p2; 100 sample points; DP = dp4)")
    assert len(lines) == 4 and lines[3].startswith("  argmax (the brightest pixel of every row), the reading the paper")
    assert "the 30 % improvement: not determined (the interval is as wide as the 30 % claimed); RMSE ratio +50 % " \
           "[+10, +90]" in lines[3]
    assert "over 3 of 6 pairs" in lines[2] and "DP more precise: not shown (the intervals overlap)" in lines[1]
    assert "2 of argmax's 3 samples outside ±5 mm lie where the threshold detects no stripe" in by["argmax"]["sentence"]
    assert paper_claims({**config, "dp": []}, robust, improvement, verdicts, conditions) == []
    # no baseline is a reading: the first baseline is reported
    only = paper_claims({**config, "baselines": ["centroid"]}, robust, improvement, verdicts, conditions)
    assert [(c["baseline"], c["reading"]) for c in only] == [("centroid", None)]
