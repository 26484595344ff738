import numpy as np
import pytest

from bench.metrics import coverage, error_stats, false_detection_rate, frame_record, outlier_rate


def test_error_stats_by_hand():
    s = error_stats([1.0, -1.0, 2.0, np.nan])
    assert s["mae"] == pytest.approx(4 / 3) and s["rmse"] == pytest.approx(np.sqrt(2)) and s["n"] == 3
    assert s["p95"] == pytest.approx(np.percentile([1, 1, 2], 95))
    assert np.isnan(error_stats([np.nan])["rmse"])


def test_coverage_outliers_false_detections():
    truth = np.array([10.0, 10.0, 10.0, np.nan, np.nan])
    pred = np.array([10.5, np.nan, 20.0, 7.0, np.nan])
    assert coverage(pred, truth) == pytest.approx(2 / 3)
    assert outlier_rate(pred, truth) == pytest.approx(1 / 2)
    assert false_detection_rate(pred, truth) == pytest.approx(1 / 2)
    assert np.isnan(coverage(pred, np.full(5, np.nan)))


def test_frame_record_keys_and_values():
    truth = np.array([[1.0, 2.0], [np.nan, 4.0]])
    pred = np.array([[1.0, 3.0], [5.0, np.nan]])
    rec = frame_record(pred, truth, depth_pred_mm=np.array([10.0, 20.0]), depth_true_mm=np.array([11.0, 20.0]))
    assert rec["px_mae"] == pytest.approx(0.5) and rec["coverage"] == pytest.approx(2 / 3)
    assert rec["false_detections"] == 1.0 and rec["n_lit"] == 3 and rec["n_detected"] == 3
    assert rec["depth_mae_mm"] == pytest.approx(0.5)
    assert np.isnan(frame_record(pred, truth)["depth_rmse_mm"])


def test_hit_rate_counts_misses_and_far_detections_as_misses():
    from bench.metrics import hit_rate

    truth = np.array([10.0, 10.0, 10.0, 10.0, np.nan])
    pred = np.array([12.9, 13.5, np.nan, 7.0, 3.0])  # hit, too far, missed, exactly 3 px (hit), unlit row
    assert hit_rate(pred, truth) == pytest.approx(2 / 4)
    assert hit_rate(pred, truth, tol_px=4.0) == pytest.approx(3 / 4)
    assert np.isnan(hit_rate(pred, np.full(5, np.nan)))
    assert frame_record(pred, truth)["hit_rate"] == pytest.approx(0.5)
