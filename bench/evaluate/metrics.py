"""Accuracy metrics: pure functions on arrays.

Conventions: ``pred`` and ``truth`` are stripe columns (px) over any grid of
rows (e.g. frames x rows), NaN where the tracker reports nothing / where no
lit visible stripe exists. Depths are in mm.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.outcomes import HIT_PX, hits
from bench.evaluate.ranking import outcome_record

__all__ = ["error_stats", "coverage", "hit_rate", "outlier_rate", "false_detection_rate", "false_lock_rate",
           "frame_record", "hits", "OUTLIER_PX", "HIT_PX"]

OUTLIER_PX = HIT_PX  # a detection further than this from the truth is an outlier (a "wrong" row outcome)


def error_stats(errors) -> dict[str, float]:
    """MAE, RMSE and 95th percentile of ``|errors|`` (NaNs ignored); NaN if none.

    Examples
    --------
    >>> error_stats([3.0, -4.0])["rmse"]
    3.5355339059327378
    """
    e = np.abs(np.asarray(errors, dtype=np.float64))
    e = e[~np.isnan(e)]
    if e.size == 0:
        return {"mae": np.nan, "rmse": np.nan, "p95": np.nan, "n": 0}
    return {"mae": float(e.mean()), "rmse": float(np.sqrt(np.mean(e * e))), "p95": float(np.percentile(e, 95)),
            "n": int(e.size)}


def coverage(pred, truth) -> float:
    """Rows with a detection among the rows with a lit visible stripe (NaN if none)."""
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    lit = ~np.isnan(truth)
    n = int(lit.sum())
    return float(np.count_nonzero(~np.isnan(pred[lit])) / n) if n else float("nan")


def hit_rate(pred, truth, tol_px: float = HIT_PX) -> float:
    """Among rows with a lit visible stripe, the fraction where the tracker reports a
    column within ``tol_px`` of the truth (a row with no detection is a miss); NaN if none.

    Examples
    --------
    >>> hit_rate([10.0, 20.0, np.nan, 5.0], [11.0, 30.0, 7.0, np.nan])
    0.3333333333333333
    """
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    lit = ~np.isnan(truth)
    n = int(lit.sum())
    if not n:
        return float("nan")
    return float(np.count_nonzero(hits(pred[lit], truth[lit], tol_px)) / n)


def outlier_rate(pred, truth, threshold_px: float = OUTLIER_PX) -> float:
    """Among rows with both a detection and a stripe, the fraction off by more than ``threshold_px``."""
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    both = ~np.isnan(pred) & ~np.isnan(truth)
    n = int(both.sum())
    return float(np.count_nonzero(~hits(pred[both], truth[both], threshold_px)) / n) if n else float("nan")


def false_detection_rate(pred, truth) -> float:
    """Among rows with no stripe, the fraction where the tracker reports one (NaN if none)."""
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    dark = np.isnan(truth)
    n = int(dark.sum())
    return float(np.count_nonzero(~np.isnan(pred[dark])) / n) if n else float("nan")


def false_lock_rate(pred, false_cols, truth, tol_px: float = OUTLIER_PX) -> float:
    """Among rows with a detection, the fraction locked onto a false stripe (NaN if none).

    A row counts when its detection lies within ``tol_px`` of one of the row's false-stripe columns
    and not within ``tol_px`` of the truth (rows without a truth column count as "not within").

    Parameters
    ----------
    pred : array_like (...,)
        Tracked columns (px), NaN where nothing is reported.
    false_cols : array_like (..., K)
        The false-stripe columns of each row (px), NaN-padded
        (:attr:`scenes.Truth.false_columns`); ``K`` may be 0.
    truth : array_like (...,)
        True columns (px), NaN where there is no lit visible stripe.
    tol_px : float
        Match distance (px), > 0.

    Returns
    -------
    float

    Examples
    --------
    >>> false_lock_rate([10.0, 40.0, np.nan], [[40.0], [41.0], [5.0]], [10.0, 20.0, 30.0])
    0.5
    """
    tol = float(tol_px)
    if not tol > 0:
        raise ValueError(f"`tol_px` must be > 0, got {tol_px!r}")
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    false_cols = np.asarray(false_cols, dtype=np.float64)
    if false_cols.shape[:-1] != pred.shape or truth.shape != pred.shape:
        raise ValueError(f"`false_cols` must have shape {pred.shape} + (K,) and `truth` {pred.shape}, got "
                         f"{false_cols.shape} and {truth.shape}")
    detected = ~np.isnan(pred)
    n = int(detected.sum())
    if not n:
        return float("nan")
    near_false = np.any(hits(false_cols, pred[..., None], tol), axis=-1)
    near_truth = hits(pred, truth, tol)
    return float(np.count_nonzero(detected & near_false & ~near_truth) / n)


def frame_record(pred, truth, depth_pred_mm=None, depth_true_mm=None, false_cols=None, *, state=None,
                 score=None) -> dict[str, float]:
    """Every metric of one tracker on one grid of rows, as a flat dict.

    Keys: ``px_mae, px_rmse, px_p95, depth_mae_mm, depth_rmse_mm, depth_p95_mm,
    coverage, hit_rate, false_lock_rate, outlier_rate, false_detections, n_rows, n_lit, n_detected``
    (``false_lock_rate`` NaN when no ``false_cols`` are given: no false-stripe truth), then the
    row outcomes (:mod:`bench.evaluate.outcomes`): ``n_hit, n_wrong, n_missed, n_false, n_quiet,
    n_unknown, precision, recall, f1, false_report_rate``, ``ap`` (the average precision of
    ``score`` over the rows; NaN without one) and ``ap_constant`` (every report has one score).
    ``state`` gives the rows' states (default: exact truth, NaN = no stripe); ``n_false`` is the
    number of false 3-D points (reports on stripe-less rows).
    """
    pred = np.asarray(pred, dtype=np.float64)
    truth = np.asarray(truth, dtype=np.float64)
    px = error_stats(pred - truth)
    rec = {"px_mae": px["mae"], "px_rmse": px["rmse"], "px_p95": px["p95"]}
    if depth_pred_mm is not None and depth_true_mm is not None:
        d = error_stats(np.asarray(depth_pred_mm, float) - np.asarray(depth_true_mm, float))
    else:
        d = {"mae": np.nan, "rmse": np.nan, "p95": np.nan}
    rec.update(depth_mae_mm=d["mae"], depth_rmse_mm=d["rmse"], depth_p95_mm=d["p95"])
    rec.update(
        coverage=coverage(pred, truth),
        hit_rate=hit_rate(pred, truth),
        false_lock_rate=false_lock_rate(pred, false_cols, truth) if false_cols is not None else float("nan"),
        outlier_rate=outlier_rate(pred, truth),
        false_detections=false_detection_rate(pred, truth),
        n_rows=int(truth.size),
        n_lit=int(np.count_nonzero(~np.isnan(truth))),
        n_detected=int(np.count_nonzero(~np.isnan(pred))),
    )
    rec.update(outcome_record(pred, truth, state, score))
    return rec
