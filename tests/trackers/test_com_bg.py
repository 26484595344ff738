import numpy as np
import pytest

import trackers
from trackers.com_bg import ComBgTracker
from trackers.testing import make_stripe_image


def test_registered():
    assert isinstance(trackers.make("com_bg"), ComBgTracker) and ComBgTracker.subpixel


def test_weights_are_the_difference_above_the_threshold_within_the_window():
    off = np.full((1, 40), 30.0)
    on = off.copy()
    on[0, 10:15] = [33, 80, 130, 100, 40]  # D = 3, 50, 100, 70, 10
    on[0, 20] = 120  # beyond the window: ignored
    # D has median 0 and no spread: T = 0.25 * max(D) = 25 -> weights 50, 100, 70
    got = ComBgTracker(half_window=5).track(on, background=off).columns[0]
    assert got == pytest.approx((11 * 50 + 12 * 100 + 13 * 70) / 220)
    assert ComBgTracker(threshold=5.0, half_window=5).track(on, background=off).columns[0] == pytest.approx(
        (11 * 50 + 12 * 100 + 13 * 70 + 14 * 10) / 230)


def ambient_scene(seed=0):
    """A stripe plus a bright ambient object on its left (laser-off frame has the object too)."""
    img, truth = make_stripe_image(seed=seed, noise=1.0)
    rng = np.random.default_rng(seed)
    off = np.full(img.shape, 10.0) + rng.normal(0, 1.0, img.shape)
    obj = np.zeros(img.shape)
    obj[:, 5:25] = 240.0  # a bright object, brighter than the stripe
    on = np.clip(img + obj, 0, 255).astype(np.uint8)
    off = np.clip(np.rint(off + obj), 0, 255).astype(np.uint8)
    return on, off, truth


def test_laser_off_frame_removes_ambient_light():
    on, off, truth = ambient_scene()
    out = ComBgTracker().track(on, background=off)
    assert np.isfinite(out.columns).all()
    assert np.mean(np.abs(out.columns - truth)) < 0.12


def test_fallback_without_background_sees_the_ambient_object():
    # documented: without a laser-off frame only the frame's flat level is
    # subtracted, and the brighter ambient object wins the rows
    on, _, truth = ambient_scene()
    cols = ComBgTracker().track(on).columns
    assert np.mean(np.abs(cols - truth) > 5) > 0.9
    # ... but on a dark scene the fallback works
    img, truth = make_stripe_image(seed=4)
    assert np.mean(np.abs(ComBgTracker().track(img).columns - truth)) < 0.1


@pytest.mark.parametrize(
    "params, message",
    [
        ({"half_window": -1}, r"`half_window` must be >= 0, got -1"),
        ({"half_window": 2.0}, r"`half_window` must be an integer, got 2.0"),
        ({"k_sigma": None}, r"`k_sigma` must be a real number, got None"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        ComBgTracker(**params).track(np.zeros((3, 3)))
