"""Image conditions on synthetic frames with known values (bench.evaluate.conditions)."""

import math

import numpy as np
import pytest

from bench.evaluate import conditions as cond
from bench.evaluate.predict_settings import DEFAULT, PredictSettings

H, W = 120, 160


def _stripe(amp=100.0, sigma=2.0, base=20.0, noise=2.0, col=80.0, seed=0, rows=None):
    rng = np.random.default_rng(seed)
    x = np.arange(W, dtype=float)
    f = np.full((H, W), base) + rng.normal(0.0, noise, (H, W))
    prof = amp * np.exp(-0.5 * ((x - col) / sigma) ** 2)
    r = np.arange(H) if rows is None else rows
    f[r] += prof
    return f


def test_noise_width_contrast_and_background_of_a_gaussian_stripe():
    c = cond.measure(_stripe(amp=100.0, sigma=2.0, base=20.0, noise=2.0))
    assert c.noise_dn == pytest.approx(2.0, rel=0.1)
    assert c.width_px == pytest.approx(2.3548 * 2.0, rel=0.1)
    assert c.contrast == pytest.approx(100.0 / 2.0, rel=0.15)  # the argmax rides the noise a little
    assert c.background == pytest.approx(20.0 / 255.0, abs=0.01)
    assert c.visible == 1.0 and c.jumps == 0.0 and c.gaps == 0.0 and c.saturated == 0.0
    assert c.texture == pytest.approx(1.0, abs=0.15)
    assert c.rival < 0.2
    assert math.isnan(c.laser_share)


@pytest.mark.parametrize("sigma", [1.5, 3.0, 6.0])
def test_width_follows_sigma(sigma):
    assert cond.measure(_stripe(sigma=sigma, noise=1.0)).width_px == pytest.approx(2.3548 * sigma, rel=0.12)


def test_contrast_scales_with_amplitude_over_noise():
    a = cond.measure(_stripe(amp=40.0, noise=2.0)).contrast
    b = cond.measure(_stripe(amp=160.0, noise=2.0)).contrast
    assert b / a == pytest.approx(4.0, rel=0.15)


def test_texture_against_noise():
    rng = np.random.default_rng(1)
    f = _stripe(noise=1.0)
    flat = cond.measure(f).texture
    tex = f + rng.normal(0.0, 5.0, (H, W // 4)).repeat(4, axis=1)[:, :W] * (np.arange(H)[:, None] >= 40)
    t = cond.measure(tex)
    assert flat < 1.2 and t.texture > 2.0  # a quarter of the tiles stay flat: the noise is still 1 DN
    assert t.noise_dn == pytest.approx(1.0, rel=0.25)


def test_a_second_ridge_is_a_rival_of_its_relative_height():
    x = np.arange(W, dtype=float)
    f = _stripe(amp=100.0, noise=1.0) + 50.0 * np.exp(-0.5 * ((x - 30.0) / 2.0) ** 2)
    assert cond.measure(f).rival == pytest.approx(0.5, abs=0.08)


def test_gaps_visible_fraction_and_jumps():
    rows = np.r_[0:40, 60:90, 100:120]
    c = cond.measure(_stripe(rows=rows, noise=1.0))
    assert c.visible == pytest.approx(rows.size / H, abs=0.02)
    assert c.gaps == pytest.approx(100.0 * 2 / H, abs=1e-9)  # two interior runs of dark rows
    f = _stripe(noise=1.0, rows=np.arange(60)) + 0.0
    x = np.arange(W, dtype=float)
    f[60:] += 100.0 * np.exp(-0.5 * ((x - 120.0) / 2.0) ** 2)  # the stripe steps 40 px at row 60
    assert cond.measure(f).jumps == pytest.approx(1.0 / (H - 1), abs=1e-9)


def test_zigzag_stripe_jumps_every_row():
    f = _stripe(noise=1.0, rows=np.arange(0, H, 2))
    x = np.arange(W, dtype=float)
    f[1::2] += 100.0 * np.exp(-0.5 * ((x - 40.0) / 2.0) ** 2)
    assert cond.measure(f).jumps == pytest.approx(1.0)


def test_saturation_of_a_clipped_stripe():
    f = np.clip(_stripe(amp=400.0, sigma=3.0, noise=2.0), 0, 255).round().astype(np.uint8)
    c = cond.measure(f)
    assert c.saturated == 1.0
    f2 = np.clip(_stripe(amp=100.0, noise=2.0), 0, 255).round().astype(np.uint8)
    assert cond.measure(f2).saturated == 0.0


def test_laser_off_frame_removes_a_static_ridge():
    x = np.arange(W, dtype=float)
    ridge = 150.0 * np.exp(-0.5 * ((x - 30.0) / 2.0) ** 2)
    rng = np.random.default_rng(3)
    off = 20.0 + ridge + rng.normal(0, 1.0, (H, W))
    on = off + _stripe(amp=100.0, base=0.0, noise=1.0)
    with_off = cond.measure(on, off)
    assert with_off.rival < 0.2
    # without it the brighter static ridge wins the argmax and the stripe is its rival (100 / 150)
    assert cond.measure(on).rival == pytest.approx(100.0 / 150.0, abs=0.08)


def test_colour_laser_share():
    f = _stripe(amp=100.0, noise=1.0, base=30.0)
    red = np.stack([f, np.full_like(f, 30.0), np.full_like(f, 30.0)], axis=2)
    white = np.stack([f, f, f], axis=2)
    assert cond.measure(f, rgb=red, laser="red").laser_share == pytest.approx(1.0, abs=0.02)
    assert math.isnan(cond.measure(f, rgb=white, laser="red").laser_share)  # a grey picture stored as RGB
    pink = np.stack([f, 0.5 * f + 15.0, 0.5 * f + 15.0], axis=2)
    assert cond.measure(f, rgb=pink, laser="red").laser_share == pytest.approx(0.5, abs=0.03)
    green = np.stack([np.full_like(f, 30.0), f, np.full_like(f, 30.0)], axis=2)
    assert cond.measure(f, rgb=green, laser="green").laser_share == pytest.approx(1.0, abs=0.02)


def test_no_stripe():
    rng = np.random.default_rng(4)
    c = cond.measure(20.0 + rng.normal(0, 2.0, (H, W)))
    assert c.visible < 0.05 and c.contrast < DEFAULT.visible_k


def test_distance_is_small_between_like_frames_and_large_between_unlike_ones():
    a = cond.measure(_stripe(amp=100.0))
    b = cond.measure(_stripe(amp=100.0, seed=5))
    far = cond.measure(_stripe(amp=10.0))
    assert cond.distance(a, b) < 0.5 < cond.distance(a, far)
    # a coarser unit of contrast brings the faint stripe nearer
    coarse = PredictSettings(condition_scales=tuple((k, 10 * v) for k, v in DEFAULT.condition_scales))
    assert cond.distance(a, far, settings=coarse) < cond.distance(a, far) / 5


def test_bad_shapes_are_refused():
    with pytest.raises(ValueError):
        cond.measure(np.zeros((4, 4, 3)))
    with pytest.raises(ValueError):
        cond.measure(np.zeros((8, 8)), np.zeros((8, 9)))


def test_a_stripe_along_the_rows_is_said_to_run_across_and_one_down_them_is_not():
    rng = np.random.default_rng(2)
    rows, cols = np.mgrid[0:80, 0:100]
    down = 20.0 + rng.normal(0, 2.0, (80, 100)) + 150.0 * np.exp(-0.5 * ((cols - 40.0 - 0.1 * rows) / 1.2) ** 2)
    assert not cond.runs_across(down)
    assert cond.runs_across(np.rot90(down)) and cond.runs_across(np.rot90(down, 3))
    bg = np.full((80, 100), 20.0)
    assert not cond.runs_across(down, bg) and cond.runs_across(np.rot90(down), np.rot90(bg))


def test_the_likelier_laser_is_the_colour_whose_excess_shows_the_stripe_far_more_clearly():
    rng = np.random.default_rng(3)
    img = rng.normal(60.0, 2.0, (60, 80, 3))
    img[:, 30, 2] += 100.0  # a blue line
    assert [cond.likelier_laser(img, c) for c in ("red", "green", "blue")] == ["blue", "blue", None]
    grey = np.repeat(rng.normal(60.0, 2.0, (60, 80, 1)), 3, axis=2)
    assert cond.likelier_laser(grey, "red") is None  # no colour anywhere
    with pytest.raises(ValueError, match=r"`rgb` must be a colour image \(H, W, 3\), got shape \(60, 80\)"):
        cond.likelier_laser(img[..., 0])
    with pytest.raises(ValueError, match="`laser` must be one of red, green, blue, got 'violet'"):
        cond.likelier_laser(img, "violet")
