"""Predicted beside measured (bench.evaluate.prediction): the three figures compared, the false-report frames counted
on the predicted side only."""

import pandas as pd
import pytest

from bench.evaluate.prediction import COMPARED, compare_by_group, predicted_figures


def _row(name, tracker, false, quiet, **cut):
    return {"name": name, "experiment": name, "tracker": tracker, "n_hit": 8, "n_wrong": 0, "n_missed": 2,
            "n_false": false, "n_quiet": quiet, "n_unknown": 0, **cut}


def test_the_false_report_rate_counts_the_false_report_frames_on_the_predicted_side():
    """Predicted: 1 + 3 false of 20 stripe-less rows (the moved frames' and the false-report frames'); measured: 2 of
    10. F1 reads the moved frames alone, on both sides."""
    pred = pd.DataFrame([_row("p", t, 1, 9, n_false_cut=3, n_quiet_cut=7) for t in ("a", "b", "c")])
    real = pd.DataFrame([_row("p", t, 2, 8) for t in ("a", "b", "c")])
    r = compare_by_group(pred, real, {"p": "rig"})["rig"]
    assert set(COMPARED) <= set(r)
    row = r["false_report_rate"]["table"][0]
    assert row["synthetic"] == pytest.approx(4 / 20) and row["real"] == pytest.approx(2 / 10)
    assert r["false_report_rate"]["mean_abs_diff"] == pytest.approx(0.0)
    f1 = r["f1"]["table"][0]
    assert f1["synthetic"] == pytest.approx(predicted_figures(_row("p", "a", 1, 9))["f1"])
    assert f1["synthetic"] != pytest.approx(predicted_figures(_row("p", "a", 4, 16))["f1"])


def test_without_false_report_frames_the_figures_are_the_counts_own():
    f = predicted_figures(_row("p", "a", 1, 9))
    assert f["false_report_rate"] == pytest.approx(0.1) and f["recall"] == pytest.approx(0.8)


def _ranked(names, hits_of):
    """Real-run rows: tracker ``t`` hits ``hits_of(name, t)`` of 10 stripe rows in photograph ``name``."""
    return pd.DataFrame([{"experiment": n, "tracker": t, "n_hit": hits_of(n, t), "n_wrong": 0,
                          "n_missed": 10 - hits_of(n, t), "n_false": 1, "n_quiet": 9} for n in names
                         for t in ("a", "b", "c", "d")])


def test_rank_reliability_is_high_where_every_photograph_ranks_alike_and_low_where_each_ranks_its_own_way():
    import numpy as np

    from bench.evaluate.prediction import rank_reliability

    names = [f"p{i}" for i in range(12)]
    order = {"a": 9, "b": 7, "c": 5, "d": 3}
    alike = rank_reliability(_ranked(names, lambda n, t: order[t]), names, n_splits=50)
    assert alike["hit_rate"]["split_half_rho"] == 1.0 and alike["hit_rate"]["full_set"] == 1.0
    assert alike["hit_rate"]["n_splits"] == 50
    assert np.isnan(alike["false_report_rate"]["split_half_rho"])  # every tracker alike: no ranks to compare
    rng = np.random.default_rng(3)
    hits = {(n, t): int(rng.integers(0, 11)) for n in names for t in order}
    noise = rank_reliability(_ranked(names, lambda n, t: hits[(n, t)]), names, n_splits=200)
    assert abs(noise["hit_rate"]["split_half_rho"]) < 0.5
    again = rank_reliability(_ranked(names, lambda n, t: hits[(n, t)]), names, n_splits=200)
    assert repr(again) == repr(noise)  # seeded (repr: NaN equals NaN)
    for f in ("hit_rate", "f1"):  # halves that do not agree have no whole-set reliability
        assert (noise[f]["split_half_rho"] > 0) != np.isnan(noise[f]["full_set"])


def test_rank_reliability_refuses_too_few_or_unknown_photographs():
    from bench.evaluate.prediction import rank_reliability

    df = _ranked(["p0", "p1", "p2", "p3"], lambda n, t: 5)
    with pytest.raises(ValueError, match="`names` must hold at least 4 photographs to split in halves, got 3"):
        rank_reliability(df, ["p0", "p1", "p2"])
    with pytest.raises(ValueError, match="`names` must be photographs of `real_metrics`, got 'mean'"):
        rank_reliability(df, ["p0", "p1", "p2", "mean"])
    with pytest.raises(ValueError, match="`n_splits` must be an integer >= 1, got 0"):
        rank_reliability(df, ["p0", "p1", "p2", "p3"], n_splits=0)


def _both(names, pred_hits, real_hits):
    """A prediction's per-photograph rows and a real run's, tracker ``t`` hitting ``*_hits(name, t)`` of 10 rows."""
    def rows(hits):
        return [{"name": n, "experiment": n, "tracker": t, "n_hit": hits(n, t), "n_wrong": 0,
                 "n_missed": 10 - hits(n, t), "n_false": 1, "n_quiet": 9} for n in names for t in ("a", "b", "c", "d")]
    return pd.DataFrame(rows(pred_hits)), pd.DataFrame(rows(real_hits))


def test_rank_interval_is_narrow_where_every_photograph_ranks_alike_and_wide_where_one_photograph_decides():
    """Twelve photographs on which predicted and measured ranks agree: every resample ranks alike (1.0 to 1.0). Where
    the measured ranks are all but tied and one photograph orders them, the interval spans whether it is drawn."""
    from bench.evaluate.prediction import rank_interval

    names = [f"p{i}" for i in range(12)]
    order = {"a": 9, "b": 7, "c": 5, "d": 3}
    pred, real = _both(names, lambda n, t: order[t], lambda n, t: order[t] - 1)
    alike = rank_interval(pred, real, names, n_draws=200)
    assert alike["hit_rate"] == {"interval": [1.0, 1.0], "median": 1.0, "n_draws": 200}
    # measured: every tracker hits 5 of 10, but on p0 (weight 1 of 12) they order as predicted, on p1 reversed
    pred, real = _both(names, lambda n, t: order[t],
                       lambda n, t: order[t] if n == "p0" else 12 - order[t] if n == "p1" else 5)
    split = rank_interval(pred, real, names, n_draws=400)
    lo, hi = split["hit_rate"]["interval"]
    assert lo <= -0.9 and hi >= 0.9
    assert repr(rank_interval(pred, real, names, n_draws=400)) == repr(split)  # seeded
    assert rank_interval(pred, real, names, n_draws=400, seed=1) != split


def test_rank_interval_refuses_too_few_or_unknown_photographs_and_a_bad_level():
    from bench.evaluate.prediction import rank_interval

    names = ["p0", "p1", "p2", "p3"]
    pred, real = _both(names, lambda n, t: 5, lambda n, t: 5)
    with pytest.raises(ValueError, match="`names` must hold at least 4 photographs to resample, got 3"):
        rank_interval(pred, real, names[:3])
    with pytest.raises(ValueError, match="`names` must be photographs of both tables, got 'mean'"):
        rank_interval(pred, real, [*names[:3], "mean"])
    with pytest.raises(ValueError, match="`n_draws` must be an integer >= 1, got 0"):
        rank_interval(pred, real, names, n_draws=0)
    with pytest.raises(ValueError, match=r"`level` must lie in \(0, 1\), got 1.5"):
        rank_interval(pred, real, names, level=1.5)
    tied = rank_interval(pred, real, names, n_draws=10)  # every tracker alike: nothing ranks
    assert tied["hit_rate"]["n_draws"] == 0 and all(v != v for v in tied["hit_rate"]["interval"])


def test_a_tracker_without_a_figure_is_left_out_of_that_figure_s_ranks_only():
    """Tracker ``d`` has no stripe-less rows (no false-report rate): the false-report rate is ranked over the other
    three, in every split, as the whole-row ranking ranks the hit rate over all four."""
    from bench.evaluate.prediction import rank_interval, rank_reliability

    names = [f"p{i}" for i in range(6)]
    rows = [{"name": n, "experiment": n, "tracker": t, "n_hit": h, "n_wrong": 0, "n_missed": 10 - h,
             "n_false": fa, "n_quiet": q} for n in names
            for t, h, fa, q in (("a", 9, 1, 9), ("b", 7, 3, 7), ("c", 5, 5, 5), ("d", 3, 0, 0))]
    df = pd.DataFrame(rows)
    rel = rank_reliability(df, names, n_splits=20)
    assert rel["hit_rate"]["split_half_rho"] == 1.0 and rel["hit_rate"]["n_splits"] == 20
    assert rel["false_report_rate"]["split_half_rho"] == 1.0 and rel["false_report_rate"]["n_splits"] == 20
    reversed_ = df.assign(n_false=df["n_false"].map({1: 5, 3: 3, 5: 1, 0: 0}),
                          n_quiet=df["n_quiet"].map({9: 5, 7: 7, 5: 9, 0: 0}))
    iv = rank_interval(df, reversed_, names, n_draws=20)
    assert iv["false_report_rate"] == {"interval": [-1.0, -1.0], "median": -1.0, "n_draws": 20}
    assert iv["hit_rate"]["interval"] == [1.0, 1.0]
