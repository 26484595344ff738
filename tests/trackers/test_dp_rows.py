"""``trackers._dp_rows.marked_rows`` (the DP trackers' row summaries) against a plain-Python
reference written from its docstring, hand-computed rows and its documented contract."""

import math
import statistics

import numpy as np
import pytest

import trackers
from trackers import _dp_rows as R
from trackers.testing import make_stripe_image

RULES = {"mean": R.RULE_MEAN, "crossing": R.RULE_CROSSING, "brightest": R.RULE_BRIGHTEST}


def reference(image, mark, rows, cols, inner, outer, rule):
    """The docstring of ``marked_rows``, one row at a time, on Python floats and lists.

    Returns ``(col, contrast, side_sd, span)`` as lists of length H.
    """
    H, W = image.shape
    px = [[float(v) for v in row] for row in image]
    out_col, out_contrast, out_sd, out_span = [math.nan] * H, [math.nan] * H, [math.nan] * H, [0] * H
    for r in range(H):
        nodes = sorted(int(c) for rr, c in zip(rows, cols) if rr == r)
        if not nodes:
            continue
        out_span[r] = nodes[-1] - nodes[0] + 1
        if rule == R.RULE_MEAN:
            col = statistics.fmean(nodes)
            level = statistics.fmean(px[r][c] for c in nodes)
        else:
            candidates = nodes
            if rule == R.RULE_CROSSING:
                candidates = [c for c in nodes if mark[r, c] & 2] or nodes
            level = max(px[r][c] for c in candidates)
            tied = [c for c in candidates if px[r][c] == level]  # ascending columns
            col = float(tied[(len(tied) - 1) // 2])  # the lower median
        centre = math.floor(col + 0.5)
        near = [px[r][j] for j in range(centre - outer, centre + outer + 1) if 0 <= j < W]
        half = 0.5 * (level + min(near + [level]))
        sides = []
        for step in (-1, 1):
            ext = 0  # columns next to the centre at or above half height, at most 64
            while ext < 64 and 0 <= centre + step * (ext + 1) < W and px[r][centre + step * (ext + 1)] >= half:
                ext += 1
            shift = max(0, ext - (inner - 2))
            sides += [px[r][centre + step * d] for d in range(inner + shift, outer + shift + 1)
                      if 0 <= centre + step * d < W]
        out_col[r] = col
        if len(sides) >= 2:
            out_sd[r] = statistics.stdev(sides)
            out_contrast[r] = level - statistics.fmean(sides)
        elif len(sides) == 1:
            out_contrast[r] = level - sides[0]
        else:
            out_contrast[r] = 0.0
    return out_col, out_contrast, out_sd, out_span


def kernel(image, mark, rows, cols, inner, outer, rule, fill=123.0):
    """``marked_rows`` on outputs pre-filled with ``fill`` (so a row it skips shows)."""
    H = image.shape[0]
    col, contrast, side_sd = (np.full(H, fill) for _ in range(3))
    span = np.full(H, int(fill), np.int64)
    R.marked_rows(image, mark, np.asarray(rows, np.int64), np.asarray(cols, np.int64), inner, outer, rule,
                  col, contrast, side_sd, span)
    return col, contrast, side_sd, span


def labels(shape, nodes, crossing=()):
    """``mark``, ``rows``, ``cols`` for labelled ``nodes`` [(r, c), ...], bit 2 on those in ``crossing``."""
    mark = np.zeros(shape, np.uint8)
    for r, c in nodes:
        mark[r, c] |= 1
    for r, c in crossing:
        mark[r, c] |= 3
    rows = np.array([r for r, _ in nodes], np.int64)
    cols = np.array([c for _, c in nodes], np.int64)
    return mark, rows, cols


def assert_matches_reference(image, mark, rows, cols, inner, outer, rule):
    got = kernel(image, mark, rows, cols, inner, outer, rule)
    want = reference(image, mark, rows, cols, inner, outer, rule)
    col, contrast, side_sd, span = got
    np.testing.assert_array_equal(col, want[0])  # NaN where NaN, else the same column exactly
    np.testing.assert_array_equal(span, want[3])
    scale = max(1.0, float(np.max(np.abs(image))))
    np.testing.assert_allclose(contrast, want[1], rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(side_sd, want[2], rtol=1e-9, atol=1e-7 * scale)  # sum-of-squares formula


def random_labels(rng, H, W):
    """A random set of labelled nodes: in some rows none, in others a run or scattered columns."""
    nodes, crossing = [], []
    for r in range(H):
        kind = rng.integers(4)
        if kind == 0:
            continue
        if kind == 1:  # a run, as where a path walks along the row
            a = int(rng.integers(W))
            b = int(rng.integers(a, min(W, a + 6)))
            cs = list(range(a, b + 1))
        else:
            cs = sorted(set(rng.integers(0, W, int(rng.integers(1, 5))).tolist()))
        nodes += [(r, c) for c in cs]
        crossing += [(r, c) for c in cs if rng.random() < 0.4]
    order = rng.permutation(len(nodes))  # the kernels list nodes in no particular order
    return labels((H, W), [nodes[k] for k in order], crossing)


# -- against the reference -------------------------------------------------------------------------

@pytest.mark.parametrize("rule", RULES.values(), ids=RULES.keys())
@pytest.mark.parametrize("dtype", [np.uint8, np.float64])
def test_random_frames_match_the_reference(rule, dtype):
    rng = np.random.default_rng(36 + rule)
    for _ in range(40):
        H, W = int(rng.integers(1, 9)), int(rng.integers(1, 40))
        if dtype == np.uint8:
            image = rng.integers(0, 4 if rng.random() < 0.5 else 256, (H, W)).astype(np.uint8)  # few levels: ties
        else:
            image = rng.normal(50.0, 30.0, (H, W))
            if rng.random() < 0.5:
                image = np.round(image / 10.0) * 10.0  # ties, and negative values
        inner = int(rng.integers(1, 6))
        outer = inner + int(rng.integers(0, 8))
        assert_matches_reference(image, *random_labels(rng, H, W), inner, outer, rule)


@pytest.mark.parametrize("rule", RULES.values(), ids=RULES.keys())
def test_wide_stripes_match_the_reference(rule):
    """Plateaus wider than ``inner - 2`` (the side windows move out), some wider than 64 columns."""
    rng = np.random.default_rng(7)
    for width in (1, 3, 5, 9, 30, 70, 150):
        W = width + 60
        image = rng.integers(0, 20, (3, W)).astype(np.float64)
        a = int(rng.integers(0, W - width + 1))
        image[:, a : a + width] = 200.0 + rng.integers(0, 2, (3, width))
        nodes = [(r, c) for r in range(3) for c in range(a, a + width) if rng.random() < 0.5] or [(0, a)]
        mark, rows, cols = labels(image.shape, nodes, nodes[::3])
        assert_matches_reference(image, mark, rows, cols, 4, 12, rule)


@pytest.mark.parametrize("rule", RULES.values(), ids=RULES.keys())
@pytest.mark.parametrize("name", ["dp4", "dp8", "dp_gap"])
def test_the_trackers_labels_match_the_reference(name, rule):
    """On the labelled optimal-path nodes a tracker really gives (stripe frames with a cut)."""
    from trackers import dp_stages as S

    t = trackers.make(name)
    for seed in range(3):
        image, _ = make_stripe_image(40, 50, seed=seed, noise=2.0)
        image[15:19] = 5
        mark, rows, cols = S.labelled_nodes(t, image)
        assert_matches_reference(image, mark, rows, cols, t.side_inner, t.side_outer, rule)


# -- hand-computed rows ----------------------------------------------------------------------------

def test_a_narrow_stripe_by_hand():
    image = np.array([[1, 2, 3, 4, 5, 20, 100, 20, 6, 7, 8, 9, 10]], np.uint8)
    mark, rows, cols = labels(image.shape, [(0, 6)], [(0, 6)])
    for rule in RULES.values():
        col, contrast, side_sd, span = kernel(image, mark, rows, cols, 3, 5, rule)
        # half height (100 + 2) / 2: no neighbour above it, so the sides are 3..5 columns away:
        # columns 1, 2, 3 (2, 3, 4) and 9, 10, 11 (7, 8, 9); mean 5.5, squared deviations sum 41.5
        assert col[0] == 6.0 and span[0] == 1
        assert contrast[0] == pytest.approx(100 - 5.5, abs=1e-12)
        assert side_sd[0] == pytest.approx(math.sqrt(41.5 / 5), abs=1e-12)


def test_a_wide_stripe_moves_the_side_windows_out():
    # a plateau of 200 on columns 8..16, elsewhere the column index
    image = np.arange(25, dtype=np.float64)[None, :].copy()
    image[0, 8:17] = 200.0
    plateau = [(0, c) for c in range(8, 17)]
    mark, rows, cols = labels(image.shape, plateau, [(0, 8), (0, 16)])
    # brightest and mean: the 9 tied columns' lower median, 12 (the mean column is 12 too);
    # low = min(7..17) = 7, half = 103.5: 4 columns on either side above it, so each window moves
    # out by 4 - (3 - 2) = 3 columns: 6..8 columns from the centre, 6, 5, 4 and 18, 19, 20
    for rule in (R.RULE_BRIGHTEST, R.RULE_MEAN):
        col, contrast, side_sd, span = kernel(image, mark, rows, cols, 3, 5, rule)
        assert col[0] == 12.0 and span[0] == 9
        assert contrast[0] == pytest.approx(200 - 12, abs=1e-12)
        assert side_sd[0] == pytest.approx(math.sqrt(2 * (64 + 49 + 36) / 5), abs=1e-12)
    # crossing: the crossing nodes 8 and 16 tie; the lower median is 8. Low = min(3..13) = 3, half
    # 101.5: no column left of 8 above it, 8 right of it (9..16), so the right window moves out by
    # 8 - 1 = 7 columns: 5, 4, 3 and 18, 19, 20
    col, contrast, side_sd, span = kernel(image, mark, rows, cols, 3, 5, R.RULE_CROSSING)
    assert col[0] == 8.0 and span[0] == 9
    sides = [5, 4, 3, 18, 19, 20]
    assert contrast[0] == pytest.approx(200 - sum(sides) / 6, abs=1e-12)
    assert side_sd[0] == pytest.approx(statistics.stdev(sides), rel=1e-12)


def test_the_half_height_extent_is_at_most_64_columns():
    # a flat plateau on columns 26..174 around the node at 100: its extent counts 64 columns on
    # either side (of 74), so the windows move out by 62, to 66..74 columns away: columns 34..26 and
    # 166..174, the plateau's last ones: no contrast, no spread. One column more, or no cap, and
    # they would reach the dark beyond it.
    image = np.zeros((1, 200))
    image[0, 26:175] = 100.0
    mark, rows, cols = labels(image.shape, [(0, 100)])
    col, contrast, side_sd, span = kernel(image, mark, rows, cols, 4, 12, R.RULE_BRIGHTEST)
    assert (col[0], contrast[0], side_sd[0], span[0]) == (100.0, 0.0, 0.0, 1)


def test_side_windows_are_clipped_to_the_image():
    image = np.array([[50.0, 0.0, 10.0, 30.0, 7.0, 7.0]])
    mark, rows, cols = labels(image.shape, [(0, 0)])
    col, contrast, side_sd, span = kernel(image, mark, rows, cols, 2, 3, R.RULE_BRIGHTEST)
    # at column 0 only the right window (columns 2, 3) is inside the image
    assert col[0] == 0.0
    assert contrast[0] == pytest.approx(50 - 20.0, abs=1e-12)
    assert side_sd[0] == pytest.approx(math.sqrt(200.0), abs=1e-12)


def test_one_side_pixel_gives_a_contrast_and_no_spread():
    image = np.array([[50.0, 0.0, 10.0]])
    mark, rows, cols = labels(image.shape, [(0, 0)])
    col, contrast, side_sd, span = kernel(image, mark, rows, cols, 2, 5, R.RULE_BRIGHTEST)
    assert col[0] == 0.0 and contrast[0] == 40.0 and np.isnan(side_sd[0]) and span[0] == 1


def test_no_side_pixel_gives_zero_contrast():
    image = np.array([[9.0], [4.0]])  # one column: no pixel beside the path
    mark, rows, cols = labels(image.shape, [(0, 0), (1, 0)])
    for rule in RULES.values():
        col, contrast, side_sd, span = kernel(image, mark, rows, cols, 1, 3, rule)
        assert col.tolist() == [0.0, 0.0] and contrast.tolist() == [0.0, 0.0]
        assert np.isnan(side_sd).all() and span.tolist() == [1, 1]


@pytest.mark.parametrize("ties, want", [([1, 4, 6, 9], 4), ([2, 5, 8], 5), ([3], 3), ([0, 11], 0)])
def test_ties_in_brightness_go_to_the_lower_median(ties, want):
    image = np.full((1, 12), 10, np.uint8)
    image[0, ties] = 90
    nodes = [(0, c) for c in range(12)]  # every column labelled, a crossing node at each tie
    for rule, crossing in ((R.RULE_BRIGHTEST, []), (R.RULE_CROSSING, [(0, c) for c in ties])):
        col = kernel(image, *labels(image.shape, nodes, crossing), 4, 6, rule)[0]
        assert col[0] == want


def test_the_crossing_rule_prefers_a_dimmer_crossing_node():
    image = np.array([[0, 10, 80, 60, 20, 0, 0, 0]], np.uint8)
    nodes = [(0, 1), (0, 2), (0, 3), (0, 4)]
    crossing = kernel(image, *labels(image.shape, nodes, [(0, 3), (0, 4)]), 1, 2, R.RULE_CROSSING)
    brightest = kernel(image, *labels(image.shape, nodes, [(0, 3), (0, 4)]), 1, 2, R.RULE_BRIGHTEST)
    assert crossing[0][0] == 3.0 and brightest[0][0] == 2.0
    assert crossing[3][0] == brightest[3][0] == 4  # the span counts every labelled node


def test_without_crossing_nodes_the_crossing_rule_is_the_brightest_rule():
    rng = np.random.default_rng(3)
    image = rng.integers(0, 256, (6, 20)).astype(np.uint8)
    mark, rows, cols = random_labels(rng, 6, 20)
    mark &= 1  # no bit 2 anywhere
    for a, b in zip(kernel(image, mark, rows, cols, 2, 6, R.RULE_CROSSING),
                    kernel(image, mark, rows, cols, 2, 6, R.RULE_BRIGHTEST)):
        np.testing.assert_array_equal(a, b)


def test_the_mean_rule_reports_the_mean_column_and_intensity():
    image = np.array([[0.0, 0.0, 0.0, 40.0, 60.0, 0.0, 0.0, 0.0, 0.0]])
    col, contrast, side_sd, span = kernel(image, *labels(image.shape, [(0, 3), (0, 4)]), 2, 3, R.RULE_MEAN)
    # column 3.5 (centred on 4), level 50; half height 25: column 3 is above it on the left, so the
    # left window moves out by 1 - 0 = 1 (columns 1, 0), the right one stays (6, 7): all zero
    assert col[0] == 3.5 and span[0] == 2
    assert contrast[0] == 50.0 and side_sd[0] == 0.0


# -- the contract ----------------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(1, 1), (1, 7), (5, 3)])
def test_no_labelled_node_gives_nan_everywhere(shape):
    image = np.ones(shape, np.uint8)
    for rule in RULES.values():
        col, contrast, side_sd, span = kernel(image, *labels(shape, []), 1, 2, rule)
        assert np.isnan(col).all() and np.isnan(contrast).all() and np.isnan(side_sd).all()
        assert (span == 0).all()


def test_rows_without_nodes_at_the_ends_are_nan():
    rng = np.random.default_rng(11)
    image = rng.integers(0, 256, (7, 15)).astype(np.uint8)
    nodes = [(r, c) for r in (2, 3, 4) for c in (5, 6)]
    for rule in RULES.values():
        col, contrast, side_sd, span = kernel(image, *labels(image.shape, nodes, nodes[:2]), 2, 4, rule)
        empty = np.array([True, True, False, False, False, True, True])
        assert np.isnan(col[empty]).all() and np.isnan(contrast[empty]).all() and np.isnan(side_sd[empty]).all()
        assert (span[empty] == 0).all() and (span[~empty] == 2).all()
        assert np.isfinite(col[~empty]).all() and np.isfinite(contrast[~empty]).all()


@pytest.mark.parametrize("rule", RULES.values(), ids=RULES.keys())
def test_the_column_is_a_node_or_between_the_nodes(rule):
    rng = np.random.default_rng(5)
    for _ in range(30):
        H, W = int(rng.integers(1, 8)), int(rng.integers(1, 30))
        image = rng.integers(0, 6, (H, W)).astype(np.uint8)
        mark, rows, cols = random_labels(rng, H, W)
        col, contrast, side_sd, span = kernel(image, mark, rows, cols, 2, 5, rule)
        for r in range(H):
            cs = set(cols[rows == r].tolist())
            if not cs:
                continue
            assert span[r] == max(cs) - min(cs) + 1
            assert min(cs) <= col[r] <= max(cs)
            if rule != R.RULE_MEAN:
                assert col[r] in cs
                assert image[r, int(col[r])] == max(image[r, c] for c in cs
                                                    if rule == R.RULE_BRIGHTEST or mark[r, c] & 2
                                                    or not any(mark[r, k] & 2 for k in cs))
            assert np.isnan(side_sd[r]) or side_sd[r] >= 0


def test_the_order_of_the_nodes_and_the_dtype_do_not_matter():
    rng = np.random.default_rng(8)
    image = rng.integers(0, 256, (9, 25)).astype(np.uint8)
    mark, rows, cols = random_labels(rng, 9, 25)
    order = rng.permutation(rows.size)
    for rule in RULES.values():
        a = kernel(image, mark, rows, cols, 3, 7, rule)
        b = kernel(image, mark, rows[order], cols[order], 3, 7, rule)
        c = kernel(image.astype(np.float64), mark, rows, cols, 3, 7, rule)
        for x, y, z in zip(a, b, c):
            np.testing.assert_array_equal(x, y)  # integer intensities: every sum is exact
            np.testing.assert_array_equal(x, z)


def test_the_rule_codes_are_the_trackers_row_rules():
    from trackers.dp import ROW_RULES

    assert ROW_RULES == {"crossing": R.RULE_CROSSING, "mean": R.RULE_MEAN, "brightest": R.RULE_BRIGHTEST}
    assert len(set(ROW_RULES.values())) == 3
