"""The per-row detection statistics and rule (trackers._detect)."""

import numpy as np
import pytest

from trackers._detect import MAX_SAMPLES, _median, detect_rows, row_statistics


def stats(img):
    H = img.shape[0]
    col, mid, lo, hi = (np.empty(H, np.int64) for _ in range(4))
    peak, bg, noise, runner = (np.empty(H) for _ in range(4))
    row_statistics(img, col, mid, peak, bg, noise, runner, lo, hi)
    return dict(col=col, mid=mid, peak=peak, bg=bg, noise=noise, runner=runner, lo=lo, hi=hi)


@pytest.mark.parametrize("n", [1, 2, 3, 10, 11, 256])
def test_median_is_numpys(n):
    rng = np.random.default_rng(n)
    for _ in range(20):
        v = rng.integers(0, 5, n).astype(float)  # many ties
        assert _median(v.copy(), n) == np.median(v)


def test_row_statistics_on_a_known_row():
    row = np.full(40, 10.0)
    row[20:23] = [50, 90, 50]  # the stripe: half-contrast run 21 only (50 is not > 50)
    row[5] = 30.0  # the runner-up
    s = stats(row[None, :])
    assert s["col"][0] == 21 and s["mid"][0] == 21 and s["peak"][0] == 90 and s["bg"][0] == 10
    assert (s["lo"][0], s["hi"][0]) == (21, 21) and s["runner"][0] == 30
    assert s["noise"][0] == 0.0  # most adjacent pixels are equal


def test_noise_measures_pixel_noise_not_texture():
    rng = np.random.default_rng(0)
    x = np.arange(512)
    texture = 80 * (np.sin(x / 15.0) > 0) + 40 * np.sin(x / 40.0)  # print blocks and shading
    img = 100 + texture[None, :] + rng.normal(0, 2.0, (200, 512))
    s = stats(img)
    assert np.median(s["noise"]) == pytest.approx(2.0, rel=0.15)
    assert np.std(img[0]) > 20  # what a frame-wide spread would have measured


def test_plateau_middle_and_sampling():
    img = np.zeros((2, 3 * MAX_SAMPLES))
    img[0, 100:109] = 255  # a clipped plateau
    img[1, 7] = 1
    s = stats(img)
    assert s["col"].tolist() == [100, 7] and s["mid"].tolist() == [104, 7]
    assert (s["lo"][0], s["hi"][0]) == (100, 108)


def test_rule_and_explicit_threshold():
    rng = np.random.default_rng(1)
    img = 50 + rng.normal(0, 2.0, (4, 300))
    img[0, 100] = 50 + 40  # 20 sigma
    img[1, 100] = 50 + 8  # 4 sigma: below k_sigma = 5
    img[2, 100] = 50 + 40
    img[2, 200] = 50 + 35  # a runner-up with 7/8 of the contrast
    d = detect_rows(img, 5.0, 1.5)
    assert d.hit.tolist()[:3] == [True, False, False]
    assert detect_rows(img, 2.0, 0.0).hit[1] and detect_rows(img, 5.0, 1.1).hit[2]
    assert d.score[0] == pytest.approx((90 - d.bg[0]) / d.noise[0]) and d.noise[0] == pytest.approx(2.0, rel=0.15)
    assert detect_rows(img, 5.0, 1.5, threshold=80.0).hit.tolist() == [True, False, True, False]


def test_constant_and_dtype_invariance():
    assert not detect_rows(np.full((5, 9), 7.0), 0.0, 0.0).hit.any()
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (30, 70)).astype(np.uint8)
    a, b = detect_rows(img, 3.0, 1.2), detect_rows(img.astype(np.float64), 3.0, 1.2)
    for f in ("col", "mid", "peak", "bg", "noise", "runner_up", "hit", "score"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f))


def test_min_run_on_a_frame_shorter_than_the_run():
    # a 4-row frame cannot hold a 5-row chain: a stripe through all of its rows is the longest there can be
    rng = np.random.default_rng(2)
    img = 10 + rng.normal(0, 1.0, (4, 60))
    img[:, 30] = 120
    assert detect_rows(img, 4.0, 1.1, min_run=5).hit.all()
    img[3, 30] = 10  # three rows of four: shorter than the frame, and than min_run
    assert not detect_rows(img, 4.0, 1.1, min_run=5).hit.any()
    assert detect_rows(img, 4.0, 1.1, min_run=3).hit[:3].all()
