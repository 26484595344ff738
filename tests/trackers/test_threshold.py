import numpy as np
import pytest

from trackers.threshold import ThresholdTracker


def test_reports_the_brightest_pixel_above_the_threshold():
    img = np.full((4, 10), 10, np.uint8)
    img[0, 3] = 200
    img[1, 7] = 200
    img[2, 5] = 30  # far below a quarter of the range: no stripe
    out = ThresholdTracker().track(img)
    assert out.columns[:2].tolist() == [3.0, 7.0]
    assert np.isnan(out.columns[2:]).all()


def test_default_threshold_follows_its_documented_rule():
    rng = np.random.default_rng(0)
    img = rng.normal(50, 2, (60, 80))
    img[:, 40] = 150
    img[10, 40] = 60  # only 5 sigma above the background: below rel * range
    t = ThresholdTracker(k_sigma=5.0, rel=0.25)
    out = t.track(img)
    assert np.isnan(out.columns[10]) and (out.columns[np.arange(60) != 10] == 40).all()
    # with rel=0 only the noise term remains and row 10 passes
    out0 = ThresholdTracker(k_sigma=3.0, rel=0.0).track(img)
    assert out0.columns[10] == 40


def test_explicit_threshold_overrides():
    img = np.zeros((2, 5), np.uint8)
    img[0, 1] = 100
    img[1, 2] = 40
    assert ThresholdTracker(threshold=50).track(img).columns[1] != 2
    assert ThresholdTracker(threshold=30).track(img).columns.tolist() == [1.0, 2.0]


def test_score_is_contrast_in_noise_units():
    rng = np.random.default_rng(1)
    img = rng.normal(20, 4, (50, 60))
    img[:, 30] = 220
    out = ThresholdTracker().track(img)
    assert np.allclose(out.score, (220 - 20) / 4, rtol=0.1)


@pytest.mark.parametrize(
    "params, message",
    [
        ({"threshold": "high"}, r"`threshold` must be a real number, got 'high'"),
        ({"k_sigma": -1}, r"`k_sigma` must be >= 0, got -1"),
        ({"rel": 1.5}, r"`rel` must be <= 1, got 1.5"),
        ({"rel": float("nan")}, r"`rel` must be a real number, got nan"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        ThresholdTracker(**params).track(np.zeros((3, 3)))
