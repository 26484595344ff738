import numpy as np
import pytest

import trackers
from trackers.gauss3 import Gauss3Tracker
from trackers.testing import make_stripe_image


def sampled_stripe(centres, sigma=1.2, width=64, peak=150.0, bg=12.0):
    x = np.arange(width)
    return bg + peak * np.exp(-0.5 * ((x[None, :] - np.asarray(centres)[:, None]) / sigma) ** 2)


def test_registered():
    assert isinstance(trackers.make("gauss3"), Gauss3Tracker) and Gauss3Tracker.subpixel


def test_exact_on_sampled_gaussians_on_the_frames_background():
    # far from the stripe the pixels equal the background exactly, so the
    # frame's robust level is the true background and the fit is exact
    centres = 30 + np.linspace(-0.5, 0.5, 11)[:-1] + np.arange(10) * 0.3
    out = Gauss3Tracker().track(sampled_stripe(centres))
    assert np.allclose(out.columns, centres, atol=1e-9, rtol=0)


def test_better_than_centroid_on_narrow_noisy_stripes():
    # sigma 0.7 px: the half-maximum window holds one or two pixels
    errs = {"gauss3": [], "centroid": []}
    for seed in range(4):
        img, truth = make_stripe_image(sigma_px=0.7, noise=1.0, seed=seed)
        for name in errs:
            errs[name].append(np.abs(trackers.make(name).track(img).columns - truth))
    g = np.nanmean(np.concatenate(errs["gauss3"]))
    c = np.nanmean(np.concatenate(errs["centroid"]))
    assert g < 0.04 and g < 0.5 * c


def test_detection_and_score_are_the_threshold_trackers():
    img, _ = make_stripe_image(seed=3)
    img = img.copy()
    img[10:20] = 10  # no stripe in these rows
    got = Gauss3Tracker().track(img)
    ref = trackers.make("threshold").track(img)
    assert np.array_equal(np.isnan(got.columns), np.isnan(ref.columns))
    assert np.isnan(got.columns[10:20]).all()
    assert np.array_equal(got.score, ref.score, equal_nan=True)
    assert np.all(np.abs(got.columns - ref.columns)[~np.isnan(got.columns)] <= 0.5)


def test_saturated_plateau_and_border_peaks():
    img = np.zeros((2, 12), np.uint8)
    img[0, 3:9] = [60, 255, 255, 255, 255, 60]  # saturated: plateau centre
    img[1, 0:3] = [200, 90, 20]  # peak on the first column
    assert Gauss3Tracker(threshold=30).track(img).columns.tolist() == [5.5, 0.0]


@pytest.mark.parametrize(
    "params, message",
    [
        ({"threshold": "high"}, r"`threshold` must be a real number, got 'high'"),
        ({"k_sigma": -1}, r"`k_sigma` must be >= 0, got -1"),
        ({"prominence": -1.5}, r"`prominence` must be >= 0, got -1.5"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        Gauss3Tracker(**params).track(np.zeros((3, 3)))
