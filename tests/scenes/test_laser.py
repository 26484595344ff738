import math

import numpy as np
import pytest

from scenes import laser as L


def test_fan_angle_is_exact_and_profile_is_a_centred_gaussian():
    p = L.profile(3.0, 90.0)
    assert math.degrees(2 * math.atan(p.tan_half_y)) == pytest.approx(90.0, abs=1e-9)
    ny, nx, _ = p.texture.shape
    # Mitsuba: tan(fov_y/2) = tan(fov_x/2) * ny / nx
    assert p.tan_half_x * ny / nx == pytest.approx(p.tan_half_y, rel=1e-12)
    row = p.texture[0, :, 0].astype(float)
    assert np.all(p.texture == p.texture[:1])  # uniform fan
    x = np.arctan(((np.arange(nx) + 0.5) / nx * 2 - 1) * p.tan_half_x)
    assert np.allclose(row, p.relative_irradiance(x), atol=1e-6)
    assert np.allclose(row, row[::-1])  # symmetric: the sheet's centre is the plane
    # FWHM from the samples (linear interpolation at half maximum)
    right = x[nx // 2:]
    half = np.interp(0.5, row[nx // 2:][::-1], right[::-1])
    assert 2 * half * 1e3 == pytest.approx(3.0, rel=0.02)
    assert row[0] < 1e-3  # window covers the tails


def test_scale_for_power_is_linear():
    p = L.profile(2.0, 60.0)
    assert p.scale_for_power(2.0) == pytest.approx(2 * p.scale_for_power(1.0))
    mean = float(p.texture.mean(dtype=np.float64))
    assert math.pi * p.scale_for_power(1e-3) * mean * 4 * p.tan_half_x * p.tan_half_y == pytest.approx(1e-3)
