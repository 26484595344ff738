"""The DP trackers' reporting rule on a path's row readings (``dp4``, ``dp8``, ``dp8_subpixel``, ``dp_gap``).

The solver (:mod:`trackers._dp_kernels`) finds the path and :mod:`trackers._dp_rows` reads each row of it; this
rule decides which rows are reported. :class:`trackers.dp.DPTracker` calls it as ``_reporting_rule``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["reporting_rule"]


def reporting_rule(image, contrast, side_sd, span, tracker, ask=None):
    """The reporting rule of the DP trackers (and ``dp_gap``) on a path's row readings.

    ``contrast`` and ``side_sd`` (H,) are each row's contrast of the path's column and the
    spread of its sides, ``span`` (H,) the columns the path walks in the row. A row
    *supports* the path when its contrast is above ``tracker.k_sigma`` times the frame's
    median side spread; too few supporting rows (``tracker.min_support``) mean no stripe
    (None). Otherwise the rows from the first to the last supporting one are reported,
    less gaps of unsupported rows longer than ``tracker.max_gap``, less stretches (runs of
    reported rows) with fewer than ``tracker.min_run`` supporting rows, and less rows
    walking more than ``tracker.max_walk`` columns. Returns ``(z, support, report)``, all (H,).

    ``ask`` (the stripe question, None: not asked) maps the supporting rows (H,) bool to the rows
    whose peak is a stripe: a supporting row it says no to neither supports the path nor is
    reported (it stood out, and not as a stripe); the unsupported rows are bridged as before.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> rule = SimpleNamespace(k_sigma=5.0, min_support=0.0, max_gap=2, min_run=1, max_walk=None)
    >>> contrast = np.array([90.0, 90, 1, 90, 1, 1, 1, 90, 90])       # a gap of one row, then one of three
    >>> z, support, report = reporting_rule(np.zeros((9, 4)) + np.arange(4), contrast, np.ones(9),
    ...                                     np.zeros(9, int), rule)
    >>> report.astype(int).tolist()
    [1, 1, 1, 1, 0, 0, 0, 1, 1]
    """
    H = image.shape[0]
    vmax = float(image.max())
    vmin = float(image.min())
    finite_sd = side_sd[np.isfinite(side_sd)]
    s = float(np.median(finite_sd)) if finite_sd.size else 0.0
    s = max(s, 1e-3 * (vmax - vmin), np.finfo(np.float64).tiny)
    z = contrast / s
    support = z > tracker.k_sigma
    veto = None
    if ask is not None and support.any():
        veto = support & ~ask(support)
        support = support & ~veto
    if int(np.count_nonzero(support)) < max(3, tracker.min_support * H):
        return None
    first = int(np.argmax(support))
    last = H - 1 - int(np.argmax(support[::-1]))
    report = np.zeros(H, dtype=bool)
    report[first : last + 1] = True
    if tracker.max_gap is not None:
        gap_start = None
        for r in range(first, last + 1):
            if not support[r]:
                if gap_start is None:
                    gap_start = r
            elif gap_start is not None:
                if r - gap_start > tracker.max_gap:
                    report[gap_start:r] = False
                gap_start = None
    run = min(tracker.min_run, len(report))  # a frame shorter than min_run needs support on every row
    if run > 1:
        edges = np.flatnonzero(np.diff(np.r_[0, report.astype(np.int8), 0]))
        for a, b in zip(edges[::2], edges[1::2]):  # each stretch report[a:b]
            if int(np.count_nonzero(support[a:b])) < run:
                report[a:b] = False
    if tracker.max_walk is not None:
        report &= span <= tracker.max_walk
    if veto is not None:
        report &= ~veto
    return z, support, report
