"""The DP trackers' stages one at a time: thin public entry points to their numba kernels.

For every frame a DP tracker (``dp4``, ``dp8``: :class:`trackers.dp.DPTracker`; ``dp_gap``:
:class:`trackers.dp_gap.DPGapTracker`) runs, in turn:

1. :func:`half_costs` - the half node costs ``0.5 / (max(I, 0) + eps)`` and each row's least one;
2. :func:`distance_field` - every node's least path cost from the top row (``dp4``, ``dp8``), or
   :func:`gap_fields` - the same with ``dp_gap``'s off state;
3. :func:`optimal_nodes` - the labelled union of all optimal paths (:func:`backtrack`: one of them;
   :func:`labelled_nodes`: steps 1 to 3 as a tracker runs them);
4. :func:`row_readings` - each row's column, contrast, side spread and span from those nodes;
5. :func:`reporting_rule` - which rows support the path and which are reported.

Each function calls the kernel the trackers call (``trackers._dp_kernels``, ``trackers._dp_gap``,
``trackers._dp_rows``) on the caller's arrays, without validation or copies, and takes output
arrays to fill again: a profile of one stage times its kernel (``scripts/dp_profile.py``) and a
check of the kernels sees what the trackers compute (``scripts/dp_kernel_identity.py``). The
inputs must be what the trackers pass: a frame as :meth:`trackers.dp.DPTracker.readings` returns
it (C-contiguous, ``uint8`` or ``float64``, finite), C-contiguous ``float64`` cost arrays and
``int64`` indices. For validated solvers use :func:`trackers.dp.shortest_path`,
:func:`trackers.dp.accumulated_cost` and :func:`trackers.dp_gap.gap_nodes`.

Examples
--------
>>> import trackers
>>> frame = np.zeros((4, 9), np.uint8)
>>> frame[:, 4] = 200
>>> hc, rowmin, left, right = half_costs(frame)
>>> D, sweeps = distance_field(hc, rowmin, left, connectivity=8, right=right)
>>> mark, rows, cols = optimal_nodes(D, hc, connectivity=8)
>>> sorted(set(cols.tolist()))
[4]
>>> col, contrast, side_sd, span = row_readings(frame, mark, rows, cols)
>>> col.tolist(), contrast.tolist(), span.tolist()
([4.0, 4.0, 4.0, 4.0], [200.0, 200.0, 200.0, 200.0], [1, 1, 1, 1])
"""

from __future__ import annotations

import numpy as np

from . import _dp_gap as G
from . import _dp_kernels as K
from . import _dp_rows as R
from .dp import _TIE_TOL, ROW_RULES, _check_connectivity, _half_cost, _reporting_rule

__all__ = ["TIE_TOL", "ROW_RULES", "half_costs", "distance_field", "optimal_nodes", "backtrack", "gap_fields",
           "labelled_nodes", "row_readings", "reporting_rule"]

#: Relative tolerance within which two path costs tie (of the optimum), as the trackers label.
TIE_TOL = _TIE_TOL


def half_costs(image: np.ndarray, eps: float = 1.0, out: np.ndarray | None = None):
    """Half node costs of a frame and each row's least one (stage 1).

    Parameters
    ----------
    image : ndarray of uint8 or float64, shape (H, W)
        The frame the DP sees (image units), C-contiguous and finite.
    eps : float, default 1.0
        Node-cost offset in image units, > 0.
    out : ndarray of float64, shape (H, W), optional
        Filled with the half costs and returned (a new array if omitted).

    Returns
    -------
    hc : ndarray of float64, shape (H, W)
        ``0.5 / (max(I, 0) + eps)`` (1 / image units).
    rowmin : ndarray of float64, shape (H,)
        Each row's least half cost (its brightest pixel's).
    left, right : ndarray of int64, shape (H,)
        The leftmost and the rightmost column holding it.
    """
    return _half_cost(image, eps, out)


def distance_field(hc, rowmin, left, connectivity: int = 4, h_weight: float = 1.0, *, right=None,
                   exact: bool = False, out: np.ndarray | None = None):
    """Every node's least path cost from the top row, as ``dp4``/``dp8`` compute it (stage 2).

    Parameters
    ----------
    hc : ndarray of float64, shape (H, W)
        Half node costs, > 0 (:func:`half_costs`).
    rowmin, left : ndarray, shape (H,)
        Each row's least half cost (float64) and its leftmost column (int64).
    connectivity : {4, 8}, default 4
    h_weight : float, default 1.0
        Weight of a horizontal edge, finite and > 0 (see :func:`trackers.dp.shortest_path`).
    right : ndarray of int64, shape (H,), optional
        Each row's rightmost column holding ``rowmin`` (computed if omitted; same result).
    exact : bool, default False
        False: only nodes that can lie on an optimal path are exact, every other value is the
        cost of a real path or +inf (the trackers' field). True: every node is exact.
    out : ndarray of float64, shape (H, W), optional
        Filled and returned (a new array if omitted).

    Returns
    -------
    D : ndarray of float64, shape (H, W)
        Path costs in node-cost units (1 / image units; the top row 0).
    sweeps : int
        The row sweeps the solver ran (``trackers._dp_kernels.accumulate``).
    """
    D = np.empty_like(hc) if out is None else out
    conn8 = _check_connectivity(connectivity)
    if right is None:
        sweeps = K.accumulate(hc, conn8, not exact, D, rowmin, left, float(h_weight))
    else:
        sweeps = K.accumulate(hc, conn8, not exact, D, rowmin, left, float(h_weight), right)
    return D, int(sweeps)


def optimal_nodes(D, hc, connectivity: int = 4, h_weight: float = 1.0, *, tol: float = TIE_TOL, mark=None,
                  rows=None, cols=None):
    """Label every node on an optimal top-to-bottom path of a distance field (stage 3).

    Parameters
    ----------
    D : ndarray of float64, shape (H, W)
        The field of :func:`distance_field` (with the same ``hc``, connectivity and ``h_weight``).
    hc : ndarray of float64, shape (H, W)
    connectivity : {4, 8}, default 4
    h_weight : float, default 1.0
    tol : float, default :data:`TIE_TOL`
        Path costs within ``tol`` times the optimum tie.
    mark : ndarray of uint8, shape (H, W), optional
        Zeroed array to receive the labels (a new one if omitted).
    rows, cols : ndarray of int64, shape (H * W,), optional
        Work arrays for the labelled nodes (new ones if omitted).

    Returns
    -------
    mark : ndarray of uint8, shape (H, W)
        Bit 1 on every labelled node, bit 2 on those where an optimal path enters or leaves its
        row by a vertical or diagonal edge.
    rows, cols : ndarray of int64, shape (n,)
        The n labelled nodes, in no particular order (views of the work arrays).
    """
    H, W = hc.shape
    mark = np.zeros((H, W), np.uint8) if mark is None else mark
    rows = np.empty(H * W, np.int64) if rows is None else rows
    cols = np.empty(H * W, np.int64) if cols is None else cols
    n = K.optimal_nodes(D, hc, _check_connectivity(connectivity), float(tol), mark, rows, cols, float(h_weight))
    return mark, rows[:n], cols[:n]


def backtrack(D, hc, connectivity: int = 4, h_weight: float = 1.0):
    """One optimal path of a distance field, with :func:`trackers.dp.shortest_path`'s tie rule.

    Parameters
    ----------
    D, hc : ndarray of float64, shape (H, W)
        A field of :func:`distance_field` and its half costs.
    connectivity : {4, 8}, default 4
    h_weight : float, default 1.0

    Returns
    -------
    rows, cols : ndarray of int64, shape (n,)
        The path's pixels from the top row to the bottom row.
    """
    H, W = hc.shape
    rows = np.empty(H * W, np.int64)
    cols = np.empty(H * W, np.int64)
    n = K.backtrack(D, hc, _check_connectivity(connectivity), rows, cols, float(h_weight))
    if n < 0:  # pragma: no cover - would mean a bug in the kernels
        raise RuntimeError("backtracking did not reach the top row")
    return rows[:n][::-1].copy(), cols[:n][::-1].copy()


def gap_fields(hc, off_half, switch: float, connectivity: int = 8, h_weight: float = 1.0, *, out=None):
    """``dp_gap``'s least path costs from the top row, with an off node per row (stage 2).

    Parameters
    ----------
    hc : ndarray of float64, shape (H, W)
        Half node costs, > 0.
    off_half : ndarray of float64, shape (H,)
        Half costs of the rows' off nodes, > 0 (half the off cost of
        :meth:`trackers.dp_gap.DPGapTracker.off_costs`).
    switch : float
        Cost of leaving or entering the off state, >= 0.
    connectivity : {4, 8}, default 8
    h_weight : float, default 1.0
    out : ndarray of float64, shape (H, W), optional
        Filled with ``F`` and returned (a new array if omitted).

    Returns
    -------
    F : ndarray of float64, shape (H, W)
        The least cost of a path from row 0 to each pixel.
    Foff : ndarray of float64, shape (H,)
        The least cost of a path from row 0 to each row's off node.
    """
    F = np.empty(hc.shape) if out is None else out
    Foff = np.empty(hc.shape[0])
    G.sweep(hc, off_half, float(switch), _check_connectivity(connectivity), float(h_weight), F, Foff)
    return F, Foff


def labelled_nodes(tracker, frame):
    """Stages 1 to 3 as a DP tracker runs them: its labelled optimal-path nodes on a frame.

    Parameters
    ----------
    tracker : trackers.dp.DPTracker
        ``dp4``, ``dp8`` or ``dp_gap`` (:class:`trackers.dp_gap.DPGapTracker`), with its parameters.
    frame : ndarray of uint8 or float64, shape (H, W)
        The frame the DP sees (:meth:`trackers.dp.DPTracker.readings` returns it).

    Returns
    -------
    mark, rows, cols
        As :func:`optimal_nodes` returns them; :func:`row_readings` of them gives the tracker's
        readings.
    """
    from .dp_gap import DPGapTracker

    hw = float(tracker.h_weight)
    hc, rowmin, left, right = half_costs(frame, tracker.eps)
    if isinstance(tracker, DPGapTracker):
        H, W = hc.shape
        off, switch = tracker.off_costs(frame, rowmin)
        ho = np.full(H, 0.5 * off)
        conn8 = tracker.connectivity == 8
        F, Foff = gap_fields(hc, ho, switch, tracker.connectivity, hw)
        mark = np.zeros((H, W), np.uint8)
        off_opt = np.empty(H, np.bool_)
        rows = np.empty(H * W, np.int64)
        cols = np.empty(H * W, np.int64)
        n = G.label(hc, ho, switch, conn8, hw, F, Foff, TIE_TOL, mark, off_opt, rows, cols)
        return mark, rows[:n], cols[:n]
    D, _ = distance_field(hc, rowmin, left, tracker.connectivity, hw, right=right)
    return optimal_nodes(D, hc, tracker.connectivity, hw)


def row_readings(frame, mark, rows, cols, side_inner: int = 4, side_outer: int = 12, row_rule: str = "crossing",
                 *, out=None):
    """Each row's column, contrast, side spread and span from labelled nodes (stage 4).

    Parameters
    ----------
    frame : ndarray of uint8 or float64, shape (H, W)
        The frame the DP sees (image units).
    mark, rows, cols
        Labelled optimal-path nodes (:func:`optimal_nodes`, :func:`labelled_nodes`).
    side_inner, side_outer : int, default 4 and 12
        The background pixels' distance from the row's column, in columns (1 <= inner <= outer).
    row_rule : {"crossing", "mean", "brightest"}, default "crossing"
        Which column a row reports (see :class:`trackers.dp.DPTracker`).
    out : tuple of 4 ndarrays, optional
        ``(col, contrast, side_sd, span)`` to fill (float64 thrice, then int64; shape (H,)).

    Returns
    -------
    col : ndarray of float64, shape (H,)
        Each row's column (NaN where no node is labelled).
    contrast, side_sd : ndarray of float64, shape (H,)
        The intensity at that column over the mean of its side pixels, and their standard
        deviation (image units).
    span : ndarray of int64, shape (H,)
        Columns from the row's leftmost to its rightmost labelled node (0 if none).

    Notes
    -----
    The rules in full are those of ``trackers._dp_rows.marked_rows``.
    """
    if row_rule not in ROW_RULES:
        raise ValueError(f"`row_rule` must be one of {sorted(ROW_RULES)}, got {row_rule!r}")
    H = frame.shape[0]
    if out is None:
        out = (np.empty(H), np.empty(H), np.empty(H), np.empty(H, np.int64))
    R.marked_rows(frame, mark, rows, cols, int(side_inner), int(side_outer), ROW_RULES[row_rule], *out)
    return out


def reporting_rule(frame, contrast, side_sd, span, tracker):
    """The DP trackers' reporting rule on a frame's row readings (stage 5).

    Parameters
    ----------
    frame : ndarray, shape (H, W)
        The frame the DP sees.
    contrast, side_sd : ndarray of float64, shape (H,)
    span : ndarray of int64, shape (H,)
        As :func:`row_readings` gives them.
    tracker : trackers.dp.DPTracker
        Whose ``k_sigma``, ``min_support``, ``max_gap``, ``min_run`` and ``max_walk`` apply.

    Returns
    -------
    None or (z, support, report)
        None when too few rows support the path (the frame has no stripe); else each row's
        contrast in noise units (float64) and whether it supports the path and is reported
        (bool), all shape (H,). See :class:`trackers.dp.DPTracker`.
    """
    return _reporting_rule(frame, contrast, side_sd, span, tracker)
