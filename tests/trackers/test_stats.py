import numpy as np

from trackers._stats import _stride, default_threshold, noise_floor, robust_level, row_peaks


def test_robust_level_ignores_a_thin_bright_stripe():
    rng = np.random.default_rng(0)
    img = rng.normal(20.0, 3.0, (480, 512))
    img[:, 200:205] = 250.0
    bg, sigma, vmax = robust_level(img)
    assert abs(bg - 20.0) < 0.3
    assert abs(sigma - 3.0) < 0.2
    assert vmax == 250.0


def test_robust_level_is_dtype_invariant():
    rng = np.random.default_rng(1)
    img = rng.integers(0, 40, (100, 90)).astype(np.uint8)
    assert robust_level(img) == robust_level(img.astype(np.float64))


def test_stride_is_coprime_with_width():
    from math import gcd

    for width in (512, 640, 96, 7, 1):
        step = _stride(480 * width, width)
        assert width == 1 or gcd(step, width) == 1


def test_sampling_does_not_alias_onto_one_column():
    # a stripe on a column that a stride sharing a factor with the width would
    # hit in every row must not move the median
    img = np.zeros((480, 512))
    for col in range(0, 512, 2):
        img[:, col] = 100.0  # every even column bright: half the frame
    bg, _, _ = robust_level(img)
    assert bg in (0.0, 50.0, 100.0)  # a fair sample straddles both halves
    sample_cols = np.arange(0, img.size, _stride(img.size, 512)) % 512
    assert 0.3 < np.mean(sample_cols % 2 == 0) < 0.7


def test_row_peaks_leftmost_on_ties():
    img = np.array([[1, 5, 5], [7, 0, 7]], np.uint8)
    cols, vals = row_peaks(img)
    assert cols.tolist() == [1, 0] and vals.tolist() == [5.0, 7.0]


def test_noise_floor_and_threshold():
    assert noise_floor(2.0, 10.0, 200.0) == 2.0
    assert noise_floor(0.0, 10.0, 210.0) == 0.2
    assert noise_floor(0.0, 5.0, 5.0) > 0.0
    assert default_threshold(10.0, 2.0, 210.0, 5.0, 0.25) == 60.0
    assert default_threshold(10.0, 20.0, 50.0, 5.0, 0.25) == 110.0
