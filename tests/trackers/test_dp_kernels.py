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


def _sequential_walks(Dr, hr, hw, first, last):
    """The walk along a row as the plain loops: the left-to-right chain, then
    the right-to-left one over its result (the former kernel's order)."""
    d = Dr.copy()
    for j in range(first + 1, last + 1):
        y = d[j - 1] + hw * (hr[j - 1] + hr[j])
        d[j] = y if y < d[j] else d[j]
    for j in range(last - 1, first - 1, -1):
        y = d[j + 1] + hw * (hr[j] + hr[j + 1])
        d[j] = y if y < d[j] else d[j]
    return d


def test_the_four_chain_walk_equals_the_plain_chains_bit_for_bit():
    rng = np.random.default_rng(3)
    W = 90
    scratch = [np.empty(W) for _ in range(3)]
    cases = 0
    for n in list(range(2, 40)) + [64, 65, 89, 90]:  # short (two chains), even and odd halves
        for _ in range(4):
            first = int(rng.integers(0, W - n + 1))
            last = first + n - 1
            hw = float(rng.choice([1.0, 0.25, 0.01, 3.0]))
            hr = 0.5 / (rng.integers(0, 256, W) + 1.0)
            # values with improvements to carry far (steps cheaper than the gaps) and none at all
            Dr = np.where(rng.random(W) < 0.3, rng.random(W), np.inf) * rng.choice([1.0, 50.0])
            expected = _sequential_walks(Dr, hr, hw, first, last)
            got = Dr.copy()
            K._chains(got, hr, hw, first, last, np.inf, 1.0, *scratch)
            assert got.tobytes() == expected.tobytes(), (n, first, hw)
            cases += 1
    assert cases == 4 * 42


def test_the_vertical_relaxation_reports_its_improved_range():
    rng = np.random.default_rng(4)
    for conn8 in (False, True):
        for _ in range(50):
            W = int(rng.integers(1, 40))
            a = int(rng.integers(0, W))
            b = int(rng.integers(a, W))
            hs, hr = 0.5 / (rng.integers(0, 256, (2, W)) + 1.0)
            Ds = rng.random(W) * 5
            Dr = np.where(rng.random(W) < 0.5, rng.random(W) * 5, np.inf)
            limit = float(rng.choice([np.inf, 2.5]))
            dg = np.sqrt(2.0)
            cand = Ds + (hs + hr)
            if conn8 and W > 1:
                left = np.full(W, np.inf)
                left[1:] = Ds[:-1] + dg * (hs[:-1] + hr[1:])
                right = np.full(W, np.inf)
                right[:-1] = Ds[1:] + dg * (hs[1:] + hr[:-1])
                cand = np.minimum(np.minimum(cand, left), right)
            improved = np.zeros(W, bool)
            improved[a : b + 1] = (cand < Dr)[a : b + 1] & (cand < limit)[a : b + 1]
            expected = Dr.copy()
            expected[a : b + 1] = np.minimum(Dr, cand)[a : b + 1]
            got = Dr.copy()
            n, nch, first, last = K._vertical(got, Ds, hr, hs, conn8, dg, a, b, limit, 1.0 - 1e-12)
            assert got.tobytes() == expected.tobytes()
            assert n == improved.sum() and nch == n  # improvements here are far above the tolerance
            if n:
                assert (first, last) == (np.flatnonzero(improved)[0], np.flatnonzero(improved)[-1])


def test_half_cost_kernels_give_the_rightmost_minimum():
    rng = np.random.default_rng(5)
    img = rng.integers(0, 8, (30, 25)).astype(np.uint8)  # many tied brightest pixels
    img[4] = 3  # a constant row: its whole width
    for arr, kernel in ((img, K.half_cost_u8), (img.astype(np.float64), K.half_cost_float)):
        hc = np.empty(img.shape)
        rowmin = np.empty(30)
        centre = np.empty(30, np.int64)
        rightc = np.empty(30, np.int64)
        kernel(arr, 1.0, hc, rowmin, centre, rightc)
        np.testing.assert_array_equal(centre, np.argmax(img, axis=1))
        np.testing.assert_array_equal(rightc, 24 - np.argmax(img[:, ::-1], axis=1))
        assert rightc[4] == 24 and centre[4] == 0
        # accumulate finds the same columns itself when not given them
        D1 = np.empty_like(hc)
        D2 = np.empty_like(hc)
        K.accumulate(hc, True, True, D1, rowmin, centre, 0.5, rightc)
        K.accumulate(hc, True, True, D2, rowmin, centre, 0.5)
        assert D1.tobytes() == D2.tobytes()
