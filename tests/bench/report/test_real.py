"""The real-run pictures and page (bench.report.real): one palette, escaped names."""

import numpy as np

from bench.report.palette import TRACKER_COLOURS, tracker_colour, tracker_rgb
from bench.report.real import _img_tag, legend, overlay


def test_overlays_and_figures_share_one_palette():
    from bench.report import figures

    assert figures.tracker_colour is tracker_colour
    ov = overlay(np.zeros((4, 5), np.uint8), {"dp4": [1.0] * 4, "mine": [3.0] * 4}, radius=0)
    assert tuple(ov[0, 1]) == tracker_rgb("dp4") and tuple(ov[0, 3]) == tracker_rgb("mine")
    assert legend(["dp4"]) == f"dp4={TRACKER_COLOURS['dp4']}"
    assert all(c.lower() not in ("#000000", "#ffffff") for c in TRACKER_COLOURS.values())  # visible on photographs


def test_a_hostile_image_name_is_escaped_in_the_alt_attribute(tmp_path):
    import imageio.v3 as iio

    p = tmp_path / "x' onload='alert(3).png"
    iio.imwrite(p, np.zeros((4, 4, 3), np.uint8))
    tag = _img_tag(p)
    assert "onload='alert" not in tag and "x&#x27; onload=&#x27;alert(3).png" in tag
