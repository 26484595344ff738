"""Synthetic photographs of the failure classes (bench.studies.hard_frames)."""

import numpy as np
import pytest

from bench.studies.hard_frames import DISTRACTORS, KINDS, argmax_right, hard_frame, hard_frames, plateau_middles


@pytest.mark.parametrize("kind", KINDS)
def test_frames_are_seeded_and_have_stripe_and_stripeless_rows(kind):
    a, b = hard_frame(kind, 7), hard_frame(kind, 7)
    np.testing.assert_array_equal(a.rgb, b.rgb)
    np.testing.assert_array_equal(a.rgb_off, b.rgb_off)
    assert not np.array_equal(a.rgb, hard_frame(kind, 8).rgb)
    assert a.rgb.dtype == np.uint8 and a.rgb.shape[2] == 3 and a.truth.shape == (a.rgb.shape[0],)
    # stripe rows and stripe-less ones; the distractor kinds' stripe starts or ends mid-frame
    assert (0.2 if kind in DISTRACTORS else 0.5) < np.isfinite(a.truth).mean() < (0.85 if kind in DISTRACTORS else 1.0)
    assert a.laser_channel.shape == a.rgb.shape[:2] and a.laser in ("red", "green")
    # the laser-off frame has no stripe: the laser channel is darker on the stripe rows' centres
    rows = np.nonzero(np.isfinite(a.truth))[0]
    c = np.rint(a.truth[rows]).astype(int)
    assert a.laser_channel[rows, c].mean() > a.laser_channel_off[rows, c].mean()


def test_saturated_wide_frames_clip_and_plain_frames_are_easy():
    f = hard_frame("saturated_wide", 0)
    assert f.saturated and argmax_right(f.laser_channel, f.truth) > 0.9
    assert argmax_right(hard_frame("plain", 0).laser_channel, hard_frame("plain", 0).truth) == 1.0
    assert len(hard_frames(["plain", "printed"], [0, 1])) == 4


def test_plateau_middles_and_bad_arguments():
    assert plateau_middles(np.array([[1, 5, 5, 5, 5, 0], [3, 0, 0, 0, 0, 0]])).tolist() == [2, 0]
    with pytest.raises(ValueError, match="`kind` must be one of"):
        hard_frame("snow", 0)
    with pytest.raises(ValueError, match="`seed` must be an integer >= 0, got -1"):
        hard_frame("plain", -1)


def test_every_kind_has_its_look_and_no_other():
    from bench.studies import hard_frames as hf

    assert tuple(hf._LOOKS) == hf.KINDS


@pytest.mark.parametrize("kind", DISTRACTORS)
def test_distractor_kinds_hold_their_distractor_in_stripeless_rows(kind):
    # every seed: a stretch of at least a fifth of the rows without the stripe at the top or the bottom
    # (the object covers part of the height), and something there that is not dark: the distractor
    for seed in range(4):
        f = hard_frame(kind, seed)
        H = f.truth.size
        none = ~np.isfinite(f.truth)
        end = none[: H // 5].all() or none[H - H // 5:].all()
        assert end, f"{kind} seed {seed}: no stripe-less end"
        img = f.laser_channel.astype(float)
        level = np.median(img)
        assert (img[none].max(axis=1) - level).max() > 25, f"{kind} seed {seed}: nothing in the stripe-less rows"


def test_new_kinds_leave_the_old_kinds_frames_as_they_were():
    # the distractor kinds come after the failure classes in KINDS, so those keep their seeds' frames
    assert KINDS[:9] == ("printed", "noisy_floor", "polished", "daylight", "noisy_sensor", "saturated_wide",
                         "thin_faint", "plain", "dim")
    assert KINDS[9:] == DISTRACTORS
