import numpy as np
import pytest

from scenes import colour_camera as C
from scenes.sensor import SensorModel


def test_sensitivities_and_channel_radiometry():
    s = C.sensitivities()
    assert s.shape == (421, 3) and np.allclose(s.max(axis=0), 1.0)
    assert list(np.argsort(C.peak_wavelengths_nm())) == [2, 1, 0]  # blue < green < red
    none = C.channel_sky_radiance(400.0, "D65", "none")
    band = C.channel_sky_radiance(400.0, "D65", "bandpass")
    assert np.all(none > 0) and np.all(band < none) and band[0] > 10 * band[2]
    assert np.allclose(C.channel_sky_radiance(800.0, "D65", "none"), 2 * none)
    p = C.channel_laser_power_w(3.0, 650.0, "none")
    assert p[0] > 10 * p[1] > 0 and np.isclose(C.channel_laser_power_w(3.0, 650.0, "bandpass")[0], 0.9 * p[0])
    # incandescent light is redder than daylight: the red gain is lower under A
    assert C.white_balance_gains("A")[0] < C.white_balance_gains("daylight")[0]
    with pytest.raises(ValueError, match="`filter` must be one of 'bandpass', 'none', got 'red'"):
        C.channel_sky_radiance(400.0, "D65", "red")


def test_bayer_round_trip_of_a_flat_field_is_flat():
    flat = np.broadcast_to(np.array([30.0, 80.0, 55.0]), (10, 12, 3))
    assert np.allclose(C.demosaic(C.mosaic(flat)), flat, atol=1e-12)
    # Malvar-He-Cutler reproduces a linear ramp exactly away from the edges
    y, x = np.mgrid[0:16, 0:20].astype(float)
    ramp = np.stack([x + 2 * y, 3 * x - y + 40, 0.5 * x + y], axis=-1)
    out = C.demosaic(C.mosaic(ramp))
    assert np.allclose(out[2:-2, 2:-2], ramp[2:-2, 2:-2], atol=1e-9)
    assert C.cfa_channels(4, 4)[::2, ::2].max() == 0 and C.cfa_channels(4, 4)[1::2, 1::2].min() == 2
    with pytest.raises(ValueError, match="even H and W"):
        C.demosaic(np.zeros((5, 6)))


def test_blooming_spills_along_the_column_and_keeps_the_charge():
    e = np.zeros((9, 3))
    e[4, 1] = 50.0
    out = C.bloom(e, 10.0)
    assert out.max() <= 10.0 and np.isclose(out.sum(), 50.0)
    assert np.all(out[:, [0, 2]] == 0)  # only the column
    assert np.array_equal(out[:, 1], [0, 0, 10, 10, 10, 10, 10, 0, 0])
    edge = np.zeros((3, 1))
    edge[0, 0] = 40.0
    assert np.array_equal(C.bloom(edge, 10.0)[:, 0], [10, 10, 5])  # the half that goes up is lost
    assert np.array_equal(C.bloom(np.full((3, 2), 5.0), 10.0), np.full((3, 2), 5.0))


def _white_radiance(illuminant, lux, albedo=0.85, shape=(40, 48)):
    return np.broadcast_to(albedo * C.channel_sky_radiance(lux, illuminant, "none"), shape + (3,))


@pytest.mark.parametrize("illuminant,lux", [("D65", 400.0), ("A", 300.0), ("daylight", 2000.0)])
def test_a_white_patch_white_balances_to_grey(illuminant, lux):
    exposure = 5.0 * 400.0 / lux
    cam = C.ColourCamera(SensorModel(exposure_ms=exposure), illuminant)
    rgb = cam.capture(_white_radiance(illuminant, lux), np.random.default_rng(0))
    assert rgb.shape == (40, 48, 3) and rgb.dtype == np.uint8
    m = rgb.reshape(-1, 3).mean(axis=0)
    assert m.max() - m.min() < 3.0, m
    assert 60 < m.mean() < 200
    # the same patch through the wrong preset is visibly tinted
    wrong = C.ColourCamera(SensorModel(exposure_ms=exposure), "A" if illuminant != "A" else "D65")
    w = wrong.capture(_white_radiance(illuminant, lux), np.random.default_rng(0)).reshape(-1, 3).mean(axis=0)
    assert w.max() - w.min() > 10.0


def test_saturated_stripe_blooms_into_its_column():
    rad = _white_radiance("D65", 400.0, shape=(60, 64)).copy()
    rad[30, 30:34, 0] *= 200.0  # a very bright red spot
    cam = C.ColourCamera(SensorModel(read_noise_e=0.0))
    raw = cam.raw(rad, np.random.default_rng(1))
    col = raw[:, 30].astype(float)  # a red column of the mosaic (even row, even column)
    full = 2 ** C.RAW_BITS - 1
    assert (col[::2] >= 0.99 * full).sum() >= 4  # several red pixels of the column are full
    assert raw[10, 30] < 0.5 * full and raw[30, 40] < 0.5 * full


def test_jpeg_round_trip_and_defocus():
    y, x = np.mgrid[0:48, 0:64]
    img = np.stack([(2 * x) % 256, (3 * y) % 256, np.full_like(x, 128)], axis=-1).astype(np.uint8)
    out = C.jpeg_round_trip(img, 90)
    assert out.shape == img.shape and out.dtype == np.uint8
    assert 0 < np.abs(out.astype(int) - img).mean() < 4.0
    g = C.jpeg_round_trip(img[..., 0], 50)
    assert g.shape == img.shape[:2]
    spot = np.zeros((21, 21))
    spot[10, 10] = 1.0
    blur = C.defocus(spot, 3.0)
    assert np.isclose(blur.sum(), 1.0) and blur[10, 13] > 0 and blur[10, 15] == 0
    assert np.array_equal(C.defocus(spot, 0.0), spot)
    with pytest.raises(ValueError, match="`defocus_px` must be >= 0"):
        C.defocus(spot, -1.0)


def test_colour_matrix_keeps_white_and_saturates():
    M = C.colour_matrix("D65")
    assert np.allclose(M.sum(axis=1), 1.0) and np.all(np.diag(M) > 1.0)
    assert np.allclose(C.srgb_encode([0.0, 1.0, 2.0]), [0.0, 1.0, 1.0])
    assert C.luma(np.full((1, 1, 3), 200, np.uint8))[0, 0] == 200
