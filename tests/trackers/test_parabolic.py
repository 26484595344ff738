import numpy as np
import pytest

import trackers
from trackers.parabolic import ParabolicTracker


def test_registered():
    assert isinstance(trackers.make("parabolic"), ParabolicTracker) and ParabolicTracker.subpixel


def test_exact_on_parabolic_peaks_whatever_the_background():
    vertices = np.array([20.0, 20.3, 20.5, 19.6, 21.45])
    x = np.arange(48)
    img = np.clip(200.0 - 30.0 * (x[None, :] - vertices[:, None]) ** 2, 37.0, None)
    assert np.allclose(ParabolicTracker().track(img).columns, vertices, atol=1e-12, rtol=0)


def test_biased_towards_the_pixel_centre_on_gaussians():
    # the classic bias of the parabola on a Gaussian: the estimated offset
    # has the sign of the true one but a smaller magnitude
    phases = np.array([-0.4, -0.25, -0.1, 0.1, 0.25, 0.4])
    x = np.arange(48)
    img = 10 + 150 * np.exp(-0.5 * ((x[None, :] - (24 + phases[:, None])) / 1.0) ** 2)
    est = ParabolicTracker().track(img).columns - 24
    assert np.all(np.sign(est) == np.sign(phases))
    assert np.all(np.abs(est) < np.abs(phases) - 0.005)


@pytest.mark.parametrize(
    "params, message",
    [({"k_sigma": "5"}, r"`k_sigma` must be a real number, got '5'"), ({"prominence": -0.1}, r"`prominence` must be >= 0, got -0.1")],
)
def test_bad_parameters(params, message):
    with pytest.raises(ValueError, match=message):
        ParabolicTracker(**params).track(np.zeros((3, 3)))
