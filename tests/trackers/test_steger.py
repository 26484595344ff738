import math

import numpy as np
import pytest
from scipy import ndimage as ndi
from scipy.special import erf

import trackers
from trackers.steger import (FALLBACK_WIDTH, SCALE_PER_WIDTH, StegerTracker, acceptance, default_sigma, estimate_width,
                             gaussian_derivatives)


def line_image(slope=0.0, sigma=1.5, height=80, width=96, peak=150.0, bg=10.0, noise=0.0, offset=0.0, seed=0):
    """A straight stripe x = x0 + slope * (y - y0), Gaussian profile across the
    line (standard deviation ``sigma`` normal to it), sampled at pixel centres."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[:height, :width].astype(float)
    x0 = width / 2 + offset
    truth = x0 + slope * (np.arange(height) - height / 2)
    dist = (x - x0 - slope * (y - height / 2)) / math.hypot(1.0, slope)
    img = bg + peak * np.exp(-0.5 * (dist / sigma) ** 2) + rng.normal(0.0, noise, (height, width))
    return img, truth


def test_registered_and_scale():
    t = trackers.make("steger")
    assert isinstance(t, StegerTracker) and t.subpixel
    assert t.scale() == pytest.approx(default_sigma(FALLBACK_WIDTH))  # no frame, no width: the fallback
    assert StegerTracker(width=8.0).scale() == pytest.approx(default_sigma(8.0))
    assert StegerTracker(sigma=2.0, width=8.0).scale() == 2.0
    assert StegerTracker(width=1.0).scale() == 0.6  # floored


@pytest.mark.parametrize("full_width", [1, 3, 6, 10, 15])
def test_the_scale_follows_the_stripe_width_measured_on_the_frame(full_width):
    img = np.full((30, 80), 20.0)
    img[:, 30:30 + full_width] = 250.0  # a clipped bar of that width
    assert estimate_width(img) == full_width
    assert StegerTracker().scale(img) == pytest.approx(max(0.6, SCALE_PER_WIDTH * full_width))
    assert estimate_width(np.zeros((5, 5))) == FALLBACK_WIDTH


@pytest.mark.parametrize("sigma_px, peak", [(0.5, 150.0), (1.5, 150.0), (3.0, 150.0), (5.0, 150.0), (3.0, 2000.0),
                                            (6.0, 3000.0)])
def test_stripes_of_1_to_15_px_and_saturated_plateaus(sigma_px, peak):
    # pixel-integrated Gaussian stripes (FWHM 1.2-14 px), clipped at 255 where the peak is higher
    from trackers.testing import stripe_profile

    rng = np.random.default_rng(4)
    centre = 60.3 + 0.2 * (np.arange(90) - 45)  # straight and tilted: no curvature bias
    img = np.clip(np.rint(15 + stripe_profile(centre, 128, sigma_px, peak) + rng.normal(0, 2, (90, 128))), 0, 255)
    cols = StegerTracker().track(img.astype(np.uint8)).columns
    err = np.abs(cols - centre)
    assert np.mean(err <= 3.0) >= 0.95, (sigma_px, peak, np.nanmedian(err))
    if peak < 255:  # unclipped: sub-pixel
        assert np.nanmedian(err) < 0.15, (sigma_px, np.nanmedian(err))


def test_background_frame_is_subtracted():
    rng = np.random.default_rng(5)
    img, truth = line_image(noise=1.0, seed=5)
    lamp = np.zeros_like(img)
    lamp[:, 10:14] = 400.0  # a bright line of ambient light, in both frames
    off = 10 + rng.normal(0, 1.0, img.shape) + lamp
    on = img + lamp
    with_off = StegerTracker().track(on, background=off).columns
    assert np.nanmax(np.abs(with_off[5:-5] - truth[5:-5])) < 0.2
    without = StegerTracker().track(on).columns
    assert np.mean(np.abs(without - truth) > 5) > 0.9  # the ambient line wins without the laser-off frame
    # no background: exactly what the plain frame gives
    np.testing.assert_array_equal(StegerTracker().track(img).columns,
                                  StegerTracker().track(img, background=None).columns)


@pytest.mark.parametrize("factor", [1e300, 1e-300, 3.7, 1e-5])
def test_image_scale_does_not_change_the_rows(factor):
    img, _ = line_image(noise=2.0, seed=6)
    img[:10] = 10.0  # rows with no stripe
    base = StegerTracker().track(img)
    scaled = StegerTracker().track(img * factor)
    np.testing.assert_array_equal(np.isnan(base.columns), np.isnan(scaled.columns))
    np.testing.assert_allclose(scaled.columns, base.columns, rtol=0, atol=1e-4)
    np.testing.assert_allclose(scaled.score / factor, base.score, rtol=1e-5)


def test_derivatives_are_scipys_gaussian_derivatives():
    rng = np.random.default_rng(1)
    img = rng.normal(100, 20, (30, 41))
    d = gaussian_derivatives(img, 1.3)
    assert d.shape == (5, 41, 30) and d.dtype == np.float32
    # (row order, column order) of scipy's 2-D filter for rx, ry, rxx, rxy, ryy
    for k, order in enumerate([(0, 1), (1, 0), (0, 2), (1, 1), (2, 0)]):
        ref = ndi.gaussian_filter(img, 1.3, order=order, mode="nearest")
        assert np.allclose(d[k].T, ref, rtol=0, atol=2e-4 * np.abs(ref).max() + 1e-4), order


def test_acceptance_bounds_the_newton_overshoot():
    assert acceptance(1e3) == pytest.approx(0.5, abs=1e-6)
    assert acceptance(0.51) == 1.0
    for w in (0.8, 1.2, 2.0):  # ridge std after smoothing; never below the scale
        x = 0.5
        t = x * w * w / (w * w - x * x)
        assert t <= acceptance(w) + 1e-12


@pytest.mark.parametrize("slope", [0.0, 0.35, -1.0])
@pytest.mark.parametrize("offset", [0.0, 0.25, 0.5])
def test_straight_lines_of_any_tilt_and_phase(slope, offset):
    # the row crossing of a tilted ridge is j + t / n_x; every row is reported,
    # including phase 0.5 where the ridge lies on a pixel boundary
    img, truth = line_image(slope=slope, offset=offset)
    err = np.abs(StegerTracker().track(img).columns[10:-10] - truth[10:-10])
    assert np.isfinite(err).all()
    # noise-free, the error is the Newton step's overshoot x^3 / (w^2 - x^2)
    # at distance x <= 0.5 from the ridge (w^2 = 1.5^2 + 1.15^2): <= 0.038 px
    assert err.max() < 0.04


def test_error_on_a_pixel_boundary_is_the_taylor_overshoot():
    img, truth = line_image(offset=0.5)  # vertical, centre between two pixels
    t = StegerTracker(sigma=1.2)
    err = t.track(img).columns[10:-10] - truth[10:-10]
    w2 = 1.5**2 + 1.2**2  # the ridge's variance after smoothing
    assert np.allclose(np.abs(err), 0.5**3 / (w2 - 0.25), rtol=0.02, atol=0)


def test_ridges_tilted_beyond_max_tilt_are_not_reported():
    img, _ = line_image(slope=2.0, width=200)  # 63 degrees from the vertical
    assert np.isnan(StegerTracker().track(img).columns[10:-10]).all()
    assert np.isfinite(StegerTracker(max_tilt=70.0).track(img).columns[10:-10]).all()


def test_bright_smooth_areas_and_dark_rows_report_nothing():
    img, _ = line_image(noise=1.0)
    img[:20] = 10 + np.random.default_rng(2).normal(0, 1.0, (20, img.shape[1]))  # stripe cut
    img[30:40, :] = np.linspace(10, 160, img.shape[1])  # a bright ramp, no ridge, stripe hidden
    cols = StegerTracker().track(img).columns
    assert np.isnan(cols[:18]).all() and np.isnan(cols[32:38]).all()
    assert np.isfinite(cols[45:75]).all()


def test_score_is_the_ridge_strength():
    img, _ = line_image(sigma=1.5)
    s = StegerTracker(sigma=1.2).track(img).score[40]
    # -d2/dx2 of the smoothed line at its centre: peak * w / (w^2 + s^2)^1.5
    assert s == pytest.approx(150.0 * 1.5 / (1.5**2 + 1.2**2) ** 1.5, rel=0.03)


def test_scale_trades_noise_for_curvature():
    # a noisy straight stripe: the larger scale averages more noise
    img, truth = line_image(noise=6.0, sigma=2.0, seed=3)
    err = {s: np.nanmean(np.abs(StegerTracker(sigma=s).track(img).columns - truth)) for s in (0.8, 2.0)}
    assert err[2.0] < 0.8 * err[0.8]


@pytest.mark.parametrize(
    "params, message",
    [
        ({"sigma": 0.5}, r"`sigma` must be > 0.5, got 0.5"),
        ({"sigma": float("inf")}, r"`sigma` must be <= 64, got inf"),
        ({"sigma": float("nan")}, r"`sigma` must be a real number, got nan"),
        ({"sigma": "2"}, r"`sigma` must be a real number, got '2'"),
        ({"width": 0}, r"`width` must be > 0, got 0"),
        ({"width": -3.0}, r"`width` must be > 0, got -3.0"),
        ({"width": 1e9}, r"`width` must be <= 256, got 1000000000.0"),
        ({"max_tilt": 90}, r"`max_tilt` must be < 90, got 90"),
        ({"max_tilt": -5}, r"`max_tilt` must be >= 0, got -5"),
    ],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        StegerTracker(**params).track(np.zeros((3, 3)))


def test_pixel_integrated_profile():
    x = np.arange(64) - 0.5
    c = 31.3
    prof = 0.5 * np.diff(erf((np.append(x, 63.5) - c) / (np.sqrt(2) * 1.5)))
    img = 10 + 400 * np.tile(prof, (40, 1))
    assert np.nanmax(np.abs(StegerTracker().track(img).columns[5:-5] - c)) < 0.02
