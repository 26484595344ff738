import numpy as np
import pytest

import trackers
from trackers.com_bg import ComBgTracker
from trackers.testing import make_stripe_image


def test_registered():
    assert isinstance(trackers.make("com_bg"), ComBgTracker) and ComBgTracker.subpixel


def test_weights_are_the_difference_above_the_row_level_within_the_window():
    off = np.full((1, 40), 30.0)
    on = off.copy()
    on[0, 10:15] = [33, 80, 130, 100, 40]  # D = 3, 50, 100, 70, 10
    on[0, 20] = 45  # D = 15, beyond the window: ignored
    # D's row median is 0: T = frac * 100 -> with frac = 0.25 the weights 50, 100, 70
    got = ComBgTracker(frac=0.25, half_window=5).track(on, background=off).columns[0]
    assert got == pytest.approx((11 * 50 + 12 * 100 + 13 * 70) / 220)
    assert ComBgTracker(threshold=5.0, half_window=5).track(on, background=off).columns[0] == pytest.approx(
        (11 * 50 + 12 * 100 + 13 * 70 + 14 * 10) / 230)


def test_the_dim_half_of_a_stripe_in_a_bright_frame_keeps_its_rows():
    # the earlier level, a quarter of the frame's maximum of D, dropped rows 40-79
    rng = np.random.default_rng(7)
    off = 60 + rng.normal(0, 1.0, (80, 120))
    on = off.copy()
    on[:40, 50:53] += [60, 200, 60]  # bright half
    on[40:, 50:53] += [10, 35, 10]  # dim half
    cols = ComBgTracker().track(on, background=off).columns
    assert np.isfinite(cols).all() and np.abs(cols - 51).max() < 0.3


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
    # documented: without a laser-off frame ambient light is not removed, and the
    # brighter ambient object takes the rows from the stripe
    on, _, truth = ambient_scene()
    cols = ComBgTracker().track(on).columns
    with np.errstate(invalid="ignore"):
        assert not (np.abs(cols - truth) <= 3).any()  # the object wins, or the row is ambiguous and not reported
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
