import numpy as np
import pytest

import trackers
from trackers.dp import DP8Tracker
from trackers.dp_subpixel import DP8SubpixelTracker
from trackers.testing import make_stripe_image


def gappy_frame(seed=11):
    """A stripe with a dim stretch (8 % contrast), a cut and a glint beside it."""
    img, truth = make_stripe_image(height=120, width=160, seed=seed, noise=1.0)
    img = img.astype(np.float64)
    img[40:70] = 10 + 0.08 * (img[40:70] - 10)
    img[90:95] = 10.0
    img[20:23, 10:13] = 255.0  # a glint far from the stripe
    return np.clip(np.rint(img), 0, 255).astype(np.uint8), truth


def test_registered():
    t = trackers.make("dp8_subpixel")
    assert isinstance(t, DP8SubpixelTracker) and t.subpixel and t.connectivity == 8
    assert t.get_params()["estimator"] == "blais_rioux"


def test_same_rows_as_dp8_with_subpixel_precision_where_supported():
    img, truth = gappy_frame()
    dp = DP8Tracker().track(img)
    hy = DP8SubpixelTracker().track(img)
    assert np.array_equal(np.isnan(hy.columns), np.isnan(dp.columns))
    refined = hy.score > 3.0
    assert refined.sum() > 100 and not refined[90:95].any()
    err_dp = np.abs(dp.columns - truth)[refined]
    err_hy = np.abs(hy.columns - truth)[refined]
    assert err_hy.mean() < 0.05 and err_dp.mean() > 0.15 and err_hy.max() < 0.3
    # the threshold family goes to the glint (or, by its default rules, reports nothing there); the hybrid does not
    plain = trackers.make("gauss3", min_run=1, prominence=0, stripe_test=None)
    assert np.abs(plain.track(img).columns[20:23] - truth[20:23]).min() > 20
    assert not (np.abs(trackers.make("gauss3").track(img).columns[20:23] - truth[20:23]) <= 3).any()
    assert np.abs(hy.columns[20:23] - truth[20:23]).max() < 0.3


def test_bridged_rows_keep_the_dp_column_and_a_low_score():
    img, _ = gappy_frame()
    dp = DP8Tracker().track(img)
    hy = DP8SubpixelTracker().track(img)
    bridged = ~np.isnan(hy.columns) & (hy.score <= 3.0)
    assert bridged[90:95].all()
    assert np.array_equal(hy.columns[bridged], dp.columns[bridged])
    assert np.array_equal(hy.score[bridged], np.minimum(dp.score[bridged], 3.0))
    refined = hy.score > 3.0
    assert np.array_equal(hy.score[refined], dp.score[refined])


@pytest.mark.parametrize("estimator", ["gauss3", "parabolic", "blais_rioux", "centroid"])
def test_refinement_is_the_estimators_tracker_on_a_clean_frame(estimator):
    img, _ = make_stripe_image(seed=5)
    hy = DP8SubpixelTracker(estimator=estimator).track(img).columns
    ref = trackers.make(estimator).track(img).columns
    assert np.isfinite(hy).all()
    if estimator in ("gauss3", "centroid"):  # these use a background level: the frame's here, each row's there
        assert np.abs(hy - ref).max() < 0.02
    else:
        assert np.array_equal(hy, ref)


def test_blank_and_noise_frames_report_nothing():
    rng = np.random.default_rng(0)
    assert np.isnan(DP8SubpixelTracker().track(rng.normal(20, 3, (120, 100))).columns).all()


@pytest.mark.parametrize(
    "params, message",
    [
        ({"estimator": "steger"}, r"`estimator` must be one of 'blais_rioux', 'centroid', 'gauss3', 'parabolic', "
                                  r"got 'steger'"),
        ({"estimator": None}, r"`estimator` must be one of .*, got None"),
        ({"search": -1}, r"`search` must be >= 0, got -1"),
        ({"frac": 1}, r"`frac` must be < 1, got 1"),
        ({"half_window": 1.5}, r"`half_window` must be an integer, got 1.5"),
        ({"eps": 0}, r"`eps` must be > 0, got 0"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        DP8SubpixelTracker(**params).track(np.zeros((3, 3)))
