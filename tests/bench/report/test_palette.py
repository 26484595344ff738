"""bench.report.palette: one colour per tracker label."""

from bench.report.palette import REFERENCE_COLOUR, TRACKER_COLOURS, tracker_colour, tracker_rgb


def test_every_colour_is_a_colour_and_never_black_or_white():
    import trackers

    labels = list(TRACKER_COLOURS) + trackers.available() + [f"plugin-{i}" for i in range(50)]
    for lab in labels:
        c = tracker_colour(lab)
        assert len(c) == 7 and c.startswith("#")
        assert tracker_rgb(lab) not in ((0, 0, 0), (255, 255, 255))
    assert set(trackers.available()) <= set(TRACKER_COLOURS)  # every built-in has its fixed colour
    assert REFERENCE_COLOUR not in TRACKER_COLOURS.values()


def test_a_label_keeps_its_colour_whatever_runs_beside_it():
    assert tracker_colour("someone-else") == tracker_colour("someone-else")
    assert tracker_rgb("dp4") == (0x2C, 0xA0, 0x2C)
