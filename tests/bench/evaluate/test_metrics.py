import numpy as np
import pytest

from bench.evaluate.metrics import coverage, error_stats, false_detection_rate, false_lock_rate, frame_record, outlier_rate


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
    from bench.evaluate.metrics import hit_rate

    truth = np.array([10.0, 10.0, 10.0, 10.0, np.nan])
    pred = np.array([12.9, 13.5, np.nan, 7.0, 3.0])  # hit, too far, missed, exactly 3 px (hit), unlit row
    assert hit_rate(pred, truth) == pytest.approx(2 / 4)
    assert hit_rate(pred, truth, tol_px=4.0) == pytest.approx(3 / 4)
    assert np.isnan(hit_rate(pred, np.full(5, np.nan)))
    assert frame_record(pred, truth)["hit_rate"] == pytest.approx(0.5)
def test_false_lock_rate_by_hand():
    # rows: on the truth | on a false stripe | near both | off both | nothing reported | false, no truth
    pred = np.array([10.0, 40.0, 21.0, 70.0, np.nan, 52.0])
    truth = np.array([10.0, 20.0, 20.0, 20.0, 20.0, np.nan])
    false_cols = np.array([[35.0, np.nan], [38.0, 90.0], [23.0, np.nan], [60.0, np.nan], [20.0, np.nan],
                           [50.0, 54.0]])
    # detected rows 0, 1, 2, 3, 5 (5 rows); locked on a false stripe: row 1 (|40-38| = 2) and row 5
    assert false_lock_rate(pred, false_cols, truth) == pytest.approx(2 / 5)
    # at 1.5 px neither row 1 (|40-38| = 2) nor row 5 (|52-50| = |52-54| = 2) is near its false stripe
    assert false_lock_rate(pred, false_cols, truth, tol_px=1.5) == 0.0
    # a wider one: row 3 (|70-60| = 10) joins, row 2 stays excluded by its truth
    assert false_lock_rate(pred, false_cols, truth, tol_px=10.0) == pytest.approx(3 / 5)


def test_false_lock_rate_shapes_and_edges():
    # frames x rows, K = 0: no false stripe anywhere
    assert false_lock_rate(np.ones((2, 3)), np.zeros((2, 3, 0)), np.ones((2, 3))) == 0.0
    assert np.isnan(false_lock_rate([np.nan, np.nan], [[1.0], [2.0]], [1.0, 2.0]))
    with pytest.raises(ValueError, match="`tol_px` must be > 0, got 0"):
        false_lock_rate([1.0], [[1.0]], [1.0], tol_px=0)
    with pytest.raises(ValueError, match="`false_cols` must have shape"):
        false_lock_rate([1.0, 2.0], [[1.0]], [1.0, 2.0])


def test_docstring_examples_run():
    import doctest
    import importlib

    module = importlib.import_module("bench.evaluate.metrics")
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_frame_record_false_lock_rate_needs_false_stripe_truth():
    truth = np.array([[10.0, 10.0, np.nan]])
    pred = np.array([[10.0, 40.0, 41.0]])
    false_cols = np.array([[[np.nan], [40.0], [42.0]]])
    assert frame_record(pred, truth, false_cols=false_cols)["false_lock_rate"] == pytest.approx(2 / 3)
    assert np.isnan(frame_record(pred, truth)["false_lock_rate"])


def test_every_hit_rate_of_the_harness_uses_the_one_hit_rule():
    from bench.evaluate.metrics import HIT_PX, hit_rate, hits
    from bench.evaluate.simreal import image_metrics
    from bench.evaluate.outcomes import truth_states
    from bench.studies.tuning import TuningFrame, frame_counts

    rng = np.random.default_rng(5)
    truth = rng.uniform(0, 100, 400)
    truth[rng.random(400) < 0.1] = np.nan
    pred = truth + rng.choice([-HIT_PX, HIT_PX, -3.5, 2.0, 0.0, np.nan], 400)  # exactly HIT_PX away is a hit
    want = hits(pred, truth)[~np.isnan(truth)].mean()
    assert hit_rate(pred, truth) == pytest.approx(want)
    assert image_metrics(pred, truth)["hit_rate"] == pytest.approx(want)
    frame = TuningFrame("renders", "f", "k", np.zeros((400, 1)), None, truth, truth_states(truth))
    counts = frame_counts(pred, frame, HIT_PX)  # the tuning procedures' row outcomes: hits first
    assert counts[0] / (~np.isnan(truth)).sum() == pytest.approx(want)
    assert 0.3 < want < 0.9
