import math

import numpy as np
import pytest
from scipy import integrate

from scenes import radiometry as rad


def _gauss_filter(lam, c=650.0, fwhm=10.0, peak=0.9):
    sigma = fwhm / (2 * math.sqrt(2 * math.log(2)))
    return peak * math.exp(-0.5 * ((lam - c) / sigma) ** 2)


def test_equal_energy_illuminant_has_a_closed_form():
    """Illuminant E: L(λ) is flat, so the in-band radiance is L · peak · FWHM · sqrt(π / 4 ln 2)."""
    import colour

    v = colour.colorimetry.SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    v_integral = integrate.trapezoid(v.values, v.wavelengths)  # ∫V dλ ≈ 106.86 nm
    assert v_integral == pytest.approx(106.86, rel=1e-3)
    lux = 400.0
    flat = lux / (math.pi * 683.0 * v_integral)
    expected = flat * 0.9 * 10.0 * math.sqrt(math.pi / (4 * math.log(2)))
    assert rad.inband_sky_radiance(lux, "E") == pytest.approx(expected, rel=2e-3)


def test_d65_inband_radiance_matches_an_independent_quadrature():
    """scipy quad over a linear interpolant of colour's D65 table, normalised by colour's luminous flux."""
    import colour

    sd = colour.SDS_ILLUMINANTS["D65"]
    wl, val = np.asarray(sd.wavelengths, float), np.asarray(sd.values, float)
    flux = colour.luminous_flux(sd)  # 683 ∫ S V dλ, colour's own integration
    lux = 400.0
    scale = lux / (math.pi * flux)
    inband, _ = integrate.quad(lambda lam: scale * np.interp(lam, wl, val) * _gauss_filter(lam), 560, 740,
                               points=[650.0], limit=200)
    assert rad.inband_sky_radiance(lux, "D65") == pytest.approx(inband, rel=5e-3)
    # the field notes' reference: 400 lux of D65 is about 1.41e-3 W/m²/sr/nm at 650 nm
    assert rad.sky_spectral_radiance(lux, "D65")[650 - 360] == pytest.approx(1.41e-3, rel=0.02)


def test_sky_radiance_is_linear_in_lux_and_depends_on_illuminant():
    a = rad.inband_sky_radiance(100.0, "D65")
    assert rad.inband_sky_radiance(400.0, "D65") == pytest.approx(4 * a)
    assert rad.inband_sky_radiance(0.0, "D65") == 0.0
    # illuminant A (tungsten) is much redder than D65: more in-band power per lux
    assert rad.inband_sky_radiance(100.0, "A") > 1.5 * a


def test_illuminance_of_the_sky_spectrum_is_the_requested_lux():
    lam = rad.WAVELENGTHS_NM
    spec = rad.sky_spectral_radiance(250.0, "FL2")
    lux = 683.0 * math.pi * np.trapezoid(spec * rad.photopic_efficiency(), lam)
    assert lux == pytest.approx(250.0, rel=1e-9)


def test_laser_power_through_the_filter():
    assert rad.inband_laser_power_w(3.0, 650.0) == pytest.approx(0.9 * 3e-3)
    assert rad.inband_laser_power_w(3.0, 655.0) == pytest.approx(0.45 * 3e-3)  # half maximum
    assert rad.inband_laser_power_w(3.0, 700.0) < 1e-12


def test_filter_shape():
    t = rad.filter_transmission(np.array([645.0, 650.0, 655.0]), 650.0, 10.0, 0.9)
    assert np.allclose(t, [0.45, 0.9, 0.45])


def test_projector_scale_inverts_the_power_formula():
    s = rad.projector_scale(2e-3, 0.25, 0.01, 1.0)
    assert math.pi * s * 0.25 * (2 * 0.01) * (2 * 1.0) == pytest.approx(2e-3)
    with pytest.raises(ValueError, match="texture_mean"):
        rad.projector_scale(1.0, 0.0, 0.1, 0.1)


def test_unknown_illuminant_lists_valid_names():
    with pytest.raises(KeyError, match="D65"):
        rad.inband_sky_radiance(400.0, "D66")


def test_importing_colour_science_leaves_numpy_print_options_alone():
    import subprocess
    import sys

    code = ("import numpy as np; before = np.get_printoptions(); from scenes import radiometry; "
            "radiometry.illuminant_names(); print(np.get_printoptions() == before)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"


def test_daylight_is_the_cie_d75_alias():
    assert "daylight" in rad.illuminant_names() and rad.ALIASES["daylight"] == "D75"
    assert np.array_equal(rad.illuminant_spd("daylight"), rad.illuminant_spd("D75"))
    # bluer than D65 at the same illuminance
    d65, day = rad.sky_spectral_radiance(400.0, "D65"), rad.sky_spectral_radiance(400.0, "daylight")
    i450, i650 = 450 - 360, 650 - 360
    assert day[i450] / day[i650] > d65[i450] / d65[i650]
