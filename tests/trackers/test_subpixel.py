"""The shared sub-pixel estimator kernels (trackers._subpixel)."""

import numpy as np
import pytest

from trackers._subpixel import (
    ESTIMATORS,
    LOG_FLOOR,
    blais_rioux_column,
    blais_rioux_filter,
    estimate,
    gauss3_offset,
    parabola_offset,
    plateau,
    refine,
)


def gaussian_row(centre, sigma=1.0, width=32, peak=100.0, bg=10.0):
    x = np.arange(width)
    return (bg + peak * np.exp(-0.5 * ((x - centre) / sigma) ** 2))[None, :]


@pytest.mark.parametrize("phase", [-0.49, -0.3, 0.0, 0.17, 0.45])
@pytest.mark.parametrize("sigma", [0.6, 1.0, 2.5])
def test_gauss3_is_exact_on_a_sampled_gaussian(phase, sigma):
    row = gaussian_row(12 + phase, sigma)[0]
    d = gauss3_offset(row[11], row[12], row[13], 10.0)
    assert d == pytest.approx(phase, abs=1e-9)


def test_gauss3_floors_tails_below_the_background():
    # the left neighbour is below the background (noise): floored, so the
    # offset stays finite, inside half a pixel, towards the brighter side
    d = gauss3_offset(5.0, 100.0, 60.0, 10.0)
    floor = np.log(LOG_FLOOR * 90.0)
    expected = 0.5 * (floor - np.log(50.0)) / (floor - 2 * np.log(90.0) + np.log(50.0))
    assert d == pytest.approx(expected) and 0 < d <= 0.5
    assert gauss3_offset(10.0, 10.0, 10.0, 10.0) == 0.0  # no contrast


@pytest.mark.parametrize("vertex", [-0.4, 0.0, 0.25])
def test_parabola_is_exact_on_a_parabola(vertex):
    a, b, c = (100.0 - 7.0 * (x - vertex) ** 2 for x in (-1, 0, 1))
    assert parabola_offset(a, b, c) == pytest.approx(vertex, abs=1e-12)
    assert parabola_offset(5.0, 5.0, 5.0) == 0.0


def test_blais_rioux_filter_and_symmetric_profiles():
    img = np.array([[0, 10, 60, 100, 60, 10, 0]], dtype=np.float64)
    # g(i) = I(i-2) + I(i-1) - I(i+1) - I(i+2), edges repeated
    assert blais_rioux_filter(img, 0, 2) == 0 + 10 - 100 - 60
    assert blais_rioux_filter(img, 0, 0) == 0 + 0 - 10 - 60
    assert blais_rioux_column(img, 0, 3) == 3.0
    two_tops = np.array([[0, 10, 60, 100, 100, 60, 10, 0]], dtype=np.float64)
    assert blais_rioux_column(two_tops, 0, 3) == 3.5


def test_blais_rioux_interpolates_linearly_between_the_right_pixels():
    img = np.array([[0, 20, 70, 100, 80, 30, 5, 0]], dtype=np.float64)
    # I(4) > I(2): the crossing lies in [3, 4]
    g3 = 20 + 70 - 80 - 30
    g4 = 70 + 100 - 30 - 5
    assert blais_rioux_column(img, 0, 3) == pytest.approx(3 + g3 / (g3 - g4))


def test_plateaus_are_centred():
    sat = np.array([[0, 40, 255, 255, 255, 255, 40, 0, 0]], dtype=np.uint8)
    assert plateau(sat, 0, 3) == (2, 5)
    for name in ("gauss3", "parabolic", "blais_rioux", "centroid"):
        assert estimate(sat, 0, 2, 0.0, ESTIMATORS[name], 0.5, 7) == pytest.approx(3.5), name


def test_uint8_and_float_rows_give_identical_estimates():
    rng = np.random.default_rng(0)
    img = np.clip(gaussian_row(15.3, 1.3) + rng.normal(0, 2, (1, 32)), 0, 255).round().astype(np.uint8)
    for code in ESTIMATORS.values():
        a = estimate(img, 0, 15, 10.0, code, 0.5, 7)
        b = estimate(img.astype(np.float64), 0, 15, 10.0, code, 0.5, 7)
        assert a == b


def test_refine_searches_a_window_and_requires_a_local_maximum():
    img = np.zeros((3, 20))
    img[:, 8:11] = [50, 100, 50]
    out = np.empty(3)
    ok = np.empty(3, dtype=np.bool_)
    centre = np.array([10, 7, 13])  # 1, 2 and 4 columns away from the peak at 9
    refine(img, centre, np.array([True, True, True]), np.zeros(3), ESTIMATORS["parabolic"], 2, 0.5, 7, out, ok)
    assert ok.tolist() == [True, True, False]
    assert out[:2].tolist() == [9.0, 9.0] and np.isnan(out[2])
    # the window's brightest pixel at its edge, with a brighter one outside: not a peak
    refine(img, np.array([6, 6, 6]), np.array([True, False, True]), np.zeros(3), ESTIMATORS["gauss3"], 2, 0.5, 7,
           out, ok)
    assert ok.tolist() == [False, False, False] and np.isnan(out).all()
