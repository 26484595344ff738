"""The paper's dynamic programming stripe tracker (Wang et al. 2008, sec. 3).

The image is a graph with one node per pixel. Node cost is the inverse
brightness ``c = 1 / (max(I, 0) + eps)``; the edge between neighbouring nodes
p and q costs the mean of their node costs times the edge's weight: 1 for a
vertical step, ``h_weight`` for a horizontal one, ``sqrt(1 + h_weight**2)``
for a diagonal one (8-connectivity). The paper (Fig. 5) makes the cost
"proportional to the trace of laser light and smaller in the horizontal
orientation": ``h_weight < 1`` lets the path follow a stripe that jumps
sideways (a depth discontinuity) instead of cutting across the dark; with
``h_weight = 1`` the cost is the isotropic one of skimage's
``MCP_Geometric`` (step length). Every node of
the top row is a free start and every node of the bottom row a free goal (the
paper's zero-cost moves along those rows). The stripe is the global
minimum-cost path between the two rows. The paper relaxes its forward
procedure "until no node changes"; on this graph that fixpoint is exactly the
shortest-path distance, so any exact shortest-path algorithm finds the same
optimum. Paths may step sideways and, on either connectivity, back up.

Public functions
----------------
- :func:`node_cost` - the cost array of an image.
- :func:`shortest_path` - the fast, exact solver on a positive cost array
  (numba kernels in ``trackers._dp_kernels``; algorithm described there).
- :func:`shortest_path_reference` - a slow, literal transcription of the
  paper's procedure (synchronous relaxation of eq. (8) until no node changes,
  then backtracking), for tests and teaching.
- :func:`accumulated_cost` - the paper's accumulated cost field (Fig. 7b).

The trackers' stages one at a time (half costs, field, labelling, row
readings, reporting rule), for profiling and kernel checks, are in
:mod:`trackers.dp_stages`.

Trackers ``dp4`` and ``dp8`` (:class:`DP4Tracker`, :class:`DP8Tracker`).
"""

from __future__ import annotations

import threading

import numpy as np

from . import _dp_kernels as K
from . import _dp_rows as R
from ._base import Track, Tracker
from ._dp_report import reporting_rule as _reporting_rule
from ._params import Bool, Choice, Int, Real, check_real
from ._stripe import StripeSettings, answer
from ._validation import check_background, check_image

#: The row rules a DP tracker's ``row_rule`` names (the kernel's codes, :mod:`trackers._dp_rows`).
ROW_RULES = {"crossing": R.RULE_CROSSING, "mean": R.RULE_MEAN, "brightest": R.RULE_BRIGHTEST}

__all__ = [
    "DEFAULT_H_WEIGHT",
    "DEFAULT_REPORT",
    "PAPER_REPORT",
    "node_cost",
    "shortest_path",
    "shortest_path_reference",
    "accumulated_cost",
    "DPTracker",
    "DP4Tracker",
    "DP8Tracker",
]

_TIE_TOL = 1e-11  # relative tolerance deciding that two path costs tie
#: The DP trackers' default ``h_weight``, chosen by ``stripebench tune dp`` (profile
#: ``bench/config/profiles/tune_dp.toml``: sphere and plane x matte/patchy/absorbing/glossy, with a
#: table and no background and before the in-range wall, seed 1, 12 angles at 512x480; the
#: criterion fixed beforehand: mean fraction of lit object rows within 3 px, ties within 0.005
#: to the larger h_weight). Measured: 1: 0.944, 0.5: 0.957, 0.25: 0.969, 0.1: 0.974,
#: 0.05: 0.974, 0.025: 0.970, 0.01: 0.965 (docs/tune_dp.png).
DEFAULT_H_WEIGHT = 0.25
#: The DP trackers' reporting rule (``k_sigma``, ``max_gap``, ``min_run``), chosen by ``stripebench tune
#: dp_gap`` (stage 2; profile ``bench/config/profiles/tune_dp_gap.toml``: spheres and planes in six
#: materials on a table and before a wall at seed 1, the hard synthetic frames of seeds 100-105 and
#: the shipped photographs; the objective: the mean over those three groups of F1 over rows, a miss
#: and a false report priced alike). A row supports the path above 5 noise units; gaps of more than
#: 5 unsupported rows and stretches with fewer than 5 supporting rows are not reported.
DEFAULT_REPORT = {"k_sigma": 5.0, "max_gap": 5, "min_run": 5}
#: The paper's own reporting: every row between the first and the last supporting one
#: (``dp4_oneframe`` in the paper run, with ``use_background = False``).
PAPER_REPORT = {"k_sigma": 3.0, "max_gap": None, "min_run": 1}


def _check_connectivity(connectivity) -> bool:
    if connectivity not in (4, 8) or isinstance(connectivity, bool):
        raise ValueError(f"`connectivity` must be 4 or 8, got {connectivity!r}")
    return connectivity == 8


def _check_h_weight(h_weight) -> float:
    check_real("h_weight", h_weight, low=0, low_open=True)
    if not np.isfinite(h_weight):
        raise ValueError(f"`h_weight` must be finite, got {h_weight!r}")
    return float(h_weight)


_WORK = threading.local()


def _work_arrays(shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Two float64 work arrays of ``shape`` (the half costs and the distance
    field of one solve) for the calling thread, the same ones again while the
    frame size stays the same (and new ones when it changes).

    Fresh pages of a large array cost a page fault each when first written,
    and at 960x600 a new pair per frame cost the DP trackers more than the
    solve itself (docs/dp.md, Speed). Only callers whose results keep
    neither array use them.
    """
    arrays = getattr(_WORK, "arrays", None)
    if arrays is None or arrays[0].shape != shape:
        arrays = (np.empty(shape), np.empty(shape))
        _WORK.arrays = arrays
    return arrays


def _half_cost(image: np.ndarray, eps: float, out: np.ndarray | None = None):
    """Half node costs ``0.5 / (max(I, 0) + eps)`` (into ``out`` if given),
    each row's least one and its leftmost and rightmost columns (the kernels'
    inputs)."""
    H = image.shape[0]
    hc = np.empty(image.shape, dtype=np.float64) if out is None else out
    rowmin = np.empty(H)
    centre = np.empty(H, dtype=np.int64)
    rightc = np.empty(H, dtype=np.int64)
    if image.dtype == np.uint8:
        K.half_cost_u8(image, float(eps), hc, rowmin, centre, rightc)
    else:
        K.half_cost_float(image, float(eps), hc, rowmin, centre, rightc)
    return hc, rowmin, centre, rightc


def node_cost(image, eps: float = 1.0) -> np.ndarray:
    """Node cost ``1 / (max(I, 0) + eps)`` of every pixel.

    Parameters
    ----------
    image : array_like, shape (H, W)
        Frame in camera units.
    eps : float, default 1.0
        Offset in image units (1 DN for 8-bit frames), > 0.

    Returns
    -------
    ndarray of float64, shape (H, W)

    Examples
    --------
    >>> node_cost(np.array([[0, 1, 3]], np.uint8))
    array([[1.  , 0.5 , 0.25]])
    """
    img = check_image(image)
    check_real("eps", eps, low=0, low_open=True)
    return 2.0 * _half_cost(img, eps)[0]


def _check_cost(cost) -> np.ndarray:
    c = check_image(cost, name="cost")
    if c.dtype != np.float64:
        c = c.astype(np.float64)
    if not (c > 0).all():
        raise ValueError(f"`cost` must be > 0 everywhere, got minimum {float(c.min())!r}")
    return c


def _solve(hc: np.ndarray, rowmin: np.ndarray, centre: np.ndarray, rightc: np.ndarray, conn8: bool,
           h_weight: float = 1.0, D: np.ndarray | None = None):
    H, W = hc.shape
    D = np.empty_like(hc) if D is None else D
    K.accumulate(hc, conn8, True, D, rowmin, centre, h_weight, rightc)
    rows = np.empty(H * W, dtype=np.int64)
    cols = np.empty(H * W, dtype=np.int64)
    n = K.backtrack(D, hc, conn8, rows, cols, h_weight)
    if n < 0:  # pragma: no cover - would mean a bug in the kernels
        raise RuntimeError("backtracking did not reach the top row")
    rows = rows[:n][::-1].copy()
    cols = cols[:n][::-1].copy()
    return rows, cols, D


def _stats(hc: np.ndarray):
    rowmin = np.empty(hc.shape[0])
    centre = np.empty(hc.shape[0], dtype=np.int64)
    rightc = np.empty(hc.shape[0], dtype=np.int64)
    K.row_stats(hc, rowmin, centre, rightc)
    return rowmin, centre, rightc


def shortest_path(cost, connectivity: int = 4, h_weight: float = 1.0):
    """Global minimum-cost path from the top row to the bottom row.

    Parameters
    ----------
    cost : array_like, shape (H, W)
        Positive, finite node costs.
    connectivity : {4, 8}, default 4
    h_weight : float, default 1.0
        Weight of a horizontal step relative to a vertical one, finite and
        > 0: a horizontal edge costs ``h_weight * (c_p + c_q) / 2``, a
        vertical one ``(c_p + c_q) / 2``, a diagonal one (8-connectivity)
        ``sqrt(1 + h_weight**2) * (c_p + c_q) / 2``.

    Returns
    -------
    rows, cols : ndarray of int64, shape (n,)
        The path's pixels from the top row (``rows[0] == 0``) to the bottom row
        (``rows[-1] == H - 1``); consecutive pixels are neighbours.
    total_cost : float
        Sum over the path's edges of ``(c_p + c_q) / 2`` times the edge's
        weight (1 vertical, ``h_weight`` horizontal, ``sqrt(1 + h_weight**2)``
        diagonal; with ``h_weight=1`` the same cost as
        :class:`skimage.graph.MCP_Geometric`).

    Notes
    -----
    Ties are broken deterministically: the end is the bottom-row node of least
    cost-to-go, then the cheapest, then the leftmost; backtracking prefers up,
    up-left, up-right, left, right, down, down-left, down-right in that order.

    Examples
    --------
    >>> cost = np.array([[1., 9., 9.], [9., 1., 9.], [9., 9., 1.]])
    >>> rows, cols, total = shortest_path(cost, connectivity=8)
    >>> cols.tolist(), round(total, 6)
    ([0, 1, 2], 2.828427)
    """
    c = _check_cost(cost)
    conn8 = _check_connectivity(connectivity)
    hw = _check_h_weight(h_weight)
    hc = 0.5 * c
    rows, cols, D = _solve(hc, *_stats(hc), conn8, hw)
    return rows, cols, float(D[-1, cols[-1]])


def accumulated_cost(image, *, connectivity: int = 4, eps: float = 1.0, h_weight: float = 1.0) -> np.ndarray:
    """The accumulated cost field of an image (the paper's Fig. 7b).

    Every node's exact minimum cost to the top row (the goal line); the
    bottom row is then filled with its minimum, as the paper's zero-cost moves
    along the starting line make every bottom node hold the same value.

    Parameters
    ----------
    image : array_like, shape (H, W)
    connectivity : {4, 8}, default 4
    eps : float, default 1.0
    h_weight : float, default 1.0
        Horizontal edge weight (see :func:`shortest_path`).

    Returns
    -------
    ndarray of float64, shape (H, W)
    """
    img = check_image(image)
    check_real("eps", eps, low=0, low_open=True)
    conn8 = _check_connectivity(connectivity)
    hw = _check_h_weight(h_weight)
    hc, rowmin, centre, rightc = _half_cost(img, eps)
    D = np.empty_like(hc)
    K.accumulate(hc, conn8, False, D, rowmin, centre, hw, rightc)
    D[-1, :] = D[-1].min()
    return D


def shortest_path_reference(cost, connectivity: int = 4, max_iter: int | None = None, h_weight: float = 1.0):
    """The paper's procedure, literally: slow, for tests and teaching.

    Forward procedure (sec. 3.2): ``D`` starts at 0 on the goal line (top
    row; its zero-cost links keep it there) and at a big value elsewhere;
    every node is replaced, synchronously as in the paper's cellular cells, by
    ``min(D(i,j), min over neighbours (k,l) of d_ij,kl + D(k,l))`` (eq. 8)
    until no node changes. The zero-cost links along the starting line
    (bottom row) would give every bottom node the same value; the
    backtracking therefore starts at the bottom node where that value is
    really reached (least ``D``, then cheapest, then leftmost) and moves to
    the neighbour satisfying eq. (8) (the same neighbour order as
    :func:`shortest_path`) until the goal line is reached. The edge costs
    carry the same ``h_weight`` as :func:`shortest_path`.

    Same parameters, returns and tie-breaking as :func:`shortest_path`.
    """
    c = _check_cost(cost)
    conn8 = _check_connectivity(connectivity)
    hw = _check_h_weight(h_weight)
    H, W = c.shape
    if max_iter is None:
        max_iter = H * W + 1
    # neighbour order shared with the fast solver's backtracking; the third
    # entry is the edge's weight
    dg = float(np.sqrt(1.0 + hw * hw))
    moves = [(-1, 0, 1.0), (-1, -1, dg), (-1, 1, dg), (0, -1, hw), (0, 1, hw),
             (1, 0, 1.0), (1, -1, dg), (1, 1, dg)]
    if not conn8:
        moves = [m for m in moves if m[0] == 0 or m[1] == 0]
    big = 1e300
    D = np.full((H, W), big)
    D[0, :] = 0.0
    pc = np.pad(c, 1, constant_values=np.inf)
    for _ in range(max_iter):
        pD = np.pad(D, 1, constant_values=np.inf)
        new = D.copy()
        for dr, dj, length in moves:
            nD = pD[1 + dr : 1 + dr + H, 1 + dj : 1 + dj + W]
            nc = pc[1 + dr : 1 + dr + H, 1 + dj : 1 + dj + W]
            new = np.minimum(new, nD + 0.5 * (c + nc) * length)
        new[0, :] = 0.0  # goal line
        if np.array_equal(new, D):
            break
        D = new
    else:  # pragma: no cover
        raise RuntimeError("relaxation did not converge")
    r, j = H - 1, 0
    for k in range(1, W):
        if D[r, k] < D[r, j] or (D[r, k] == D[r, j] and c[r, k] < c[r, j]):
            j = k
    total = float(D[r, j])
    path = [(r, j)]
    while r > 0:
        best = None
        for dr, dj, length in moves:
            rr, jj = r + dr, j + dj
            if 0 <= rr < H and 0 <= jj < W:
                v = D[rr, jj] + 0.5 * (c[r, j] + c[rr, jj]) * length
                if best is None or v < best[0]:
                    best = (v, rr, jj)
        r, j = best[1], best[2]
        path.append((r, j))
        if len(path) > H * W:  # pragma: no cover
            raise RuntimeError("backtracking did not reach the goal line")
    path.reverse()
    rows = np.array([p[0] for p in path], dtype=np.int64)
    cols = np.array([p[1] for p in path], dtype=np.int64)
    return rows, cols, total


def _marked_readings(tracker, image, mark, rows, cols):
    """Each row's column by ``tracker.row_rule``, contrast, side spread and span from the labelled
    optimal-path nodes ``mark`` (their ``rows``, ``cols``): :func:`trackers._dp_rows.marked_rows`."""
    H = image.shape[0]
    col = np.empty(H)
    contrast = np.empty(H)
    side_sd = np.empty(H)
    span = np.empty(H, dtype=np.int64)
    R.marked_rows(image, mark, rows, cols, int(tracker.side_inner), int(tracker.side_outer),
                  ROW_RULES[tracker.row_rule], col, contrast, side_sd, span)
    return col, contrast, side_sd, span


class DPTracker(Tracker):
    """Minimum-cost path tracker; use :class:`DP4Tracker` or :class:`DP8Tracker`.

    The path is the global minimum-cost path of :func:`shortest_path` on
    :func:`node_cost` of the frame. As in the paper's backtracking, which
    labels every node satisfying eq. (8) "expansively", the tracker takes
    the union of all optimal paths (exact cost ties are common in 8-bit
    frames; the union does not depend on tie-breaking, so flipping the frame
    flips the result). It crosses every row.

    *Row rule* (a row's column is a place the stripe could be): in each row
    the tracker reports the brightest of the row's *crossing* nodes, the
    optimal-path nodes where a path enters or leaves the row by a vertical
    or diagonal edge (all the row's optimal-path nodes if none does; ties in
    brightness go to the lower median of the tied columns). Where the path
    walks along a row (a jump of the stripe, a cut, a flat saturated top)
    the mean column of its nodes there is a column between the two ends
    that the stripe never had; the crossing nodes are the ends. Measured
    (``scripts/dp_row_rules.py``, 6 synthetic 160x120 frames with a 40-column
    jump and a cut): rows more than 3 px off, mean rule vs this rule, 11.4 %
    vs 10.5 % (dp4, ``h_weight=1``; the rest is the isotropic path cutting
    across the jump) and 0.44 % (worst 19 px) vs 0 % (worst 1.5 px) at
    ``h_weight=0.1``; the brightest of all the row's optimal nodes scored
    the same as the crossing rule, and dropping rows where the path walks
    more than 5 columns removed a few rows without removing an error.

    Where the path runs through no stripe at all it is not reported:

    * per row, the path's brightness ``I_p`` (the intensity at the row's
      column) is compared with the local background ``b_r``, the mean of the
      pixels ``side_inner``..``side_outer`` columns to either side of it (moved
      outwards on a side where the stripe stays above half its height for
      more than ``side_inner - 2`` columns: wide or saturated stripes); the
      noise ``s`` is the median over rows of the standard deviation of those
      side pixels (floored at 1e-3 of the frame's dynamic range);
    * the row *supports* the path if ``I_p - b_r > k_sigma * s``;
    * if fewer than ``max(3, min_support * H)`` rows support it, the frame has
      no stripe and nothing is reported (so a blank frame gives all-NaN);
    * otherwise every row from the first to the last supporting row is
      reported: the path's strength is to bridge the rows in between where the
      stripe is dim or cut, except gaps of more than ``max_gap`` unsupported
      rows (if set) and stretches of reported rows with fewer than ``min_run``
      supporting rows (a path crossing the dark picks up a few noise peaks
      that support it by chance). Rows above the first and below the last
      supporting row are not reported. The defaults of ``k_sigma``,
      ``max_gap`` and ``min_run`` are the operating point chosen by
      ``stripebench tune dp_gap`` (:data:`DEFAULT_REPORT`); ``k_sigma = 3,
      max_gap = None, min_run = 1`` bridges every row between the first and the
      last supporting row, as the paper's DP crosses every row.

    ``score`` is the contrast ``(I_p - b_r) / s`` in noise units (low or
    negative in bridged rows).

    *The stripe question* (``stripe_test``, :class:`trackers.StripeTest`; None: not
    asked): it is asked of the supporting rows' columns on the frame the DP sees (with
    the laser-off frame and the colour evidence where given); a supporting row it says
    no to does not support the path and is not reported (:func:`_reporting_rule`).

    *Background*: given a laser-off frame (``background``) and with
    ``use_background`` (the default), the tracker works on the difference
    ``image - background`` (float64, signed) instead of the frame: node
    costs, the reporting rule's contrast and noise, everything. The laser
    adds its light to the ambient light, so the difference is the laser's
    light plus noise, and the ambient structure (lamps, windows, bright
    objects: what the paper's Fig. 2 calls bright illumination) cancels. The
    node cost clips the difference at 0 (``1 / (max(D, 0) + eps)``) as it
    clips any frame; the reporting rule sees the signed difference, so the
    side pixels' mean and spread are those of the difference's noise, not of
    its positive half. Without a background (or with
    ``use_background=False``: the paper's one-frame method) the frame itself
    is used, exactly as before the background was supported.

    Parameters
    ----------
    eps : float, default 1.0
        Node-cost offset in image units (1 DN for 8-bit frames), > 0.
    k_sigma : float, default ``DEFAULT_REPORT["k_sigma"]``
        A row supports the path when its contrast exceeds ``k_sigma`` noise units (>= 0).
    min_support : float, default 0.05
        Least fraction of rows that must support the path.
    max_gap : int or None, default ``DEFAULT_REPORT["max_gap"]``
        Longest run of unsupported rows reported between supported rows (None: any).
    min_run : int, default ``DEFAULT_REPORT["min_run"]``
        Least number of supporting rows in a reported stretch (>= 1).
    side_inner, side_outer : int, default 4 and 12
        The background pixels' distance from the path, in columns.
    h_weight : float, default :data:`DEFAULT_H_WEIGHT` (0.25)
        Weight of a horizontal edge relative to a vertical one, finite and
        > 0 (see :func:`shortest_path`); 1 is the isotropic reading. The
        default was chosen by ``stripebench tune dp``, a fixed procedure on
        scenes and a seed the paper experiment does not use.
    use_background : bool, default True
        Track the difference ``image - background`` when a laser-off frame
        is given (see *Background* above); False ignores it.
    row_rule : {"crossing", "mean", "brightest"}, default "crossing"
        Which column a row reports (see *Row rule* above): the brightest
        crossing node (the default), the mean column of the row's
        optimal-path nodes (the old rule), or the brightest of them.
        The others are kept for the comparison in ``scripts/dp_row_rules.py``.
    max_walk : int or None, default None
        Rows whose optimal-path nodes span more than ``max_walk`` columns are
        not reported (None: any span; >= 0).
    stripe_test : dict or None, default None
        The stripe question's settings (see *The stripe question* above; ``{}``:
        its defaults).
    """

    connectivity = 4
    uses_background = True
    uses_colour = True

    def __init__(self, eps=1.0, k_sigma=DEFAULT_REPORT["k_sigma"], min_support=0.05,
                 max_gap=DEFAULT_REPORT["max_gap"], side_inner=4, side_outer=12, h_weight=DEFAULT_H_WEIGHT,
                 use_background=True, row_rule="crossing", max_walk=None, min_run=DEFAULT_REPORT["min_run"],
                 stripe_test=None):
        self.eps = eps
        self.h_weight = h_weight
        self.k_sigma = k_sigma
        self.min_support = min_support
        self.max_gap = max_gap
        self.min_run = min_run
        self.side_inner = side_inner
        self.side_outer = side_outer
        self.use_background = use_background
        self.row_rule = row_rule
        self.max_walk = max_walk
        self.stripe_test = stripe_test

    parameter_constraints = {"eps": Real(low=0, low_open=True), "k_sigma": Real(low=0),
                             "min_support": Real(low=0, high=1), "max_gap": Int(low=0, optional=True),
                             "side_inner": Int(low=1), "side_outer": Int(low=1),
                             "h_weight": Real(low=0, low_open=True), "use_background": Bool(),
                             "row_rule": Choice(frozenset(ROW_RULES)), "max_walk": Int(low=0, optional=True),
                             "min_run": Int(low=1), "stripe_test": StripeSettings()}

    def validate_params(self):
        """The parameters' constraints (:attr:`parameter_constraints`), then ``side_outer >= side_inner``."""
        super().validate_params()
        if self.side_outer < self.side_inner:
            raise ValueError(f"`side_outer` must be >= `side_inner` ({self.side_inner}), got {self.side_outer!r}")

    def seen_frame(self, image: np.ndarray, background: np.ndarray | None) -> np.ndarray:
        """The frame the DP works on: ``image`` itself, or ``image - background``
        (float64, signed, (H, W), image units) when a laser-off frame is given
        and ``use_background`` is True. Both arguments already validated."""
        if background is None or not self.use_background:
            return image
        return np.subtract(image, background, dtype=np.float64)

    def path(self, image, background=None):
        """The minimum-cost path of a frame (of ``image - background`` when a
        laser-off frame is given, see :meth:`seen_frame`): ``(rows, cols,
        total_cost)`` (see :func:`shortest_path`)."""
        img = check_image(image)
        bg = check_background(background, img.shape)
        self.validate_params()
        img = self.seen_frame(img, bg)
        hc, D = _work_arrays(img.shape)
        rows, cols, D = _solve(*_half_cost(img, self.eps, hc), self.connectivity == 8, float(self.h_weight), D)
        return rows, cols, float(D[-1, cols[-1]])

    def readings(self, image, background=None):
        """The optimal path's readings of each row of a frame, the reporting rule's inputs.

        The frame is validated, and ``image - background`` taken as in :meth:`seen_frame`.

        Returns
        -------
        frame : ndarray, shape (H, W)
            The frame the DP saw.
        col, contrast, side_sd : ndarray of float64, shape (H,)
            Each row's column by the row rule (NaN where the path has no node), the
            contrast of the path's pixel over its sides and the sides' spread (image units).
        span : ndarray of int64, shape (H,)
            The columns the path walks in the row.

        :meth:`report` applies the reporting rule to them; ``track`` is the two in turn
        (the tuning procedure reads a frame once and tries many rules).
        """
        img = check_image(image)
        bg = check_background(background, img.shape)
        self.validate_params()
        frame = self.seen_frame(img, bg)
        return (frame,) + self._readings(frame)

    def _readings(self, image):
        """``(col, contrast, side_sd, span)`` of :meth:`readings` for a frame the DP sees."""
        H, W = image.shape
        hc, D = _work_arrays(image.shape)
        hc, rowmin, centre, rightc = _half_cost(image, self.eps, hc)
        conn8 = self.connectivity == 8
        hw = float(self.h_weight)
        K.accumulate(hc, conn8, True, D, rowmin, centre, hw, rightc)
        mark = np.zeros((H, W), dtype=np.uint8)
        rows = np.empty(H * W, dtype=np.int64)
        cols = np.empty(H * W, dtype=np.int64)
        n = K.optimal_nodes(D, hc, conn8, _TIE_TOL, mark, rows, cols, hw)
        return _marked_readings(self, image, mark, rows[:n], cols[:n])

    def report(self, frame, col, contrast, side_sd, span) -> Track:
        """The reporting rule (see the class notes) on the readings of :meth:`readings`, with this
        tracker's ``k_sigma``, ``min_support``, ``max_gap``, ``min_run`` and ``max_walk`` (the
        stripe question, asked of ``frame`` alone: no laser-off frame, no colour)."""
        rule = _reporting_rule(frame, contrast, side_sd, span, self, self._asker(frame, col))
        if rule is None:
            return Track.empty(frame.shape[0])
        z, _, rep = rule
        rep = rep & ~np.isnan(col)
        return Track(np.where(rep, col, np.nan), np.where(rep, z, np.nan))

    def _asker(self, frame, col, image=None, background=None, colour=None):
        """The stripe question for :func:`_reporting_rule` (None when ``stripe_test`` is None): the
        supporting rows (H,) bool -> the rows whose peak at ``col`` on ``frame`` is a stripe; ``image``,
        ``background`` and ``colour`` as for :func:`trackers._stripe.ask`."""
        if self.stripe_test is None:
            return None

        def ask(support):
            columns = np.where(support, col, np.nan)
            return answer(self.stripe_test, frame, columns, image=image, background=background, colour=colour).yes
        return ask

    def _path_rows(self, image, raw=None, background=None, colour=None):
        """The reporting rule's pieces for one frame (the one the DP sees; ``raw``, ``background`` and
        ``colour``: the laser-on and laser-off frames and the colour evidence, for the stripe question).

        Returns ``None`` when the frame has no stripe (too few supporting
        rows), else ``(col, z, support, report)``, all (H,): each row's
        column by the row rule, the contrast in noise units, the rows
        supporting the path, the rows to report.
        """
        col, contrast, side_sd, span = self._readings(image)
        rule = _reporting_rule(image, contrast, side_sd, span, self, self._asker(image, col, raw, background, colour))
        if rule is None:
            return None
        z, support, report = rule
        return col, z, support, report & ~np.isnan(col)

    def find_stripe(self, image, background, colour=None):
        rows = self._path_rows(self.seen_frame(image, background), image, background, colour)
        if rows is None:
            return Track.empty(image.shape[0])
        mean_col, z, _, report = rows
        return Track(np.where(report, mean_col, np.nan), np.where(report, z, np.nan))


class DP4Tracker(DPTracker):
    __doc__ = "``dp4``: the paper's DP on the 4-connected graph.\n\n" + DPTracker.__doc__.split("\n", 2)[2]
    name = "dp4"
    connectivity = 4


class DP8Tracker(DPTracker):
    __doc__ = "``dp8``: the paper's DP on the 8-connected graph.\n\n" + DPTracker.__doc__.split("\n", 2)[2]
    name = "dp8"
    connectivity = 8
