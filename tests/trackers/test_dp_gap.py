"""``dp_gap``: the solver against two independent oracles (Dijkstra on the explicit
graph, enumeration of every path on tiny frames) and the tracker's behaviour."""

import itertools

import numpy as np
import pytest
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

import trackers
from trackers.dp_gap import DPGapTracker, gap_nodes, gap_path
from trackers.testing import stripe_profile

SHAPES = [(1, 1), (1, 6), (6, 1), (2, 2), (3, 3), (2, 7), (7, 2), (12, 9), (9, 12), (25, 17), (6, 35), (4, 64)]


def random_costs(shape, kind, rng):
    if kind == "uniform":
        return rng.random(shape) + 0.01
    if kind == "lognormal":
        return np.exp(2.5 * rng.normal(size=shape))
    if kind == "bytes":  # 8-bit frames: exact ties everywhere
        return 1.0 / (rng.integers(0, 4, size=shape) * 60.0 + 1.0)
    return np.where(rng.random(shape) < 0.45, 1e-3, 1.0) + 1e-6 * rng.random(shape)


def explicit_graph(cost, off, switch, conn8, hw):
    """The graph of trackers._dp_gap's docstring as a sparse matrix: pixel (r, j) is node
    r * W + j, off node r is H * W + r; edges directed down or along the row."""
    H, W = cost.shape
    n = H * W + H
    src, dst, wt = [], [], []
    dg = np.sqrt(1.0 + hw * hw)

    def add(a, b, w):
        src.append(a)
        dst.append(b)
        wt.append(w)

    for r in range(H):
        for j in range(W):
            p = r * W + j
            if j + 1 < W:
                w = hw * 0.5 * (cost[r, j] + cost[r, j + 1])
                add(p, p + 1, w)
                add(p + 1, p, w)
            if r + 1 < H:
                add(p, p + W, 0.5 * (cost[r, j] + cost[r + 1, j]))
                if conn8:
                    for dj in (-1, 1):
                        if 0 <= j + dj < W:
                            add(p, p + W + dj, dg * 0.5 * (cost[r, j] + cost[r + 1, j + dj]))
                add(p, H * W + r + 1, 0.5 * (cost[r, j] + off[r + 1]) + switch)
                add(H * W + r, (r + 1) * W + j, 0.5 * (off[r] + cost[r + 1, j]) + switch)
        if r + 1 < H:
            add(H * W + r, H * W + r + 1, 0.5 * (off[r] + off[r + 1]))
    return csr_matrix((wt, (src, dst)), shape=(n, n))


def oracle(cost, off, switch, conn8, hw):
    """Distances from the top row and to the bottom row, and the optimum."""
    H, W = cost.shape
    g = explicit_graph(cost, off, switch, conn8, hw)
    top = list(range(W)) + [H * W]
    bottom = list(range((H - 1) * W, H * W)) + [H * W + H - 1]
    F = dijkstra(g, directed=True, indices=top, min_only=True)
    B = dijkstra(g.T.tocsr(), directed=True, indices=bottom, min_only=True)
    return F, B, float(F[bottom].min())


def brute_force(cost, off, switch, conn8, hw):
    """Every path, enumerated: a row holds either its off node or a walk from column a to b."""
    H, W = cost.shape
    dg = np.sqrt(1.0 + hw * hw)
    states = ["off"] + [(a, b) for a in range(W) for b in range(W)]

    def walk(r, a, b):
        lo, hi = min(a, b), max(a, b)
        return sum(hw * 0.5 * (cost[r, k] + cost[r, k + 1]) for k in range(lo, hi))

    def step(r, prev, cur):
        if prev == "off" and cur == "off":
            return 0.5 * (off[r - 1] + off[r])
        if prev == "off":
            return 0.5 * (off[r - 1] + cost[r, cur[0]]) + switch + walk(r, *cur)
        if cur == "off":
            return 0.5 * (cost[r - 1, prev[1]] + off[r]) + switch
        b, a = prev[1], cur[0]
        if a == b:
            e = 0.5 * (cost[r - 1, b] + cost[r, a])
        elif conn8 and abs(a - b) == 1:
            e = dg * 0.5 * (cost[r - 1, b] + cost[r, a])
        else:
            return None
        return e + walk(r, *cur)

    best, paths = np.inf, []
    for seq in itertools.product(states, repeat=H):
        total = 0.0 if seq[0] == "off" else walk(0, *seq[0])
        for r in range(1, H):
            e = step(r, seq[r - 1], seq[r])
            if e is None:
                break
            total += e
        else:
            paths.append((total, seq))
            best = min(best, total)
    on = np.zeros((H, W), bool)
    offm = np.zeros(H, bool)
    for total, seq in paths:
        if total <= best * (1 + 1e-12):
            for r, st in enumerate(seq):
                if st == "off":
                    offm[r] = True
                else:
                    on[r, min(st):max(st) + 1] = True
    return best, on, offm


def path_cost(cost, off, switch, rows, cols, offrows, hw):
    """The cost of a path returned by gap_path, summed edge by edge."""
    H = cost.shape[0]
    dg = np.sqrt(1.0 + hw * hw)
    nodes = []  # (row, col or None)
    k = 0
    for r in range(H):
        if offrows[r]:
            nodes.append((r, None))
        while k < rows.size and rows[k] == r:
            nodes.append((r, int(cols[k])))
            k += 1
    total = 0.0
    for (r0, c0), (r1, c1) in zip(nodes, nodes[1:]):
        if c0 is None and c1 is None:
            assert r1 == r0 + 1
            total += 0.5 * (off[r0] + off[r1])
        elif c0 is None or c1 is None:
            assert r1 == r0 + 1
            total += 0.5 * ((off[r0] if c0 is None else cost[r0, c0]) + (off[r1] if c1 is None else cost[r1, c1]))
            total += switch
        else:
            dr, dc = r1 - r0, abs(c1 - c0)
            assert (dr, dc) in ((0, 1), (1, 0), (1, 1))
            w = hw if dr == 0 else (1.0 if dc == 0 else dg)
            total += w * 0.5 * (cost[r0, c0] + cost[r1, c1])
    return total


CASES = [(shape, kind, conn, hw) for shape in SHAPES for kind in ("uniform", "lognormal", "bytes", "maze")
         for conn in (4, 8) for hw in (1.0, 0.25)]


@pytest.mark.parametrize("shape, kind, connectivity, hw", CASES)
def test_against_dijkstra_on_the_explicit_graph(shape, kind, connectivity, hw):
    rng = np.random.default_rng(hash((shape, kind, connectivity, hw)) % 2**32)
    H, W = shape
    for _ in range(3):
        cost = random_costs(shape, kind, rng)
        off = np.quantile(cost, rng.uniform(0.05, 0.6)) * np.exp(0.3 * rng.normal(size=H))
        switch = float(rng.choice([0.0, 0.5, 3.0])) * float(np.median(cost))
        F, B, opt = oracle(cost, off, switch, connectivity == 8, hw)
        rows, cols, offrows, total = gap_path(cost, off, switch, connectivity, hw)
        assert total == pytest.approx(opt, rel=1e-9, abs=1e-12)
        assert path_cost(cost, off, switch, rows, cols, offrows, hw) == pytest.approx(opt, rel=1e-9, abs=1e-12)
        on, crossing, offm, total2 = gap_nodes(cost, off, switch, connectivity, hw)
        assert total2 == total
        through = F + B
        px, ofs = through[: H * W].reshape(H, W), through[H * W :]
        # every node optimal to 1e-13 is labelled, none off by more than 1e-9
        assert (on >= (px <= opt * (1 + 1e-13) + 1e-300)).all() and (on <= (px <= opt * (1 + 1e-9))).all()
        assert (offm >= (ofs <= opt * (1 + 1e-13) + 1e-300)).all() and (offm <= (ofs <= opt * (1 + 1e-9))).all()
        assert on[rows, cols].all() and (offm >= offrows).all() and (crossing <= on).all()
        # every row holds an optimal pixel or an optimal off node
        assert (on.any(axis=1) | offm).all()


@pytest.mark.parametrize("shape", [(1, 3), (2, 3), (3, 2), (3, 3), (4, 2)])
@pytest.mark.parametrize("connectivity", [4, 8])
def test_union_of_optimal_paths_against_enumeration(shape, connectivity):
    rng = np.random.default_rng(shape[0] * 10 + shape[1] + connectivity)
    for trial in range(6):
        kind = ("uniform", "bytes", "maze")[trial % 3]
        cost = random_costs(shape, kind, rng)
        off = np.full(shape[0], float(np.quantile(cost, 0.3)))
        switch = (0.0, 0.2)[trial % 2]
        hw = (1.0, 0.25)[trial % 2]
        best, on_bf, off_bf = brute_force(cost, off, switch, connectivity == 8, hw)
        on, crossing, offm, total = gap_nodes(cost, off, switch, connectivity, hw)
        assert total == pytest.approx(best, rel=1e-12, abs=1e-15)
        np.testing.assert_array_equal(on, on_bf)
        np.testing.assert_array_equal(offm, off_bf)


def test_the_path_resumes_at_any_column_after_an_absence():
    cost = np.full((31, 40), 1.0)
    cost[:15, 3] = 0.01
    cost[16:, 36] = 0.01  # a 33-column jump across a dark row
    rows, cols, off, total = gap_path(cost, off_cost=0.5, switch_cost=0.2, connectivity=8, h_weight=0.25)
    assert off.tolist() == [False] * 15 + [True] + [False] * 15
    assert cols.tolist() == [3] * 15 + [36] * 15
    # with a dear switch and off node it walks along a row instead (the oracle agrees)
    rows, cols, off, total = gap_path(cost, off_cost=2.0, switch_cost=50.0, connectivity=8, h_weight=0.25)
    assert not off.any() and cols[0] == 3 and cols[-1] == 36
    assert total == pytest.approx(oracle(cost, np.full(31, 2.0), 50.0, True, 0.25)[2], rel=1e-12)


def test_cheap_rows_are_never_left_out():
    # the off node dearer than every pixel: the path stays on and equals the down-only DP
    rng = np.random.default_rng(5)
    cost = rng.random((30, 20)) + 0.1
    on, crossing, off, total = gap_nodes(cost, off_cost=2.0, switch_cost=0.0)
    assert not off.any()


@pytest.mark.parametrize("bad, message", [
    (dict(cost=np.zeros((3, 3))), "`cost`"),
    (dict(off_cost=0.0), "`off_cost`"),
    (dict(off_cost=np.ones(2)), "`off_cost`"),
    (dict(off_cost=np.inf), "`off_cost`"),
    (dict(switch_cost=-1.0), "`switch_cost`"),
    (dict(switch_cost=np.inf), "`switch_cost`"),
    (dict(connectivity=6), "`connectivity`"),
    (dict(h_weight=0.0), "`h_weight`"),
])
def test_solver_arguments_are_validated(bad, message):
    args = dict(cost=np.ones((3, 3)), off_cost=1.0, switch_cost=0.0, connectivity=8, h_weight=1.0)
    args.update(bad)
    with pytest.raises(ValueError, match=message):
        gap_path(**args)
    with pytest.raises(ValueError, match=message):
        gap_nodes(**args)


@pytest.mark.parametrize("bad, message", [
    (dict(off_rel=1.5), "`off_rel`"), (dict(off_rel=-0.1), "`off_rel`"), (dict(off_rel=float("nan")), "`off_rel`"),
    (dict(switch_rows=-1.0), "`switch_rows`"), (dict(switch_rows=float("inf")), "`switch_rows`"),
    (dict(connectivity=5), "`connectivity`"), (dict(use_background=1), "`use_background`"),
])
def test_tracker_parameters_are_validated(bad, message):
    with pytest.raises(ValueError, match=message):
        DPGapTracker(**bad).track(np.zeros((8, 8), np.uint8))


def test_registered():
    t = trackers.make("dp_gap")
    assert isinstance(t, DPGapTracker) and t.uses_background and t.connectivity == 8


def frame(centres, height=120, width=160, peak=150.0, noise=2.0, seed=0):
    """An 8-bit frame with the stripe at ``centres`` (NaN: no stripe in that row)."""
    rng = np.random.default_rng(seed)
    c = np.asarray(centres, float)
    img = 10.0 + rng.normal(0.0, noise, (height, width))
    lit = ~np.isnan(c)
    img[lit] += stripe_profile(c[lit], width, 1.5, peak)
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def test_rows_without_a_stripe_are_not_reported_where_dp8_bridges_them():
    truth = np.full(120, np.nan)
    truth[:45] = 40.3
    truth[75:] = 120.6  # an 80-column jump across 30 dark rows
    img = frame(truth)
    gap = trackers.make("dp_gap").track(img).columns
    dp8 = trackers.make("dp8", max_gap=None).track(img).columns  # the DP with the paper's bridging
    lit = ~np.isnan(truth)
    assert np.nanmax(np.abs(gap[lit] - truth[lit])) <= 1.0 and np.isfinite(gap[lit]).all()
    assert np.isnan(gap[50:70]).all()  # the dark middle is left out
    assert np.isfinite(dp8[50:70]).all()  # dp8 bridges it with columns the stripe never had
    assert np.nanmin(np.abs(dp8[50:70, None] - np.array([40.3, 120.6])[None]), axis=1).max() > 3.0


def test_a_short_dim_stretch_is_still_bridged():
    truth = 80.0 + 10.0 * np.sin(np.arange(120) / 19.0)
    rng = np.random.default_rng(1)
    img = frame(truth, seed=1).astype(float)
    # eight rows dimmer than the off level (10 + DEFAULT_OFF_REL * 150 = 85) but cheaper on than two
    # switches: the path stays on across them
    img[50:58] = 10.0 + rng.normal(0.0, 2.0, (8, 160)) + stripe_profile(truth[50:58], 160, 1.5, 60.0)
    cols = trackers.make("dp_gap").track(np.clip(np.rint(img), 0, 255).astype(np.uint8)).columns
    assert np.isfinite(cols).all() and np.abs(cols - truth).max() <= 1.5


def test_a_long_faint_stretch_is_left_out():
    truth = 80.0 + 10.0 * np.sin(np.arange(120) / 19.0)
    rng = np.random.default_rng(1)
    img = frame(truth, seed=1).astype(float)
    img[40:70] = 10.0 + rng.normal(0.0, 2.0, (30, 160)) + stripe_profile(truth[40:70], 160, 1.5, 12.0)
    cols = trackers.make("dp_gap").track(np.clip(np.rint(img), 0, 255).astype(np.uint8)).columns
    assert np.isnan(cols[45:65]).all() and np.abs(cols[:38] - truth[:38]).max() <= 1.5


def test_off_level_of_a_frame():
    t = DPGapTracker(off_rel=0.5, switch_rows=4.0, eps=1.0)
    img = np.full((10, 30), 20, np.uint8)
    img[:, 7] = 220  # every row's maximum is 220, the background 20: level 120
    from trackers.dp import _half_cost

    off, switch = t.off_costs(img, _half_cost(img, 1.0)[1])
    assert off == pytest.approx(1.0 / 121.0) and switch == pytest.approx(4.0 / 121.0)


def _dotted(seed=3):
    """A stripe of dots (column 30): 12 lit rows in every 36, so a third of the rows hold the stripe."""
    rng = np.random.default_rng(seed)
    img = rng.normal(20, 3, (144, 64))
    truth = np.full(144, np.nan)
    for start in range(6, 144, 36):
        img[start:start + 12, 29:32] += [80, 200, 80]
        truth[start:start + 12] = 30
    return img.clip(0, 255).astype(np.uint8), truth


def test_the_level_quantile_reads_the_stripe_brightness_where_few_rows_hold_it():
    img, truth = _dotted()
    gap = np.isnan(truth)
    # the median row maximum is the noise's: the off level sits in the noise and the path bridges the gaps
    median = DPGapTracker(off_rel=0.3, level_quantile=0.5).track(img).columns
    assert np.isfinite(median[gap]).mean() > 0.5 and np.isfinite(median[~gap]).all()
    # a high quantile reads the dots' brightness: the gaps are off, every dot row is found on its column
    high = DPGapTracker(off_rel=0.3, level_quantile=0.9).track(img).columns
    assert not np.isfinite(high[gap]).any()
    assert np.isfinite(high[~gap]).all() and np.all(np.abs(high[~gap] - 30) <= 1)


def test_the_default_level_is_the_median_row_maximum():
    from trackers.dp import _half_cost
    from trackers.dp_gap import DEFAULT_LEVEL_QUANTILE, _background

    img, _ = _dotted(4)
    img = img.astype(np.float64)
    _, rowmin, _, _ = _half_cost(img, 1.0)
    t = DPGapTracker(off_rel=0.4, level_quantile=0.5)
    level = _background(img) + 0.4 * (float(np.median(0.5 / rowmin - 1.0)) - _background(img))
    assert t.off_costs(img, rowmin)[0] == 1.0 / (level + 1.0)  # the median to the last bit
    assert DPGapTracker().level_quantile == DEFAULT_LEVEL_QUANTILE
    with pytest.raises(ValueError, match="`level_quantile`"):
        DPGapTracker(level_quantile=1.5).track(img)
