"""Detection figures that rank or resample the row outcomes: a frame's record with its AP, precision-recall
curves and average precision over the tracker's per-row scores, and bootstrap intervals over frames.

The row outcomes and their counts are :mod:`bench.evaluate.outcomes`' (the scoring rules' one home); this module
orders and resamples them. Pure functions: arrays in, numbers out.
"""

from __future__ import annotations

import math

import numpy as np

from bench.evaluate.outcomes import (COUNT_KEYS, FALSE, FIGURE_KEYS, HIT, HIT_PX, MISSED, OUTCOMES,  # noqa: F401
                                     QUIET, WRONG, detection_figures, outcome_counts, row_outcomes)

__all__ = ["outcome_record", "pr_curve", "average_precision", "bootstrap_frames"]


def outcome_record(pred, truth, state=None, score=None, tol_px: float = HIT_PX) -> dict:
    """One frame's (or photograph's) detection record: the outcome counts (:data:`COUNT_KEYS`),
    their figures (:data:`FIGURE_KEYS`), ``ap`` (of ``score`` over the rows; NaN without one)
    and ``ap_constant``. The one definition every metric record uses.

    Parameters
    ----------
    pred, truth : array_like (H,)
        Reported and true columns (NaN: none), px.
    state : array_like (H,), optional
        Row states (:func:`row_outcomes`; default from ``truth``).
    score : array_like (H,), optional
        The tracker's per-row score (only reported rows count).
    tol_px : float

    Examples
    --------
    >>> r = outcome_record([10.0, np.nan, 7.0], [10.5, 4.0, np.nan], score=[2.0, 0.0, 1.0])
    >>> r["n_hit"], r["n_missed"], r["n_false"], r["ap"]
    (1, 1, 1, 0.5)
    """
    pred = np.asarray(pred, dtype=np.float64)
    codes = row_outcomes(pred, truth, state, tol_px)
    counts = outcome_counts(codes)
    rec = {**counts, **detection_figures(counts)}
    if score is None:
        rec.update(ap=float("nan"), ap_constant=False)
    else:
        ap = average_precision(np.where(np.isnan(pred), np.nan, np.asarray(score, dtype=np.float64)), codes)
        rec.update(ap=ap["ap"], ap_constant=bool(ap["constant"]))
    return rec


def _ranked(scores, codes):
    """The reported rows of known state, by score, best first: ``(scores, is_hit)`` and the
    number of stripe rows."""
    s = np.asarray(scores, dtype=np.float64).ravel()
    c = np.asarray(codes).ravel()
    if s.shape != c.shape:
        raise ValueError(f"`scores` and `codes` must have one size, got {s.size} and {c.size}")
    n_pos = int(np.count_nonzero((c == HIT) | (c == WRONG) | (c == MISSED)))
    ranked = (c == HIT) | (c == WRONG) | (c == FALSE)
    s = s[ranked]
    tp = c[ranked] == HIT
    if np.isinf(s).any():
        raise ValueError("`scores` must be finite where a column is reported, got an infinite score")
    return s, tp, n_pos


def pr_curve(scores, codes) -> dict:
    """The precision-recall curve over rows, reports ranked by score.

    A report is a true positive when it is a hit and a false positive when it is wrong
    or false; the positives are the stripe rows (a missed row is never retrieved, so
    recall ends at the hit rate). Tied scores form one threshold (as
    :func:`sklearn.metrics.precision_recall_curve`). Reports with a NaN score (a
    tracker or submission that gives none) all tie below every finite score.

    Parameters
    ----------
    scores : array_like, float
        The tracker's per-row score (higher is more confident), any shape.
    codes : array_like, int
        :func:`row_outcomes` of the same rows.

    Returns
    -------
    dict
        ``recall``, ``precision``, ``threshold`` (arrays, one entry per distinct score,
        best first), ``n_pos`` (stripe rows), ``constant`` (True when every report has
        the same score, or there is none: a single operating point).

    Examples
    --------
    >>> c = pr_curve([3.0, 2.0, 2.0, 1.0], [HIT, HIT, FALSE, HIT])
    >>> c["recall"].tolist(), c["precision"].tolist()
    ([0.3333333333333333, 0.6666666666666666, 1.0], [1.0, 0.6666666666666666, 0.75])
    """
    s, tp, n_pos = _ranked(scores, codes)
    nan = np.isnan(s)
    key = np.where(nan, -np.inf, s)
    order = np.argsort(-key, kind="stable")
    key = key[order]
    tp = tp[order]
    ctp = np.cumsum(tp)
    cfp = np.cumsum(~tp)
    last = np.r_[np.flatnonzero(key[1:] != key[:-1]), key.size - 1] if key.size else np.zeros(0, np.intp)
    tps = ctp[last].astype(np.float64)
    fps = cfp[last].astype(np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        precision = tps / (tps + fps)
        recall = tps / n_pos if n_pos else np.full(tps.shape, np.nan)
    return {"recall": recall, "precision": precision, "threshold": key[last] if key.size else np.zeros(0),
            "n_pos": n_pos, "constant": bool(last.size <= 1)}


def _ap_from_steps(recall, precision) -> float:
    """All-point interpolated AP (PASCAL VOC 2010+, COCO): the area under the precision
    envelope ``max_{r' >= r} P(r')``, from recall 0."""
    if recall.size == 0:
        return 0.0
    env = np.maximum.accumulate(precision[::-1])[::-1]
    dr = np.diff(np.r_[0.0, recall])
    return float(np.sum(dr * env))


def average_precision(scores, codes) -> dict:
    """Average precision of a tracker's reports over rows (all-point interpolation).

    Reports are ranked by ``scores`` (:func:`pr_curve`); AP is the area under the
    interpolated precision-recall curve from recall 0 to the tracker's last report,
    ``sum_k (R_k - R_{k-1}) max_{j >= k} P_j`` as in PASCAL VOC (2010 on) and COCO. A
    stripe row that is never reported adds nothing, so AP <= the hit rate. Where every
    report has the same score the curve is one point and AP = recall x precision of
    that single operating point (``constant`` says so).

    Parameters
    ----------
    scores : array_like, float
        Per-row scores, higher is more confident (finite where reported; NaN scores
        rank last, all tied).
    codes : array_like, int
        :func:`row_outcomes` of the same rows.

    Returns
    -------
    dict
        ``ap`` (NaN when there is no stripe row), ``constant`` (bool), ``n_pos``,
        ``n_reports``.

    Examples
    --------
    >>> average_precision([3.0, 2.0, 2.0, 1.0], [HIT, HIT, FALSE, HIT])["ap"]
    0.8333333333333333
    >>> r = average_precision([5.0, 5.0, np.nan], [HIT, FALSE, MISSED])
    >>> r["ap"], r["constant"]
    (0.25, True)
    """
    c = pr_curve(scores, codes)
    n_rep = int(np.count_nonzero(np.isin(np.asarray(codes), (HIT, WRONG, FALSE))))
    if not c["n_pos"]:
        return {"ap": float("nan"), "constant": c["constant"], "n_pos": 0, "n_reports": n_rep}
    return {"ap": _ap_from_steps(c["recall"], c["precision"]), "constant": c["constant"], "n_pos": c["n_pos"],
            "n_reports": n_rep}


def bootstrap_frames(codes, scores=None, *, n_boot: int = 1000, seed: int = 0, level: float = 0.95) -> dict:
    """Detection figures and AP of a set of frames, with percentile bootstrap intervals over frames.

    Frames (or photographs) are resampled with replacement (``numpy.random.default_rng(seed)``);
    each resample pools its frames' rows, so a frame drawn twice counts twice.

    Parameters
    ----------
    codes : sequence of array_like, or array_like (F, H)
        :func:`row_outcomes` of each frame (frames may differ in height).
    scores : like ``codes``, optional
        The per-row scores; without them AP is not computed.
    n_boot : int
        Resamples, >= 1.
    seed : int
    level : float
        Interval coverage in (0, 1).

    Returns
    -------
    dict
        For each of ``precision, recall, f1, false_report_rate`` (and ``ap`` with
        scores): the value on all frames and ``<key>_lo``, ``<key>_hi``; the pooled
        counts (``n_hit`` ...), ``n_frames``, ``ap_constant`` (with scores). Intervals
        are NaN with fewer than 2 frames.

    Examples
    --------
    >>> fr = [np.array([HIT, HIT, QUIET]), np.array([HIT, FALSE, MISSED])]
    >>> r = bootstrap_frames(fr, n_boot=200, seed=1)
    >>> r["recall"], r["false_report_rate"], r["n_frames"], r["recall_lo"] <= r["recall"] <= r["recall_hi"]
    (0.75, 0.5, 2, True)
    """
    if isinstance(n_boot, bool) or not isinstance(n_boot, (int, np.integer)) or n_boot < 1:
        raise ValueError(f"`n_boot` must be an integer >= 1, got {n_boot!r}")
    if not (isinstance(level, float) and 0 < level < 1):
        raise ValueError(f"`level` must be a float in (0, 1), got {level!r}")
    frames = [np.asarray(c).ravel() for c in codes]
    F = len(frames)
    counts = np.array([np.bincount(c.astype(np.intp), minlength=len(OUTCOMES)) for c in frames],
                      dtype=np.int64).reshape(F, len(OUTCOMES))
    total = counts.sum(axis=0)
    out: dict = {k: int(v) for k, v in zip(COUNT_KEYS, total)}
    out["n_frames"] = F
    fig = detection_figures(total)
    keys = list(FIGURE_KEYS)
    if scores is not None:
        svals = [np.asarray(s, dtype=np.float64).ravel() for s in scores]
        if len(svals) != F or any(a.size != b.size for a, b in zip(svals, frames)):
            raise ValueError("`scores` must have one array per frame, each the size of its `codes`")
        allc = np.concatenate(frames) if F else np.zeros(0, np.int8)
        alls = np.concatenate(svals) if F else np.zeros(0)
        ap = average_precision(alls, allc)
        fig["ap"] = ap["ap"]
        out["ap_constant"] = ap["constant"]
        keys.append("ap")
    out.update(fig)
    a = (1.0 - level) / 2.0
    if F < 2:
        for k in keys:
            out[f"{k}_lo"] = out[f"{k}_hi"] = float("nan")
        return out
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, F, size=(n_boot, F))
    weights = np.stack([np.bincount(d, minlength=F) for d in draws])  # (n_boot, F) times each frame is drawn
    boot_counts = weights @ counts  # (n_boot, 6)
    h, w, m, f, q = (boot_counts[:, k].astype(np.float64) for k in range(5))
    with np.errstate(invalid="ignore", divide="ignore"):
        boots = {"precision": h / (h + w + f), "recall": h / (h + w + m), "f1": 2 * h / (2 * h + 2 * w + f + m),
                 "false_report_rate": f / (f + q)}
    if scores is not None:
        boots["ap"] = _bootstrap_ap(frames, svals, weights)
    for k in keys:
        b = boots[k][np.isfinite(boots[k])]
        lo, hi = (np.quantile(b, [a, 1 - a]) if b.size and math.isfinite(out[k]) else (np.nan, np.nan))
        out[f"{k}_lo"], out[f"{k}_hi"] = float(lo), float(hi)
    return out


def _bootstrap_ap(frames, scores, weights) -> np.ndarray:
    """AP of each resample (rows weighted by their frame's draw count): one ranking of all reports,
    then a compiled pass per resample (:func:`bench.evaluate._ap_kernel.ap_resamples`)."""
    from bench.evaluate._ap_kernel import ap_resamples

    frame_of = np.concatenate([np.full(c.size, i, dtype=np.int64) for i, c in enumerate(frames)])
    c = np.concatenate(frames)
    s = np.concatenate(scores)
    pos_rows = np.isin(c, (HIT, WRONG, MISSED))
    n_pos = weights @ np.bincount(frame_of[pos_rows], minlength=len(frames))  # (n_boot,)
    ranked = np.isin(c, (HIT, WRONG, FALSE))
    key = np.where(np.isnan(s[ranked]), -np.inf, s[ranked])
    order = np.argsort(-key, kind="stable")
    key = key[order]
    tp = (c[ranked] == HIT)[order]
    fr = frame_of[ranked][order]
    out = np.full(weights.shape[0], np.nan)
    if key.size == 0:
        out[n_pos > 0] = 0.0
        return out
    last = np.zeros(key.size, dtype=np.bool_)
    last[np.r_[np.flatnonzero(key[1:] != key[:-1]), key.size - 1]] = True
    ap_resamples(np.ascontiguousarray(weights, dtype=np.int64), fr, tp, last, np.asarray(n_pos, dtype=np.int64), out)
    return out
