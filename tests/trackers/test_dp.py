"""The DP core against an independent oracle (skimage's MCP_Geometric), the
literal transcription of the paper, and the DP trackers' reporting rules."""

import numpy as np
import pytest
from skimage.graph import MCP_Geometric

from trackers.dp import (
    DEFAULT_H_WEIGHT,
    DEFAULT_REPORT,
    DP4Tracker,
    DP8Tracker,
    accumulated_cost,
    node_cost,
    shortest_path,
    shortest_path_reference,
)
from trackers.testing import make_stripe_image

SHAPES = [(1, 1), (1, 7), (7, 1), (2, 2), (3, 3), (2, 9), (9, 2), (40, 5), (5, 40), (31, 23), (64, 64)]


def mcp_optimum(cost, connectivity, full=False):
    """MCP_Geometric from every top-row start; the best bottom-row end."""
    H, W = cost.shape
    m = MCP_Geometric(cost, fully_connected=connectivity == 8)
    starts = [(0, j) for j in range(W)]
    ends = None if full else [(H - 1, j) for j in range(W)]
    costs, _ = m.find_costs(starts, ends)
    return costs if full else float(costs[-1].min())


def random_costs(shape, kind, rng):
    if kind == "uniform":
        return rng.random(shape) + 0.01
    if kind == "lognormal":  # heavy tails force paths sideways and upwards
        return np.exp(3.0 * rng.normal(size=shape))
    # a maze of cheap and dear cells
    return np.where(rng.random(shape) < 0.45, 1e-3, 1.0) + 1e-6 * rng.random(shape)


def assert_valid_path(rows, cols, shape, connectivity):
    H, W = shape
    assert rows[0] == 0 and rows[-1] == H - 1
    assert ((0 <= cols) & (cols < W)).all()
    dr, dc = np.abs(np.diff(rows)), np.abs(np.diff(cols))
    if rows.size > 1:
        assert (np.maximum(dr, dc) == 1).all()
        if connectivity == 4:
            assert (dr + dc == 1).all()


def path_cost(cost, rows, cols):
    total = 0.0
    for k in range(1, rows.size):
        step = np.hypot(rows[k] - rows[k - 1], cols[k] - cols[k - 1])
        total += 0.5 * (cost[rows[k], cols[k]] + cost[rows[k - 1], cols[k - 1]]) * step
    return total


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("kind", ["uniform", "lognormal", "maze"])
@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_total_cost_equals_mcp_geometric(shape, kind, connectivity):
    import zlib

    rng = np.random.default_rng(zlib.crc32(repr((shape, kind, connectivity)).encode()))
    for _ in range(3):
        cost = random_costs(shape, kind, rng)
        rows, cols, total = shortest_path(cost, connectivity)
        expected = mcp_optimum(cost, connectivity)
        assert total == pytest.approx(expected, rel=1e-9, abs=0)
        assert_valid_path(rows, cols, shape, connectivity)
        assert path_cost(cost, rows, cols) == pytest.approx(total, rel=1e-9, abs=1e-300)


@pytest.mark.parametrize("connectivity", [4, 8])
def test_stripe_images_with_gaps_match_mcp(connectivity):
    for seed in range(4):
        img, _ = make_stripe_image(height=120, width=160, seed=seed)
        img = img.astype(np.float64)
        img[30:55] *= 0.05  # the stripe almost vanishes
        img[80:84] = 0.0  # and is cut
        cost = node_cost(img)
        rows, cols, total = shortest_path(cost, connectivity)
        assert total == pytest.approx(mcp_optimum(cost, connectivity), rel=1e-9)
        assert_valid_path(rows, cols, cost.shape, connectivity)


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("shape", [(1, 5), (6, 1), (2, 2), (8, 9), (15, 12), (20, 30)], ids=str)
def test_fast_solver_agrees_with_the_papers_literal_procedure(shape, connectivity):
    rng = np.random.default_rng(shape[0] * 100 + shape[1] + connectivity)
    for kind in ("uniform", "lognormal", "maze"):
        cost = random_costs(shape, kind, rng)
        fast = shortest_path(cost, connectivity)
        slow = shortest_path_reference(cost, connectivity)
        assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1])
        assert fast[2] == pytest.approx(slow[2], rel=1e-12)


def test_ties_are_broken_deterministically():
    cost = np.ones((5, 6))
    a = shortest_path(cost, 4)
    b = shortest_path(cost, 4)
    assert all(np.array_equal(x, y) for x, y in zip(a[:2], b[:2]))
    # straight down the leftmost column: the documented order
    assert a[1].tolist() == [0] * 5 and a[2] == pytest.approx(4.0)


def test_path_may_step_upwards():
    # a U-shaped corridor of cheap cells: the only cheap route goes down,
    # sideways, up and down again
    cost = np.full((8, 7), 100.0)
    cost[0:6, 1] = 1  # down the left corridor to row 5
    cost[5, 1:4] = 1  # right along row 5
    cost[2:6, 3] = 1  # back up to row 2
    cost[2, 3:6] = 1  # right along row 2
    cost[2:8, 5] = 1  # and down to the bottom
    for connectivity in (4, 8):
        rows, cols, total = shortest_path(cost, connectivity)
        assert total == pytest.approx(mcp_optimum(cost, connectivity), rel=1e-12)
        assert total < 100  # it found the corridor
        assert (np.diff(rows) < 0).any(), "the optimal path here must step back up"


def test_accumulated_cost_field_is_exact():
    rng = np.random.default_rng(5)
    img = (rng.random((30, 25)) * 255).astype(np.uint8)
    for connectivity in (4, 8):
        field = accumulated_cost(img, connectivity=connectivity)
        expected = mcp_optimum(1.0 / (img + 1.0), connectivity, full=True)
        expected[-1, :] = expected[-1].min()
        np.testing.assert_allclose(field, expected, rtol=1e-9, atol=0)


def test_node_cost():
    img = np.array([[0, 1, 3], [255, 7, 0]], np.uint8)
    np.testing.assert_allclose(node_cost(img), 1.0 / (img.astype(float) + 1.0))
    np.testing.assert_allclose(node_cost(np.array([[-5.0, 1.0]]), eps=0.5), [[2.0, 1 / 1.5]])
    with pytest.raises(ValueError, match="`eps` must be > 0, got 0"):
        node_cost(img, eps=0)


@pytest.mark.parametrize(
    "cost, connectivity, message",
    [
        (np.zeros((2, 2)), 4, r"`cost` must be > 0 everywhere, got minimum 0.0"),
        (-np.ones((2, 2)), 4, r"`cost` must be > 0 everywhere"),
        (np.ones((2, 2)), 6, r"`connectivity` must be 4 or 8, got 6"),
        (np.ones((2, 2)), True, r"`connectivity` must be 4 or 8, got True"),
        (np.ones(3), 4, r"`cost` must be 2-D, got shape \(3,\)"),
        (np.full((2, 2), np.nan), 4, r"`cost` must be finite"),
    ],
)
def test_shortest_path_validates(cost, connectivity, message):
    with pytest.raises(ValueError, match=message):
        shortest_path(cost, connectivity)


@pytest.mark.parametrize("tracker_cls", [DP4Tracker, DP8Tracker])
def test_dp_bridges_a_dim_gap_that_threshold_misses(tracker_cls):
    from trackers.threshold import ThresholdTracker

    img, truth = make_stripe_image(height=120, width=160, seed=11, noise=1.0)
    img = img.astype(np.float64)
    img[40:70] = 10 + 0.08 * (img[40:70] - 10)  # the stripe at 8 % contrast
    dp = tracker_cls().track(img)
    # a frame-wide threshold at a quarter of the range (the per-row default finds this
    # noise-free dim stretch: 14 DN over a 0.1 DN noise)
    th = ThresholdTracker(threshold=float(img.min() + 0.25 * np.ptp(img))).track(img)
    assert np.isnan(th.columns[40:70]).all()
    assert not np.isnan(dp.columns).any()
    err = np.abs(dp.columns - truth)
    # a whole-pixel path on a stripe slanted up to 1 px/row: mostly within
    # half a pixel, never beyond two (the worst rows are the free start and
    # goal rows, where the path may take a vertical shortcut)
    assert np.median(err) <= 0.5 and np.percentile(err, 95) <= 1.5 and err.max() <= 2.0
    assert np.median(dp.score[40:70]) < np.median(dp.score[:40])


def test_dp_reports_nothing_outside_the_supported_rows():
    img, truth = make_stripe_image(height=100, width=120, seed=3, noise=1.0)
    img = img.astype(np.float64)
    img[:20] = 10.0  # no stripe in the top 20 rows
    img[90:] = 10.0  # nor in the bottom 10
    out = DP8Tracker().track(img)
    assert np.isnan(out.columns[:20]).all() and np.isnan(out.columns[90:]).all()
    assert not np.isnan(out.columns[20:90]).any()


def test_max_gap_limits_bridging():
    img, _ = make_stripe_image(height=100, width=120, seed=4, noise=1.0)
    img = img.astype(np.float64)
    img[40:60] = 10.0  # a 20-row cut
    assert not np.isnan(DP4Tracker(max_gap=None).track(img).columns).any()  # the paper's DP bridges it
    for max_gap in (10, DEFAULT_REPORT["max_gap"]):  # the default leaves a 20-row cut out too
        limited = DP4Tracker(max_gap=max_gap).track(img).columns
        assert np.isnan(limited[40:60]).all() and not np.isnan(limited[:40]).any()


def test_noise_only_frame_reports_nothing():
    rng = np.random.default_rng(0)
    img = rng.normal(20, 3, (200, 150))
    for cls in (DP4Tracker, DP8Tracker):
        assert np.isnan(cls().track(img).columns).all()


def test_dp_path_accessor():
    img, truth = make_stripe_image(seed=2)
    rows, cols, total = DP8Tracker(h_weight=1.0).path(img)  # the isotropic graph is MCP_Geometric's
    expected = mcp_optimum(node_cost(img), 8)
    assert total == pytest.approx(expected, rel=1e-9)
    rows, cols, total = DP8Tracker().path(img)  # the default h_weight: the shortest_path of the same costs
    assert total == pytest.approx(shortest_path(node_cost(img), 8, h_weight=DEFAULT_H_WEIGHT)[2], rel=1e-12)
    assert DP8Tracker().get_params()["h_weight"] == DEFAULT_H_WEIGHT == 0.05


@pytest.mark.parametrize(
    "params, message",
    [
        ({"eps": 0}, r"`eps` must be > 0, got 0"),
        ({"k_sigma": -2}, r"`k_sigma` must be >= 0, got -2"),
        ({"min_support": 2}, r"`min_support` must be <= 1, got 2"),
        ({"max_gap": -1}, r"`max_gap` must be >= 0, got -1"),
        ({"side_inner": 0}, r"`side_inner` must be >= 1, got 0"),
        ({"side_inner": 5, "side_outer": 4}, r"`side_outer` must be >= `side_inner` \(5\), got 4"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        DP8Tracker(**params).track(np.zeros((3, 3)))


@pytest.mark.parametrize("tracker_cls", [DP4Tracker, DP8Tracker])
def test_dp_reports_a_wide_saturated_stripe(tracker_cls):
    # peak 600 DN clipped at 255, sigma 2.5 px: 8+ saturated columns
    img, truth = make_stripe_image(height=100, width=140, sigma_px=2.5, peak=600.0, seed=8, noise=2.0)
    out = tracker_cls().track(img)
    assert np.count_nonzero(~np.isnan(out.columns)) >= 95
    # on a flat (clipped) top the whole-pixel path may run anywhere across
    # the 7 saturated columns: within them, not necessarily at the centre
    assert np.nanmedian(np.abs(out.columns - truth)) <= 3.0


# --- h_weight: the anisotropic edge cost against Dijkstra on the explicit graph

H_WEIGHTS = [1.0, 0.5, 0.1, 0.01, 3.0]


def explicit_graph(cost, connectivity, h_weight):
    """The DP graph as a scipy sparse matrix: node k = r * W + j, plus a
    super-source (index H*W, zero-cost edges to the top row) and a
    super-sink (index H*W + 1, zero-cost edges from the bottom row)."""
    import scipy.sparse as sp

    H, W = cost.shape
    n = H * W
    src, dst, w = [], [], []
    steps = [(0, 1, h_weight), (1, 0, 1.0)]
    if connectivity == 8:
        steps += [(1, 1, np.sqrt(1 + h_weight**2)), (1, -1, np.sqrt(1 + h_weight**2))]
    idx = np.arange(n).reshape(H, W)
    for dr, dc, weight in steps:
        r0, r1 = 0, H - dr
        c0, c1 = max(0, -dc), W - max(0, dc)
        a = idx[r0:r1, c0:c1].ravel()
        b = idx[r0 + dr : r1 + dr, c0 + dc : c1 + dc].ravel()
        e = 0.5 * (cost.ravel()[a] + cost.ravel()[b]) * weight
        src += [a, b]
        dst += [b, a]
        w += [e, e]
    src += [np.full(W, n), idx[-1]]
    dst += [idx[0], np.full(W, n + 1)]
    w += [np.zeros(W), np.zeros(W)]  # explicit zeros are edges for csgraph
    g = sp.csr_matrix((np.concatenate(w), (np.concatenate(src), np.concatenate(dst))), shape=(n + 2, n + 2))
    return g, n


def dijkstra_optimum(cost, connectivity, h_weight, rel=1e-9):
    """The optimum and the set of nodes on some optimal path (forward plus
    backward distance equal to the optimum, to a relative ``rel``)."""
    from scipy.sparse.csgraph import dijkstra

    g, n = explicit_graph(cost, connectivity, h_weight)
    d_s = dijkstra(g, directed=True, indices=n)
    d_t = dijkstra(g.T.tocsr(), directed=True, indices=n + 1)
    H, W = cost.shape
    best = float(d_s[idx_bottom(H, W)].min())
    on = np.abs(d_s[:n] + d_t[:n] - best) <= rel * best
    return best, on.reshape(H, W)


def idx_bottom(H, W):
    return np.arange((H - 1) * W, H * W)


def optimal_set(cost, connectivity, h_weight):
    from trackers import _dp_kernels as K

    hc = 0.5 * cost
    H, W = cost.shape
    rowmin = hc.min(axis=1)
    centre = np.argmin(hc, axis=1).astype(np.int64)
    D = np.empty_like(hc)
    K.accumulate(hc, connectivity == 8, True, D, rowmin, centre, h_weight)
    mark = np.zeros((H, W), np.uint8)
    r = np.empty(H * W, np.int64)
    c = np.empty(H * W, np.int64)
    K.optimal_nodes(D, hc, connectivity == 8, 1e-11, mark, r, c, h_weight)
    return (mark & 1).astype(bool)


def assert_same_optimal_set(cost, connectivity, h_weight, on):
    """The labelled set holds every node Dijkstra finds optimal to 1e-13
    (relative) and none it finds off by more than 1e-9 (exact ties are common
    in 8-bit frames and mazes; the kernel labels to 1e-11 per edge)."""
    mine = optimal_set(cost, connectivity, h_weight)
    strict = dijkstra_optimum(cost, connectivity, h_weight, rel=1e-13)[1]
    assert (mine >= strict).all(), f"{np.count_nonzero(strict & ~mine)} optimal nodes not labelled"
    assert (mine <= on).all(), f"{np.count_nonzero(mine & ~on)} labelled nodes not optimal"


@pytest.mark.parametrize("h_weight", H_WEIGHTS)
@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("kind", ["uniform", "lognormal", "maze"])
@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_total_cost_and_optimal_nodes_equal_dijkstra(shape, kind, connectivity, h_weight):
    import zlib

    rng = np.random.default_rng(zlib.crc32(repr((shape, kind, connectivity, h_weight)).encode()))
    for _ in range(2):
        cost = random_costs(shape, kind, rng)
        rows, cols, total = shortest_path(cost, connectivity, h_weight=h_weight)
        best, on = dijkstra_optimum(cost, connectivity, h_weight)
        assert total == pytest.approx(best, rel=1e-9, abs=0)
        assert_valid_path(rows, cols, shape, connectivity)
        assert on[rows, cols].all()
        assert_same_optimal_set(cost, connectivity, h_weight, on)
        if h_weight == 1.0:
            assert total == pytest.approx(mcp_optimum(cost, connectivity), rel=1e-9, abs=0)


@pytest.mark.parametrize("h_weight", [0.5, 0.1, 0.01])
@pytest.mark.parametrize("connectivity", [4, 8])
def test_stripe_frames_with_gaps_equal_dijkstra_for_any_h_weight(connectivity, h_weight):
    for seed in range(3):
        img, _ = make_stripe_image(height=60, width=80, seed=seed)
        img = img.astype(np.float64)
        img[15:28] *= 0.05
        img[40:43] = 0.0
        cost = node_cost(img)
        total = shortest_path(cost, connectivity, h_weight=h_weight)[2]
        best, on = dijkstra_optimum(cost, connectivity, h_weight)
        assert total == pytest.approx(best, rel=1e-9)
        assert_same_optimal_set(cost, connectivity, h_weight, on)


@pytest.mark.parametrize("h_weight", [0.5, 0.1, 3.0])
@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("shape", [(1, 5), (6, 1), (8, 9), (15, 12)], ids=str)
def test_literal_procedure_with_h_weight(shape, connectivity, h_weight):
    rng = np.random.default_rng(shape[0] * 100 + shape[1] + connectivity)
    for kind in ("uniform", "lognormal", "maze"):
        cost = random_costs(shape, kind, rng)
        fast = shortest_path(cost, connectivity, h_weight=h_weight)
        slow = shortest_path_reference(cost, connectivity, h_weight=h_weight)
        assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1])
        assert fast[2] == pytest.approx(slow[2], rel=1e-12)


def test_accumulated_cost_field_with_h_weight_is_exact():
    from scipy.sparse.csgraph import dijkstra

    rng = np.random.default_rng(6)
    img = (rng.random((20, 17)) * 255).astype(np.uint8)
    cost = 1.0 / (img + 1.0)
    for connectivity in (4, 8):
        field = accumulated_cost(img, connectivity=connectivity, h_weight=0.2)
        g, n = explicit_graph(cost, connectivity, 0.2)
        d = dijkstra(g, indices=n)[:n].reshape(cost.shape)
        d[-1, :] = d[-1].min()
        np.testing.assert_allclose(field, d, rtol=1e-9, atol=0)


def test_a_small_h_weight_makes_the_path_walk_sideways():
    # a dark frame with a stripe in column 5 that rows 8..12 show 10 columns
    # to the right: the isotropic path cuts straight down through the 5 dark
    # rows, a cheap horizontal step lets it follow the stripe there
    img = np.full((20, 30), 2.0)
    img[:, 5] = 200.0
    img[8:13, 5] = 2.0
    img[8:13, 15] = 200.0
    for hw, follows in ((1.0, False), (0.05, True)):
        rows, cols, _ = shortest_path(node_cost(img), 4, h_weight=hw)
        assert (cols[(rows >= 8) & (rows <= 12)] == 15).any() == follows


@pytest.mark.parametrize("h_weight", [0, -1.0, float("inf"), float("nan"), "1", True])
def test_h_weight_is_validated(h_weight):
    msg = r"`h_weight` must be (> 0|finite|a finite number|a real number), got"
    with pytest.raises(ValueError, match=msg):
        shortest_path(np.ones((3, 3)), 4, h_weight=h_weight)
    with pytest.raises(ValueError, match=msg):
        accumulated_cost(np.ones((3, 3)), h_weight=h_weight)
    with pytest.raises(ValueError, match=msg):
        shortest_path_reference(np.ones((3, 3)), h_weight=h_weight)
    with pytest.raises(ValueError, match=msg):
        DP8Tracker(h_weight=h_weight).track(np.zeros((3, 3)))


@pytest.mark.parametrize("h_weight", [1.0, 0.25, 0.05])
@pytest.mark.parametrize("name", ["dp4", "dp8", "dp8_subpixel"])
def test_conformance_at_several_h_weights(name, h_weight):
    import trackers
    from trackers.testing import check_tracker

    t = trackers.make(name, h_weight=h_weight)
    assert t.get_params()["h_weight"] == h_weight
    check_tracker(t)


@pytest.mark.parametrize("tracker_cls", [DP4Tracker, DP8Tracker])
def test_a_row_where_the_path_walks_reports_a_place_the_stripe_is(tracker_cls):
    # the stripe jumps from column 10 to column 40 between rows 29 and 30;
    # with a small h_weight the path follows it, walking 30 columns along one
    # of those rows (the isotropic path would rather cut through the dark)
    rng = np.random.default_rng(12)
    img = rng.normal(8.0, 1.0, (60, 60))
    truth = np.where(np.arange(60) < 30, 10.0, 40.0)
    img[np.arange(60), truth.astype(int)] = 150.0
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    for hw in (0.25, 0.1):
        t = tracker_cls(h_weight=hw)
        cols = t.track(img).columns
        assert np.isfinite(cols).all()
        assert np.abs(cols - truth).max() <= 0.5, (hw, np.flatnonzero(np.abs(cols - truth) > 0.5))
        t.row_rule = "mean"  # the old rule: the walk's mean column, a place with no stripe
        assert np.abs(t.track(img).columns - truth).max() > 5


# --- the laser-off frame ----------------------------------------------------------------------------

BG_TRACKERS = ["dp4", "dp8", "dp8_subpixel", "dp_gap"]


@pytest.mark.parametrize("name", BG_TRACKERS)
def test_without_a_background_nothing_changes(name):
    import trackers

    from trackers.testing import make_ambient_pair

    on, off, _ = make_ambient_pair(seed=3)
    plain = trackers.make(name).track(on)
    # a black laser-off frame, and a background ignored by use_background=False: byte-identical results
    for out in (trackers.make(name).track(on, background=np.zeros(on.shape)),
                trackers.make(name, use_background=False).track(on, background=off)):
        assert out.columns.tobytes() == plain.columns.tobytes() and out.score.tobytes() == plain.score.tobytes()


@pytest.mark.parametrize("name", BG_TRACKERS)
def test_with_a_background_the_tracker_sees_the_signed_difference(name):
    import trackers

    from trackers.testing import make_ambient_pair

    on, off, truth = make_ambient_pair(seed=4)
    t = trackers.make(name)
    got = t.track(on, background=off)
    diff = on.astype(np.float64) - off.astype(np.float64)
    same = t.track(diff)
    assert got.columns.tobytes() == same.columns.tobytes() and got.score.tobytes() == same.score.tobytes()
    assert np.nanmax(np.abs(got.columns - truth)) < 1.5 and np.isfinite(got.columns).all()
    # without it the ambient bar, brighter than the stripe, takes the path
    alone = t.track(on).columns
    assert np.nanmedian(np.abs(alone - truth)) > 10.0


def test_the_path_of_a_pair_is_the_path_of_the_difference():
    from trackers.testing import make_ambient_pair

    on, off, _ = make_ambient_pair(seed=5)
    t = DP8Tracker()
    r1, c1, total1 = t.path(on, background=off)
    r2, c2, total2 = t.path(on.astype(np.float64) - off)
    assert np.array_equal(r1, r2) and np.array_equal(c1, c2) and total1 == total2
    with pytest.raises(ValueError, match="`background`"):
        t.path(on, background=off[:-1])
    with pytest.raises(ValueError, match="`use_background`"):
        DP8Tracker(use_background="yes").track(on)


@pytest.mark.parametrize("name", ["dp4", "dp8", "dp8_subpixel", "dp_gap"])
def test_reused_work_arrays_change_nothing(name):
    # the trackers reuse their work arrays per thread while the frame size stays the same:
    # results of a frame are the same after frames of another size and from other threads
    import threading

    import trackers

    frames = [make_stripe_image(height=h, width=w, seed=s)[0] for s, h, w in [(0, 40, 50), (1, 30, 70), (0, 40, 50)]]
    t = trackers.make(name)
    first = [t.track(f) for f in frames]
    assert first[0].columns.tobytes() == first[2].columns.tobytes()  # the same frame after another size
    again = {}

    def work(k):
        again[k] = [t.track(f) for f in frames[::-1]][::-1]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for k in range(3):
        for a, b in zip(first, again[k]):
            assert a.columns.tobytes() == b.columns.tobytes() and a.score.tobytes() == b.score.tobytes()
    if name != "dp_gap":
        r1, c1, total = t.path(frames[0])
        t.track(frames[1])
        assert t.path(frames[0])[2] == total


@pytest.mark.parametrize("name", ["dp4", "dp8", "dp_gap"])
@pytest.mark.parametrize("rule", [{}, {"k_sigma": 5.0, "max_gap": 4, "min_run": 6}, {"min_run": 200}])
def test_report_of_readings_is_track(name, rule):
    """The tuning procedure reads a frame once (readings) and applies many rules (report): the same as track."""
    import trackers
    from trackers.testing import make_score_image

    img, _ = make_score_image(seed=2)
    off = np.full_like(img, 10)
    t = trackers.make(name, **rule)
    for bg in (None, off):
        a = t.track(img, background=bg)
        b = t.report(*trackers.make(name).readings(img, bg)) if name != "dp_gap" else t.report(*t.readings(img, bg))
        np.testing.assert_array_equal(a.columns, b.columns)
        np.testing.assert_array_equal(a.score, b.score)


def test_min_run_drops_short_supported_stretches():
    import trackers
    from trackers.testing import make_score_image

    img, truth = make_score_image(seed=5)
    base = trackers.make("dp8", max_gap=3).track(img).columns
    strict = trackers.make("dp8", max_gap=3, min_run=1000).track(img).columns
    assert np.isnan(strict).all() and (~np.isnan(base)).sum() > 40


def test_min_run_on_a_frame_shorter_than_the_run():
    import trackers

    rng = np.random.default_rng(2)
    img = 10 + rng.normal(0, 1.0, (4, 60))
    img[:, 30] = 120
    assert DEFAULT_REPORT["min_run"] > 4
    assert trackers.make("dp8").track(img).columns.tolist() == [30.0] * 4  # support on every row of the frame
    img[3, 30] = 10
    assert np.isnan(trackers.make("dp8", max_gap=0).track(img).columns).all()  # 3 supported rows of 4
