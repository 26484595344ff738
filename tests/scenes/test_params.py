import pytest

from scenes import params as P


def test_defaults_cover_the_documented_names():
    d = P.validate({})
    for k in ("material", "ambient_lux", "laser_power_mw", "width", "height", "spp", "seed", "ambient_illuminant",
              "laser_wavelength_nm", "line_fwhm_mrad", "laser_fan_deg", "n_angles"):
        assert k in d
    assert (d["width"], d["height"], d["ambient_lux"], d["laser_power_mw"]) == (512, 480, 400.0, 3.0)
    assert set(P.RENDER_KEYS) | set(P.SCALE_KEYS) | set(P.SENSOR_KEYS) <= set(P.DEFAULTS)


def test_unknown_parameter_is_a_type_error_listing_valid_names():
    with pytest.raises(TypeError, match="'laser_power'.*valid: .*laser_power_mw"):
        P.validate({"laser_power": 3})


@pytest.mark.parametrize("name,value,pattern", [
    ("laser_power_mw", -3.0, r"`laser_power_mw` must be >= 0, got -3.0"),
    ("ambient_lux", -1, r"`ambient_lux` must be >= 0, got -1"),
    ("spp", 0, r"`spp` must be an integer >= 1, got 0"),
    ("ambient_spp", 2.5, r"`ambient_spp` must be an integer >= 1, got 2.5"),
    ("width", 0, r"`width` must be an integer >= 1, got 0"),
    ("height", -60, r"`height` must be an integer >= 1, got -60"),
    ("seed", -1, r"`seed` must be an integer >= 0, got -1"),
    ("line_fwhm_mrad", 0.0, r"`line_fwhm_mrad` must be in \(0.0, 100.0\], got 0.0"),
    ("filter_peak", 1.2, r"`filter_peak` must be in \(0.0, 1.0\], got 1.2"),
    ("f_number", -2.0, r"`f_number` must be > 0, got -2.0"),
    ("ambient_lux", float("inf"), r"`ambient_lux` must be a finite number, got inf"),
    ("background", "sky", r"`background` must be one of 'wall', 'none', got 'sky'"),
    ("background", None, r"`background` must be one of 'wall', 'none', got None"),
    ("background_distance_cm", 0.0, r"`background_distance_cm` must be in \(0.0, 1000.0\], got 0.0"),
    ("background_distance_cm", 2000, r"`background_distance_cm` must be in \(0.0, 1000.0\], got 2000"),
    ("background_distance_cm", "far", r"`background_distance_cm` must be a finite number, got 'far'"),
    ("background_albedo", 1.5, r"`background_albedo` must be in \[0.0, 1.0\], got 1.5"),
    ("background_albedo", float("nan"), r"`background_albedo` must be a finite number, got nan"),
    ("support", "shelf", r"`support` must be one of 'none', 'table', got 'shelf'"),
    ("support", True, r"`support` must be one of 'none', 'table', got True"),
    ("support_albedo", -0.1, r"`support_albedo` must be in \[0.0, 1.0\], got -0.1"),
])
def test_invalid_values_name_the_parameter(name, value, pattern):
    with pytest.raises(ValueError, match=pattern):
        P.validate({name: value})


def test_pixels_must_stay_square():
    assert P.validate({"width": 64, "height": 60})["width"] == 64
    with pytest.raises(ValueError, match="square pixels.*got 100x100"):
        P.validate({"width": 100, "height": 100})


def test_unknown_material_and_illuminant_are_key_errors():
    with pytest.raises(KeyError, match="matte, absorbing, glossy, specular, patchy"):
        P.validate({"material": "chrome"})
    with pytest.raises(KeyError, match="ambient_illuminant.*D65"):
        P.validate({"ambient_illuminant": "sunset"})


def test_background_and_support_defaults_keep_todays_scene():
    d = P.validate({})
    assert (d["background"], d["background_distance_cm"], d["background_albedo"]) == ("wall", 55.0, 0.5)
    assert (d["support"], d["support_albedo"]) == ("none", 0.5)
    for k in ("background", "background_distance_cm", "background_albedo", "support", "support_albedo"):
        assert k in P.RENDER_KEYS and k not in P.SCALE_KEYS
    ok = P.validate({"background": "none", "background_distance_cm": 80, "background_albedo": 0,
                     "support": "table", "support_albedo": 1})
    assert ok["background_distance_cm"] == 80.0 and isinstance(ok["background_distance_cm"], float)
