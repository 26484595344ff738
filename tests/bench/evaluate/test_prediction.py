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
