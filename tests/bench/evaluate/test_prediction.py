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
