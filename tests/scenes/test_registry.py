import pytest

import scenes


def test_available_and_materials():
    assert scenes.available() == ["cone", "hand", "plane", "sphere"]
    assert scenes.MATERIALS == ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed",
                                "skin", "marble", "wax")


def test_make_fills_defaults_and_keeps_overrides():
    s = scenes.make("cone", material="glossy", ambient_lux=100, width=64, height=60)
    assert s.name == "cone" and s.params["material"] == "glossy" and s.params["ambient_lux"] == 100.0
    assert s.params["laser_power_mw"] == 3.0 and s.rig.width == 64 and s.rig.height == 60
    assert s.rig.pitch_x_mm == pytest.approx(scenes.Rig().pitch_x_mm * 8)


def test_unknown_names_list_valid_ones():
    with pytest.raises(KeyError, match="cone, hand, plane, sphere"):
        scenes.make("teapot")
    with pytest.raises(TypeError, match="valid: .*ambient_lux"):
        scenes.make("cone", ambient=3)
    with pytest.raises(ValueError, match="`laser_power_mw` must be >= 0, got -3.0"):
        scenes.make("cone", laser_power_mw=-3.0)
