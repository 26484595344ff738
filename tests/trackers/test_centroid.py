import numpy as np
import pytest

from trackers.centroid import CentroidTracker
from trackers.testing import make_stripe_image


def test_symmetric_profile_gives_its_centre():
    img = np.zeros((1, 11))
    img[0, 4:7] = [50, 100, 50]
    assert CentroidTracker().track(img).columns[0] == pytest.approx(5.0)
    img[0, 4:8] = [50, 100, 100, 50]
    assert CentroidTracker().track(img).columns[0] == pytest.approx(5.5)


def test_weights_are_above_the_level():
    # background 0, peak 100 at column 5, frac 0.5 -> level 50: weights 30, 50, 10
    img = np.zeros((1, 41))  # wide enough that the row's noise comes from its background
    img[0, 3:8] = [20, 80, 100, 60, 40]
    expected = (4 * 30 + 5 * 50 + 6 * 10) / 90
    assert CentroidTracker(frac=0.5).track(img).columns[0] == pytest.approx(expected)


def test_window_is_contiguous_and_bounded():
    img = np.zeros((1, 30))
    img[0, 10:13] = [60, 100, 60]
    img[0, 16] = 90  # a separate glint above the level, beyond a dark gap
    assert CentroidTracker().track(img).columns[0] == pytest.approx(11.0)
    wide = np.zeros((1, 60))  # a plateau above the level, wider than the window
    wide[0, 5:26] = 100
    wide[0, 15] = 101
    assert CentroidTracker(half_window=2).track(wide).columns[0] == pytest.approx(15.0, abs=0.01)


def test_subpixel_accuracy_on_synthetic_stripes():
    errs = []
    for seed in range(5):
        img, truth = make_stripe_image(seed=seed, noise=1.0)
        errs.append(np.abs(CentroidTracker().track(img).columns - truth))
    assert np.mean(np.concatenate(errs)) < 0.05


@pytest.mark.parametrize(
    "params, message",
    [
        ({"frac": 1.0}, r"`frac` must be < 1, got 1.0"),
        ({"frac": -0.1}, r"`frac` must be >= 0, got -0.1"),
        ({"half_window": 2.5}, r"`half_window` must be an integer, got 2.5"),
        ({"half_window": -1}, r"`half_window` must be >= 0, got -1"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        CentroidTracker(**params).track(np.zeros((3, 3)))
