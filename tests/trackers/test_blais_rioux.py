import numpy as np
import pytest

import trackers
from trackers.blais_rioux import BlaisRiouxTracker
from trackers.testing import make_stripe_image


def test_registered():
    assert isinstance(trackers.make("blais_rioux"), BlaisRiouxTracker) and BlaisRiouxTracker.subpixel


def test_symmetric_profiles_give_their_centre():
    img = np.zeros((3, 16))
    img[0, 4:9] = [10, 60, 100, 60, 10]  # centre 6
    img[1, 4:10] = [10, 60, 100, 100, 60, 10]  # centre 6.5
    img[2, 3:11] = [10, 60, 255, 255, 255, 255, 60, 10]  # saturated, centre 6.5
    assert BlaisRiouxTracker().track(img).columns.tolist() == [6.0, 6.5, 6.5]


@pytest.mark.parametrize("length", [2, 3, 4, 5, 6, 7, 8, 11])
def test_saturated_plateaus_of_any_length_give_their_centre(length):
    img = np.zeros((1, 40))
    img[0, 10 : 10 + length] = 255
    img[0, 9] = img[0, 10 + length] = 90  # symmetric flanks
    assert BlaisRiouxTracker().track(img).columns[0] == pytest.approx(10 + (length - 1) / 2)


def test_zero_crossing_is_interpolated_linearly():
    img = np.zeros((1, 24))
    img[0, 2:8] = [20, 70, 100, 80, 30, 5]
    g = lambda i: img[0, i - 2] + img[0, i - 1] - img[0, i + 1] - img[0, i + 2]  # noqa: E731
    expected = 4 + g(4) / (g(4) - g(5))
    assert BlaisRiouxTracker().track(img).columns[0] == pytest.approx(expected)


def test_error_shrinks_with_noise():
    def mae(noise):
        errs = []
        for seed in range(3):
            img, truth = make_stripe_image(sigma_px=1.5, noise=noise, seed=seed)
            errs.append(np.abs(BlaisRiouxTracker().track(img).columns - truth))
        return np.nanmean(np.concatenate(errs))

    assert mae(0.5) < 0.6 * mae(4.0)


def test_bad_parameters():
    with pytest.raises(ValueError, match=r"`threshold` must be a real number, got nan"):
        BlaisRiouxTracker(threshold=float("nan")).track(np.zeros((3, 3)))
