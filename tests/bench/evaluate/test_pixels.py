"""Shrinking a frame as a camera app does (bench.evaluate.pixels.downscale) and its truth with it."""

import numpy as np
import pytest

from bench.evaluate.pixels import downscale, downscale_columns


def test_shrinking_averages_blocks_lowers_the_noise_and_keeps_the_stripe_where_it_was():
    rng = np.random.default_rng(0)
    x = np.arange(400.0)
    centre = 150.3 + 0.1 * np.arange(200)  # a slanted stripe, 200 rows
    big = 40.0 + 150.0 * np.exp(-0.5 * ((x[None, :] - centre[:, None]) / 4.0) ** 2) + rng.normal(0, 4.0, (200, 400))
    big8 = np.clip(np.rint(big), 0, 255).astype(np.uint8)
    small = downscale(big8, 4)
    assert small.shape == (50, 100) and small.dtype == np.uint8
    # the noise falls about 4-fold (16 pixels averaged), off the stripe
    assert np.std(small[:, :20].astype(float)) == pytest.approx(1.0, abs=0.35)
    # the shrunk truth lies on the shrunk stripe (centroid of the 7 pixels around each row's peak)
    truth = downscale_columns(centre, 4)
    rows = np.arange(50)
    peak = np.argmax(small, axis=1)
    cols = peak[:, None] + np.arange(-3, 4)[None, :]
    w = np.clip(small[rows[:, None], cols].astype(float) - 40.0, 0, None)
    centroid = (w * cols).sum(axis=1) / w.sum(axis=1)
    assert np.max(np.abs(centroid - truth)) < 0.15


def test_colour_images_shrink_per_channel_and_odd_edges_are_dropped():
    rgb = np.zeros((5, 7, 3), np.uint8)
    rgb[..., 1] = 200
    out = downscale(rgb, 2)
    assert out.shape == (2, 3, 3) and np.all(out[..., 1] == 200) and np.all(out[..., 0] == 0)
    assert downscale(rgb, 1) is not None and downscale(rgb, 1).shape == rgb.shape
    assert np.isnan(downscale_columns([1.0, np.nan, 3.0, 3.0], 2)[0])
    with pytest.raises(ValueError, match="factor"):
        downscale(rgb, 0)
