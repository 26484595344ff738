import math

import numpy as np
import pytest

from scenes.sensor import SensorModel


def test_electrons_per_radiance_follows_the_camera_equation():
    s = SensorModel(f_number=2.0, lens_transmission=0.5, exposure_ms=20.0, quantum_efficiency=0.5,
                    pixel_pitch_um=5.0, wavelength_nm=600.0)
    irradiance = 1.0 * 0.5 * math.pi / (4 * 2.0 ** 2)  # W/m² for L = 1
    photons = irradiance * (5e-6) ** 2 * 20e-3 / (6.62607015e-34 * 299792458.0 / 600e-9)
    assert s.electrons_per_radiance == pytest.approx(0.5 * photons, rel=1e-12)


def test_mean_and_variance_of_captured_dn():
    s = SensorModel(gain_e_per_dn=10.0, full_well_e=100000.0)
    target_e = 1500.0
    radiance = np.full((200, 200), target_e / s.electrons_per_radiance)
    dn = s.capture(radiance, np.random.default_rng(1)).astype(float)
    assert dn.mean() == pytest.approx(target_e / s.gain_e_per_dn, abs=0.05)
    var_expected = (target_e + s.read_noise_e ** 2) / s.gain_e_per_dn ** 2 + 1 / 12  # + quantisation
    assert dn.var() == pytest.approx(var_expected, rel=0.08)


def test_clipping_at_full_well_and_8_bits():
    s = SensorModel(full_well_e=10000.0, gain_e_per_dn=20.0)
    img = s.capture(np.full((50, 50), 1e6 / s.electrons_per_radiance), np.random.default_rng(0))
    assert img.dtype == np.uint8
    assert abs(img.astype(float).mean() - 10000 / 20) > 100  # not 500: clipped ...
    assert img.max() == 255  # ... by the ADC
    s2 = SensorModel(full_well_e=10000.0, gain_e_per_dn=100.0, read_noise_e=0.0)
    img2 = s2.capture(np.full((50, 50), 1e6 / s2.electrons_per_radiance), np.random.default_rng(0))
    assert np.all(img2 == 100)  # full well / gain
    assert np.all(s.capture(np.zeros((4, 4)), np.random.default_rng(0)) <= 1)


def test_capture_is_reproducible_for_a_seed():
    s = SensorModel()
    rad = np.random.default_rng(5).uniform(0, 1, (30, 40))
    a = s.capture(rad, np.random.default_rng(7))
    b = s.capture(rad, np.random.default_rng(7))
    c = s.capture(rad, np.random.default_rng(8))
    assert np.array_equal(a, b) and not np.array_equal(a, c)


def test_default_levels_of_a_stripe_and_the_ambient():
    """Defaults: ~0.6 W/m²/sr (3 mW stripe on white at ~35 cm) near 100 DN; 400 lux D65 on white ~2 DN."""
    from scenes import radiometry

    s = SensorModel()
    ambient = 0.85 * radiometry.inband_sky_radiance(400.0, "D65")
    assert 1.0 < s.expected_dn(ambient) < 4.0
    assert 80 < s.expected_dn(0.6) < 120


@pytest.mark.parametrize("name,value,pattern", [
    ("f_number", 0.0, "`f_number` must be > 0, got 0.0"),
    ("exposure_ms", -1.0, "`exposure_ms` must be > 0, got -1.0"),
    ("quantum_efficiency", 1.5, r"`quantum_efficiency` must be in \(0.0, 1.0\], got 1.5"),
    ("read_noise_e", -3.0, "`read_noise_e` must be >= 0, got -3.0"),
    ("gain_e_per_dn", float("nan"), "`gain_e_per_dn` must be a finite number"),
])
def test_invalid_parameters_are_named(name, value, pattern):
    with pytest.raises(ValueError, match=pattern):
        SensorModel(**{name: value})


def test_sensor_noise_grows_with_the_level():
    sensor = SensorModel()
    n = sensor.noise_dn(np.array([0.0, 10.0, 100.0]))
    assert np.all(np.diff(n) > 0)
    assert math.isclose(n[2], math.sqrt(100 * sensor.gain_e_per_dn + sensor.read_noise_e ** 2)
                        / sensor.gain_e_per_dn + 12 ** -0.5)
