import numpy as np
import pandas as pd
import pytest

from bench.evaluate.tables import robust_table, verdicts, worst_frames
from bench.store.checkpoint import ScanResult


def _samples():
    return pd.DataFrame({
        "experiment": ["a"] * 4 + ["b"] * 4,
        "error_mm_dp": [0.5, -1.0, 2.0, 6.0, 0.1, 0.2, np.nan, 0.3],
        "error_mm_th": [0.2, 80.0, -60.0, 1.0, 0.1, 9.0, 0.4, 0.3],
    })


def test_robust_table_by_hand_with_missing_samples_counted_as_misses():
    rows = {(r["group"], r["tracker"]): r for r in robust_table(_samples(), ["dp", "th"])}
    a_dp, b_dp, all_th = rows[("a", "dp")], rows[("b", "dp")], rows[("all", "th")]
    assert a_dp["within"] == pytest.approx(3 / 4) and a_dp["n_gross"] == 0 and a_dp["n_missing"] == 0
    assert b_dp["n"] == 4 and b_dp["n_missing"] == 1 and b_dp["within"] == pytest.approx(3 / 4)
    assert b_dp["median_abs_mm"] == pytest.approx(0.2) and b_dp["median_mm"] == pytest.approx(0.2)
    assert rows[("a", "th")]["median_mm"] == pytest.approx(0.6)  # signed: median of -60, 0.2, 1, 80
    assert all_th["n_gross"] == 2 and all_th["within"] == pytest.approx(5 / 8)
    assert all_th["within_low"] < 5 / 8 < all_th["within_high"]


def test_verdicts_need_separated_intervals():
    rob = [
        {"group": "g", "tracker": "dp", "within": 0.95, "within_low": 0.9, "within_high": 0.98, "n": 150},
        {"group": "g", "tracker": "th", "within": 0.6, "within_low": 0.52, "within_high": 0.68, "n": 150},
        {"group": "h", "tracker": "dp", "within": 0.7, "within_low": 0.6, "within_high": 0.8, "n": 150},
        {"group": "h", "tracker": "th", "within": 0.75, "within_low": 0.65, "within_high": 0.85, "n": 150},
    ]
    imp = [{"group": "g", "dp": "dp", "baseline": "th", "statistic": "rmse", "value": -0.5, "low": -1.0, "high": -0.1},
           {"group": "h", "dp": "dp", "baseline": "th", "statistic": "rmse", "value": 0.2, "low": -0.1, "high": 0.4}]
    v = {x["group"]: x for x in verdicts(rob, imp, ["dp"], ["th"])}
    assert (v["g"]["within"], v["g"]["rmse"]) == ("dp", "th")  # the statistics disagree
    assert (v["h"]["within"], v["h"]["rmse"]) == ("tie", "tie")


def test_worst_frames_are_those_the_trackers_miss_most():
    F, H = 4, 5
    truth = np.full((F, H), 10.0)
    truth[3] = np.nan  # no lit row: never chosen
    good = truth.copy()
    bad = truth.copy()
    bad[1] = 30.0  # frame 1 missed by one tracker
    bad[2, :2] = np.nan  # frame 2 partly missed
    scan = ScanResult(key="k", angles=np.arange(F, dtype=float), truth_columns=truth,
                      truth_points_cm=np.zeros((F, H, 3)), on_object=np.ones((F, H), bool),
                      columns={"a": good, "b": bad}, scores={}, seconds={}, status={}, messages={},
                      done=np.ones(F, bool), variant="", width=64, render_seconds=0.0)
    assert worst_frames(scan, 2) == [1, 2]
    assert worst_frames(scan, 10) == [1, 2, 0]
