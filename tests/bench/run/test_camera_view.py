import types

import numpy as np
import pytest

from bench.run.camera_view import laser_colour, tracker_images
from bench.store.realset import select_channel


def test_laser_colours():
    assert [laser_colour(w) for w in (405, 489.9, 490, 532, 579.9, 580, 650, 780)] == [
        "blue", "blue", "green", "green", "green", "red", "red", "red"]


def test_mono_frames_pass_through_and_colour_frames_use_the_channel_rule():
    rng = np.random.default_rng(0)
    img, bg = rng.integers(0, 255, (6, 8), dtype=np.uint8), rng.integers(0, 255, (6, 8), dtype=np.uint8)
    mono = types.SimpleNamespace(image=img, background=bg, rgb=None, rgb_background=None)
    a, b = tracker_images(mono)
    assert a is img and b is bg
    rgb, rgb_bg = (rng.integers(0, 255, (6, 8, 3), dtype=np.uint8) for _ in range(2))
    colour = types.SimpleNamespace(image=img, background=bg, rgb=rgb, rgb_background=rgb_bg)
    a, b = tracker_images(colour, {"laser_wavelength_nm": 650.0})
    assert np.array_equal(a, select_channel(rgb, "auto", "red"))
    assert np.array_equal(b, select_channel(rgb_bg, "auto", "red"))
    g, _ = tracker_images(colour, {"laser_wavelength_nm": 532.0}, "excess")
    assert np.array_equal(g, select_channel(rgb, "excess", "green"))
    with pytest.raises(ValueError, match="`channel` must be one of"):
        tracker_images(colour, {"laser_wavelength_nm": 650.0}, "infrared")
    with pytest.raises(ValueError, match="a colour frame needs the scene's `params`"):
        tracker_images(colour)


@pytest.mark.slow
def test_a_rendered_colour_scan_is_tracked_on_the_excess_channel(tmp_path):
    import scenes
    import trackers
    from bench.run.scan import run_scan

    s = scenes.make("plane", camera="rgb", filter="none", object_texture="checker", laser_power_mw=5.0,
                    width=64, height=60, spp=4, ambient_spp=2, cache_dir=str(tmp_path))
    angles = s.default_angles()[[2, 5]]
    seen = []
    dp4 = trackers.make("dp4")

    class Recording(type(dp4)):  # records the frames the scan hands to the tracker
        def find_stripe(self, image, background):
            seen.append(np.array(image))
            return super().find_stripe(image, background)

    res = run_scan("k", s, angles, {"dp4": Recording(**dp4.get_params())}, spp=4, seed=0,
                   checkpoint=tmp_path / "k.npz", progress=False)
    f = s.render(float(angles[0]))
    assert len(seen) == 3 and not seen[0].any()  # a warm-up call on a blank frame, then the two frames
    assert np.array_equal(seen[1], select_channel(f.rgb, "auto", "red"))
    assert res.done.all() and res.status["dp4"].max() == 0
