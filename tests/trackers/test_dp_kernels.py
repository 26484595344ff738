import numpy as np

from trackers import _dp_kernels as K


def _stats(hc):
    rowmin = np.empty(hc.shape[0])
    centre = np.empty(hc.shape[0], np.int64)
    K.row_stats(hc, rowmin, centre)
    return rowmin, centre


def _field(img, conn8):
    hc = 0.5 / (img.astype(np.float64) + 1.0)
    D = np.empty_like(hc)
    K.accumulate(hc, conn8, True, D, *_stats(hc))
    return hc, D


def _union(img, conn8):
    hc, D = _field(img, conn8)
    H, W = img.shape
    mark = np.zeros((H, W), np.uint8)
    r = np.empty(H * W, np.int64)
    c = np.empty(H * W, np.int64)
    n = K.optimal_nodes(D, hc, conn8, 1e-11, mark, r, c)
    return mark, n


def test_union_of_optimal_paths_is_flip_symmetric_with_ties():
    rng = np.random.default_rng(0)
    img = rng.integers(0, 4, (30, 20)).astype(np.uint8)  # many exact ties
    for conn8 in (False, True):
        a, _ = _union(img, conn8)
        b, _ = _union(img[::-1].copy(), conn8)
        assert np.array_equal(a, b[::-1])


def test_union_contains_the_backtracked_path_and_every_tie():
    img = np.zeros((4, 3), np.uint8)  # every straight column is optimal
    mark, n = _union(img, False)
    assert n == 12 and (mark & 1).all()
    hc, D = _field(img, False)
    rows = np.empty(12, np.int64)
    cols = np.empty(12, np.int64)
    m = K.backtrack(D, hc, False, rows, cols)
    assert (mark[rows[:m], cols[:m]] & 1).all()
    assert (mark[rows[:m], cols[:m]] & 2).all()  # straight down: every node crosses rows


def test_bounded_and_exact_fields_agree_on_the_optimum():
    rng = np.random.default_rng(1)
    img = rng.integers(0, 255, (50, 40)).astype(np.uint8)
    for conn8 in (False, True):
        hc, D = _field(img, conn8)
        Dx = np.empty_like(D)
        K.accumulate(hc, conn8, False, Dx, *_stats(hc))
        assert D[-1].min() == Dx[-1].min() or abs(D[-1].min() - Dx[-1].min()) <= 1e-12 * Dx[-1].min()
        assert (D >= Dx * (1 - 1e-12)).all()  # bounded values are upper bounds


def test_half_cost_kernels_agree_and_report_row_minima():
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (20, 30)).astype(np.uint8)
    img[5, :] = 7  # a constant row: the leftmost column
    out = []
    for arr, kernel in ((img, K.half_cost_u8), (img.astype(np.float64), K.half_cost_float)):
        hc = np.empty(img.shape)
        rowmin = np.empty(20)
        centre = np.empty(20, np.int64)
        kernel(arr, 1.0, hc, rowmin, centre)
        out.append((hc, rowmin, centre))
    (a, am, ac), (b, bm, bc) = out
    assert np.array_equal(a, b) and np.array_equal(am, bm) and np.array_equal(ac, bc)
    np.testing.assert_array_equal(a, 0.5 / (img + 1.0))
    np.testing.assert_array_equal(ac, np.argmax(img, axis=1))
    assert ac[5] == 0
    np.testing.assert_array_equal(am, a.min(axis=1))
