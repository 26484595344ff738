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
    ("spp", 0, r"`spp` must be an integer >= 1 or 'auto' \(scenes.sampling\), got 0"),
    ("ambient_spp", 2.5, r"`ambient_spp` must be an integer >= 1 or 'auto' \(scenes.sampling\), got 2.5"),
    ("spp", "Auto", r"`spp` must be an integer >= 1 or 'auto' \(scenes.sampling\), got 'Auto'"),
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


@pytest.mark.parametrize("change,pattern", [
    ({"support_texture": "marble"}, r"`support_texture` must be one of 'none', 'wood'"),
    ({"object_texture": "wood", "material": "specular"}, r"`object_texture` needs one of the materials"),
    ({"texture_scale_cm": 0}, r"`texture_scale_cm` must be in \(0.0, 100.0\], got 0"),
    ({"texture_seed": -2}, r"`texture_seed` must be an integer >= 0, got -2"),
    ({"support_finish": "glossy"}, r"`support_finish` must be one of 'matte', 'polished', got 'glossy'"),
    ({"camera": "bw"}, r"`camera` must be one of 'mono', 'rgb', got 'bw'"),
    ({"filter": "none"}, r"`filter` \"none\" needs `camera` \"rgb\""),
    ({"jpeg_quality": 0}, r"`jpeg_quality` must be None \(lossless\) or an integer in \[1, 95\], got 0"),
    ({"jpeg_quality": 90.0}, r"`jpeg_quality` must be None"),
    ({"defocus_px": 25}, r"`defocus_px` must be in \[0.0, 20.0\], got 25"),
])
def test_texture_and_camera_parameters_are_checked(change, pattern):
    with pytest.raises(ValueError, match=pattern):
        P.validate(change)


def test_texture_and_camera_defaults():
    d = P.validate({})
    assert {k: d[k] for k in P.TEXTURE_KEYS + P.CAMERA_KEYS} == {
        "support_texture": "none", "background_texture": "none", "object_texture": "none", "texture_scale_cm": 2.0,
        "texture_seed": 0, "support_finish": "matte", "camera": "mono", "filter": "bandpass", "jpeg_quality": None,
        "defocus_px": 0.0}
    assert not P.textured(d) and P.textured(P.validate({"background_texture": "paper"}))
    ok = P.validate({"camera": "rgb", "filter": "none", "jpeg_quality": 80, "ambient_illuminant": "daylight"})
    assert ok["jpeg_quality"] == 80 and ok["ambient_illuminant"] == "daylight"
    assert not set(P.TEXTURE_KEYS + P.CAMERA_KEYS) & set(P.RENDER_KEYS + P.SCALE_KEYS + P.SENSOR_KEYS)


def test_translucency_defaults_to_the_reference_and_is_checked():
    assert P.validate({})["translucency"] == "volpath"
    assert P.validate({"translucency": "profile", "material": "skin"})["translucency"] == "profile"
    assert P.validate({"translucency": "profile"})["translucency"] == "profile"  # opaque materials ignore it
    assert "translucency" not in P.RENDER_KEYS  # in the cache key only as "profile" (scenes.render_key.optics_fields)
    for bad in ("mc", None, True):
        with pytest.raises(ValueError, match=rf"`translucency` must be one of 'volpath', 'profile', got {bad!r}"):
            P.validate({"translucency": bad})
