"""``dp_gap``: the paper's minimum-cost path, allowed to say "no stripe here" in a row.

The DP trackers (:mod:`trackers.dp`) cross every row: where there is no
stripe (a mirror that sends the laser away, rows beyond the object's
silhouette, the edges of a wall in range) the path bridges with columns the
stripe never had, and a stripe that jumps far sideways (a depth
discontinuity) costs it a long walk across the dark. ``dp_gap`` adds to the
paper's graph one *off* node per row: a row may be absent, at a cost per
row, and entering or leaving the off state costs a switch cost; after an
absence the path may resume at any column. Rows the optimal path spends off
are reported as NaN.

Public functions
----------------
- :func:`gap_path` - one optimal path of a cost array (tie rule documented).
- :func:`gap_nodes` - the union of all optimal paths (what the tracker uses).

Tracker ``dp_gap`` (:class:`DPGapTracker`). The kernels and the exactness
argument are in ``trackers._dp_gap``.
"""

from __future__ import annotations

from math import gcd

import numpy as np

from . import _dp_gap as G
from ._params import Choice, Real, check_real
from ._validation import check_image
from .dp import (_TIE_TOL, DEFAULT_H_WEIGHT, PAPER_REPORT, DPTracker, _check_connectivity, _check_cost,
                 _check_h_weight, _half_cost, _marked_readings, _work_arrays)

__all__ = ["gap_path", "gap_nodes", "DPGapTracker", "DEFAULT_OFF_REL", "DEFAULT_SWITCH_ROWS", "DEFAULT_LEVEL_QUANTILE"]

#: ``dp_gap``'s default off level, as a fraction of the way from the frame's
#: background to its typical row maximum (chosen by ``stripebench tune dp_gap``, stage 1: the mean
#: over renders, synthetic frames and photographs of F1 over rows).
DEFAULT_OFF_REL = 0.3
#: ``dp_gap``'s default switch cost, in rows of the off cost (chosen by
#: ``stripebench tune dp_gap``, stage 1).
DEFAULT_SWITCH_ROWS = 3.0
#: ``dp_gap``'s default quantile over rows of each row's brightest pixel that gives the stripe's typical
#: brightness (chosen by ``stripebench tune dp_gap``, stage 1).
DEFAULT_LEVEL_QUANTILE = 0.75


def _background(image: np.ndarray, samples: int = 2048) -> float:
    """Median of a deterministic sample of about ``samples`` pixels (stride coprime
    with the width, all pixels of small frames), in float64 image units."""
    flat = image.reshape(-1)
    step = max(1, flat.size // samples)
    while image.shape[1] > 1 and gcd(step, image.shape[1]) != 1:
        step += 1
    return float(np.median(flat[::step].astype(np.float64)))


def _check_off(off_cost, H: int) -> np.ndarray:
    oc = np.asarray(off_cost, dtype=np.float64)
    if oc.ndim == 0:
        oc = np.full(H, float(oc))
    if oc.shape != (H,):
        raise ValueError(f"`off_cost` must be a number or an array of shape ({H},), got shape {oc.shape}")
    if not (np.isfinite(oc).all() and (oc > 0).all()):
        raise ValueError(f"`off_cost` must be finite and > 0, got {off_cost!r}")
    return oc


def _check_switch(switch_cost) -> float:
    check_real("switch_cost", switch_cost, low=0)
    if not np.isfinite(switch_cost):
        raise ValueError(f"`switch_cost` must be finite, got {switch_cost!r}")
    return float(switch_cost)


def _fields(hc, ho, switch, conn8, hw, F=None):
    H, W = hc.shape
    F = np.empty((H, W)) if F is None else F
    Foff = np.empty(H)
    G.sweep(hc, ho, switch, conn8, hw, F, Foff)
    return F, Foff


def _labels(hc, ho, switch, conn8, hw, F=None):
    """The sweep and the labelling: ``(mark, off_opt, rows, cols, F, Foff)``
    (``F`` into the given array, if any)."""
    H, W = hc.shape
    F, Foff = _fields(hc, ho, switch, conn8, hw, F)
    mark = np.zeros((H, W), np.uint8)
    off_opt = np.empty(H, np.bool_)
    rows = np.empty(H * W, np.int64)
    cols = np.empty(H * W, np.int64)
    n = G.label(hc, ho, switch, conn8, hw, F, Foff, _TIE_TOL, mark, off_opt, rows, cols)
    return mark, off_opt, rows[:n], cols[:n], F, Foff


def _args(cost, off_cost, switch_cost, connectivity, h_weight):
    c = _check_cost(cost)
    oc = _check_off(off_cost, c.shape[0])
    return 0.5 * c, 0.5 * oc, _check_switch(switch_cost), _check_connectivity(connectivity), _check_h_weight(h_weight)


def gap_path(cost, off_cost, switch_cost=0.0, connectivity: int = 8, h_weight: float = 1.0):
    """One minimum-cost path from the top row to the bottom row that may be off in some rows.

    Parameters
    ----------
    cost : array_like, shape (H, W)
        Positive, finite node costs.
    off_cost : float or array_like, shape (H,)
        Node cost of each row's off node, finite and > 0 (a number: the same in every row).
    switch_cost : float, default 0.0
        Extra cost of each edge that leaves or enters the off state, finite and >= 0.
    connectivity : {4, 8}, default 8
    h_weight : float, default 1.0
        Weight of a horizontal edge (see :func:`trackers.dp.shortest_path`).

    Returns
    -------
    rows, cols : ndarray of int64, shape (n,)
        The path's pixels from top to bottom (several per row where it walks along one).
    off : ndarray of bool, shape (H,)
        The rows where the path is off.
    total_cost : float
        Sum of the path's edge costs: between pixels ``(c_p + c_q) / 2`` times 1 (vertical),
        ``h_weight`` (horizontal) or ``sqrt(1 + h_weight**2)`` (diagonal); between off nodes
        ``(o_r + o_{r+1}) / 2``; between a pixel and an off node ``(c_p + o_r) / 2 + switch_cost``.

    Notes
    -----
    The path never steps upwards. Ties (within a relative 1e-11) are broken by
    the rule of ``trackers._dp_gap.backtrack``: the bottom row's off node first,
    else its leftmost optimal pixel; backwards, a pixel's predecessor is the pixel
    above, above-left, above-right, the off node above, the left, the right
    neighbour, in that order; an off node's the off node above, then the
    leftmost pixel above.

    Examples
    --------
    >>> cost = np.array([[1., 9., 9.], [9., 9., 9.], [9., 9., 1.]])
    >>> rows, cols, off, total = gap_path(cost, off_cost=3.0, switch_cost=0.5)
    >>> cols.tolist(), off.tolist(), round(total, 6)
    ([0, 2], [False, True, False], 5.0)
    """
    hc, ho, s, conn8, hw = _args(cost, off_cost, switch_cost, connectivity, h_weight)
    H, W = hc.shape
    F, Foff = _fields(hc, ho, s, conn8, hw)
    rows = np.empty(H * W, np.int64)
    cols = np.empty(H * W, np.int64)
    off = np.empty(H, np.bool_)
    n = G.backtrack(hc, ho, s, conn8, hw, F, Foff, _TIE_TOL, rows, cols, off)
    if n < 0:  # pragma: no cover - would mean a bug in the kernels
        raise RuntimeError("backtracking did not reach the top row")
    return rows[:n][::-1].copy(), cols[:n][::-1].copy(), off, float(G.optimum(F, Foff))


def gap_nodes(cost, off_cost, switch_cost=0.0, connectivity: int = 8, h_weight: float = 1.0):
    """The union of all minimum-cost paths of :func:`gap_path` (same parameters).

    Returns
    -------
    on : ndarray of bool, shape (H, W)
        Pixels on an optimal path (within a relative 1e-11 of the optimum).
    crossing : ndarray of bool, shape (H, W)
        Those where an optimal path enters or leaves its row by a vertical or
        diagonal edge or through an off node.
    off : ndarray of bool, shape (H,)
        Rows where an optimal path is off.
    total_cost : float
        The optimum.
    """
    hc, ho, s, conn8, hw = _args(cost, off_cost, switch_cost, connectivity, h_weight)
    mark, off, _, _, F, Foff = _labels(hc, ho, s, conn8, hw)
    return (mark & 1).astype(bool), (mark & 2).astype(bool), off, float(G.optimum(F, Foff))


class DPGapTracker(DPTracker):
    """``dp_gap``: the minimum-cost path with an off state per row; NaN in the rows it leaves out.

    The graph is the DP trackers' (node cost ``1 / (max(I, 0) + eps)``,
    ``h_weight``, ``connectivity``) without upward edges, plus an off node
    per row (:func:`gap_path`). Its costs are set from the frame the DP sees
    (the frame, or ``image - background``, see :class:`~trackers.dp.DPTracker`):

    * the *off level* ``L_off = b + off_rel * (m - b)``, with ``b`` the
      frame's background (median of a fixed sample of about 2048 pixels) and ``m`` the
      ``level_quantile`` quantile over rows of each row's brightest pixel (the stripe's typical
      brightness: the median where most rows hold the stripe, a higher quantile where only
      some do, as in a stripe of dots or dashes or one that starts mid-frame); the off node costs what a
      pixel of that brightness costs, ``1 / (max(L_off, 0) + eps)``: a row
      whose reachable pixels are all dimmer than ``L_off`` is cheaper off;
    * the switch cost is ``switch_rows`` times that off cost, per edge that
      leaves or enters the off state: an absence costs two switches, so a dim
      stretch shorter than about ``2 * switch_rows`` rows' worth of the cost
      difference is still bridged, and a jump far sideways is taken through
      the off state when that is cheaper than the walk.

    The union of all optimal paths is labelled (independent of ties). A row
    is reported if an optimal path is on in it, with the DP trackers' row
    rule and support rule (the brightest crossing node; contrast in noise
    units; a frame with too few supporting rows reports nothing; rows above
    the first and below the last supporting row are not reported; ``max_gap``).
    Rows where every optimal path is off are NaN.

    Parameters
    ----------
    eps, k_sigma, min_support, max_gap, min_run, side_inner, side_outer, h_weight, use_background, row_rule, max_walk, stripe_test
        As for :class:`~trackers.dp.DPTracker` (a row on the path whose peak the stripe question says no to
        is off, as a row the path leaves out), except that ``k_sigma``, ``max_gap`` and ``min_run``
        default to the paper's bridging (:data:`trackers.dp.PAPER_REPORT`): the off state is
        what leaves rows out.
    connectivity : {4, 8}, default 8
    off_rel : float, default :data:`DEFAULT_OFF_REL`
        The off level's place between the background (0) and the typical row
        maximum (1), finite, in [0, 1].
    switch_rows : float, default :data:`DEFAULT_SWITCH_ROWS`
        Cost of leaving or entering the off state, in units of the off cost
        (rows spent off), finite and >= 0.
    level_quantile : float, default :data:`DEFAULT_LEVEL_QUANTILE`
        The quantile over rows of each row's brightest pixel that is the
        stripe's typical brightness ``m``, in [0, 1] (0.5: the median).

    Notes
    -----
    ``score`` is the DP contrast in noise units, as for the DP trackers.
    ``off_rel``, ``switch_rows`` and ``level_quantile`` were chosen by ``stripebench tune dp_gap``
    (``bench/config/profiles/tune_dp_gap.toml``) on scenes and a seed the paper
    experiment does not use.
    """

    name = "dp_gap"

    def __init__(self, eps=1.0, k_sigma=PAPER_REPORT["k_sigma"], min_support=0.05, max_gap=PAPER_REPORT["max_gap"],
                 side_inner=4, side_outer=12,
                 h_weight=DEFAULT_H_WEIGHT, use_background=True, connectivity=8, off_rel=DEFAULT_OFF_REL,
                 switch_rows=DEFAULT_SWITCH_ROWS, row_rule="crossing", max_walk=None,
                 min_run=PAPER_REPORT["min_run"], stripe_test=None, level_quantile=DEFAULT_LEVEL_QUANTILE):
        super().__init__(eps=eps, k_sigma=k_sigma, min_support=min_support, max_gap=max_gap,
                         side_inner=side_inner, side_outer=side_outer, h_weight=h_weight,
                         use_background=use_background, row_rule=row_rule, max_walk=max_walk, min_run=min_run,
                         stripe_test=stripe_test)
        self.connectivity = connectivity
        self.off_rel = off_rel
        self.switch_rows = switch_rows
        self.level_quantile = level_quantile

    parameter_constraints = {**DPTracker.parameter_constraints, "connectivity": Choice(frozenset({4, 8})),
                             "off_rel": Real(low=0, high=1), "switch_rows": Real(low=0),
                             "level_quantile": Real(low=0, high=1)}

    def off_costs(self, image: np.ndarray, rowmin: np.ndarray) -> tuple[float, float]:
        """The off node's cost and the switch cost for a frame.

        Parameters
        ----------
        image : ndarray, shape (H, W)
            The frame the DP sees (image units).
        rowmin : ndarray, shape (H,)
            Each row's least half node cost (its brightest pixel's).

        Returns
        -------
        off_cost, switch_cost : float
            In node-cost units (1 / image units).
        """
        eps = float(self.eps)
        b = _background(image)
        peaks, q = 0.5 / rowmin - eps, float(self.level_quantile)
        m = float(np.median(peaks) if q == 0.5 else np.quantile(peaks, q))  # the median to the last bit
        level = b + float(self.off_rel) * (m - b)
        off = 1.0 / (max(level, 0.0) + eps)
        return off, float(self.switch_rows) * off

    def path(self, image, background=None):
        """One optimal path of a frame: ``(rows, cols, off, total_cost)`` (see :func:`gap_path`)."""
        from ._validation import check_background

        img = check_image(image)
        bg = check_background(background, img.shape)
        self.validate_params()
        img = self.seen_frame(img, bg)
        hc, rowmin, _, _ = _half_cost(img, self.eps)
        off, s = self.off_costs(img, rowmin)
        return gap_path(2.0 * hc, off, s, self.connectivity, self.h_weight)

    def _readings(self, image):
        H, W = image.shape
        hc, F = _work_arrays(image.shape)  # neither is kept past this call
        hc, rowmin, _, _ = _half_cost(image, self.eps, hc)
        off, s = self.off_costs(image, rowmin)
        ho = np.full(H, 0.5 * off)
        mark, _, rows, cols, _, _ = _labels(hc, ho, s, self.connectivity == 8, float(self.h_weight), F)
        return _marked_readings(self, image, mark, rows, cols)
