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


# -- restoration per tracker setting, and the paper's ratio where one side has no value ----------

def _scan_with_a_missed_row():
    from bench.evaluate.triangulation import depth_cm
    from scenes import Rig

    rig = Rig().with_size(64, 60)
    F, H = 1, 60
    truth = np.linspace(20.0, 40.0, H)[None, :]
    pts = np.zeros((F, H, 3))
    pts[..., 0] = depth_cm(truth, rig)  # the true R of each row is that of its true column
    seen = truth.copy()
    seen[0, 30] = np.nan  # the tracker misses row 30
    scan = ScanResult(key="k", angles=np.zeros(F), truth_columns=truth, truth_points_cm=pts,
                      on_object=np.ones((F, H), bool), columns={"gaps": seen, "filled": seen.copy()},
                      scores={}, seconds={n: np.full(F, 1e-3) for n in ("gaps", "filled")},
                      status={n: np.zeros(F, np.int64) for n in ("gaps", "filled")}, messages={}, done=np.ones(F, bool),
                      variant="", width=64, render_seconds=0.0)
    return scan, rig


def test_each_setting_is_restored_by_its_own_method():
    from types import SimpleNamespace

    from bench.evaluate.tables import sample_table, scan_records
    from bench.evaluate.triangulation import depth_cm

    scan, rig = _scan_with_a_missed_row()
    exp = SimpleNamespace(key="k", scene="cone", material="patchy", condition="")
    how = {"gaps": "none", "filled": "rows"}
    rows = {r["row"]: r for r in sample_table(scan, rig, exp, 60, seed=0, restore=how)}
    assert len(rows) == 60 and rows[30]["filled_filled"] and not rows[30]["filled_gaps"]
    assert np.isnan(rows[30]["error_mm_gaps"])
    r = depth_cm(scan.truth_columns[0], rig)
    assert rows[30]["error_mm_filled"] == pytest.approx(10.0 * ((r[29] + r[31]) / 2 - r[30]))  # linear along the row
    assert all(rows[k]["error_mm_gaps"] == pytest.approx(0.0, abs=1e-9) for k in rows if k != 30)
    rec = {d["tracker"]: d for d in scan_records(scan, rig, exp, restore=how)}
    assert rec["filled"]["filled_fraction"] == pytest.approx(1 / 60) and rec["gaps"]["filled_fraction"] == 0.0
    # one method for every setting: both filled
    same = {r["row"]: r for r in sample_table(scan, rig, exp, 60, seed=0, restore="rows")}
    assert same[30]["error_mm_gaps"] == same[30]["error_mm_filled"]
    with pytest.raises(KeyError):
        sample_table(scan, rig, exp, 60, seed=0, restore={"gaps": "none"})


def test_the_ratio_over_both_valued_pairs_counts_what_each_side_could_not_restore():
    from bench.evaluate.tables import improvements

    s = pd.DataFrame({"experiment": ["a"] * 6,
                      "error_mm_dp": [1.0, -2.0, np.nan, 0.5, 3.0, np.nan],
                      "error_mm_gaps": [4.0, np.nan, np.nan, -1.0, 6.0, 2.0]})
    got = {r["statistic"]: r for r in improvements(s, ["dp"], ["gaps"], n_boot=200, seed=0, group_by=None)}
    # by hand: the pairs with both values are rows 0, 3, 4
    a, b = np.array([1.0, 0.5, 3.0]), np.array([4.0, -1.0, 6.0])
    rmse = 1 - np.sqrt(np.mean(a ** 2)) / np.sqrt(np.mean(b ** 2))
    mae = 1 - np.mean(np.abs(a)) / np.mean(np.abs(b))
    std = 1 - np.std(a, ddof=1) / np.std(b, ddof=1)
    for stat, want in (("rmse", rmse), ("mae", mae), ("std", std)):
        r = got[stat]
        assert r["value"] == pytest.approx(want, rel=1e-12)
        assert (r["n"], r["n_samples"], r["n_missing_dp"], r["n_missing_baseline"]) == (3, 6, 2, 2)
    one = improvements(s.iloc[[1, 2, 5]], ["dp"], ["gaps"], n_boot=50, seed=0, group_by=None)[0]
    assert one["n"] == 0 and np.isnan(one["value"]) and (one["n_missing_dp"], one["n_missing_baseline"]) == (2, 2)


def test_improvements_are_bootstrap_improvement_of_each_pair_bit_for_bit():
    # improvements shares one tracker's resamples among its pairs; every number must be what
    # bootstrap_improvement gives the pair alone (same seed per group and statistic)
    import pandas as pd

    from bench.evaluate.stats import STATISTICS, bootstrap_improvement
    from bench.evaluate.tables import improvements

    rng = np.random.default_rng(3)
    n = 40
    s = pd.DataFrame({"experiment": np.repeat(["e1", "e2"], n // 2),
                      **{f"error_mm_{k}": rng.normal(0, w, n) for k, w in (("d1", 1.0), ("d2", 2.0), ("b1", 3.0),
                                                                         ("b2", 1.5))}})
    s.loc[[3, 25], "error_mm_b2"] = np.nan  # a pair over fewer points
    out = improvements(s, ["d1", "d2"], ["b1", "b2"], n_boot=50, seed=7)
    assert len(out) == 3 * 2 * 2 * len(STATISTICS)
    groups = [("all", s)] + [(k, g) for k, g in s.groupby("experiment", sort=True)]
    for r in out:
        gi = [label for label, _ in groups].index(r["group"])
        g = groups[gi][1]
        a, b = g[f"error_mm_{r['dp']}"].to_numpy(), g[f"error_mm_{r['baseline']}"].to_numpy()
        ok = ~np.isnan(a) & ~np.isnan(b)
        si = STATISTICS.index(r["statistic"])
        alone = bootstrap_improvement(a[ok], b[ok], r["statistic"], n_boot=50,
                                      seed=int(np.random.SeedSequence([7, gi, si]).generate_state(1)[0]))
        assert (r["value"], r["low"], r["high"], r["n"]) == (alone["value"], alone["low"], alone["high"], alone["n"])


def test_the_object_region_shows_no_detection_figure_a_false_report_cannot_move():
    """Issue 66: rows off the object are unknown in region ``object``, so a false report there moves none of its
    figures; those (OBJECT_BLIND) are NaN, and every one of them moves in region ``all``."""
    from types import SimpleNamespace

    from bench.evaluate.tables import OBJECT_BLIND, scan_records
    from scenes import Rig

    rig = Rig().with_size(64, 60)
    F, H = 2, 60
    truth = np.full((F, H), np.nan)
    truth[:, 10:40] = 30.0  # the stripe on the object in rows 10-39; rows off it have no stripe
    on = ~np.isnan(truth)
    quiet = truth.copy()
    eager = truth.copy()
    eager[:, 45:60] = 5.0  # a report on 15 stripe-less rows per frame: 30 false 3-D points
    cols = {"quiet": quiet, "eager": eager}
    scan = ScanResult(key="k", angles=np.zeros(F), truth_columns=truth, truth_points_cm=np.ones((F, H, 3)),
                      on_object=on, columns=cols, scores={n: np.where(np.isnan(c), np.nan, 1.0) for n, c in cols.items()},
                      seconds={n: np.full(F, 1e-3) for n in cols}, status={n: np.zeros(F, np.int64) for n in cols},
                      messages={}, done=np.ones(F, bool), variant="", width=64, render_seconds=0.0)
    exp = SimpleNamespace(key="k", scene="cone", material="patchy", condition="")
    for region in (False, True):
        rec = {d["tracker"]: d for d in scan_records(scan, rig, exp, object_only=region)}
        if region:  # the object region: nothing that prices a false report, the stripe half alike for both
            assert all(np.isnan(rec[n][k]) for n in cols for k in OBJECT_BLIND)
            shown = [k for k, v in rec["quiet"].items() if isinstance(v, float) and np.isfinite(v)]
            assert all(rec["quiet"][k] == rec["eager"][k] for k in shown if k not in ("ms_per_frame",))
            assert rec["eager"]["hit_rate"] == rec["eager"]["recall"] == 1.0
        else:  # every row: each of those figures sees the false reports
            assert rec["eager"]["n_false"] == 30 and rec["quiet"]["n_false"] == 0
            for k in OBJECT_BLIND:
                if k == "ap":  # one constant score: AP is precision x recall, which the false reports lower
                    assert rec["eager"][k] < rec["quiet"][k]
                elif k in ("false_report_rate", "false_detections"):
                    assert rec["eager"][k] > rec["quiet"][k] == 0.0
                else:
                    assert rec["eager"][k] < rec["quiet"][k] == 1.0
