"""The stripe question (trackers._stripe): each test on synthetic rows, and how every tracker reads it."""

import numpy as np
import pytest

import trackers
from trackers import StripeTest, ask, colour_evidence
from trackers._stripe import REASONS, as_test
from trackers.testing import stripe_profile

H, W = 80, 160
STRIPE_COL = 60.0


def _scene(seed=0):
    """A dark frame (10 DN, noise 1.5 DN) with a laser stripe (sigma 1.2 px, 150 DN) at column 60 in
    every row, as float64, and its laser-off frame (the same without the stripe)."""
    rng = np.random.default_rng(seed)
    off = 10.0 + rng.normal(0.0, 1.5, (H, W))
    on = off + stripe_profile(np.full(H, STRIPE_COL), W, 1.2, 150.0)
    return on, off


def _rgb(on, off, laser_rows=slice(None), other=(1.0, 1.0, 1.0)):
    """A colour photograph of the pair: the laser's light (on - off) red with 8 % crosstalk, the rest grey;
    ``other``: the colour of the light added in ``on`` outside the stripe's columns."""
    extra = on - off
    stripe = np.zeros_like(extra)
    stripe[:, 50:71] = extra[:, 50:71]
    rest = extra - stripe
    rgb = off[..., None] + stripe[..., None] * np.array([1.0, 0.08, 0.08]) + rest[..., None] * np.array(other)
    return rgb


def _ask(frame, cols=None, **kw):
    settings = kw.pop("settings", StripeTest())
    cols = np.argmax(frame, axis=1).astype(float) if cols is None else cols
    return ask(settings, frame, cols, **kw)


def test_a_ridge_of_the_stripe_width_is_a_stripe():
    on, off = _scene()
    a = _ask(on, background=off, colour=colour_evidence(_rgb(on, off)), image=on)
    assert a.yes.all() and (a.reasons == 0).all()
    assert a.stripe_width_px in (2.0, 3.0)
    assert np.all(a.flank < 0.1) and np.all(a.colour > 0.8) and np.all(np.abs(a.off) < 0.2)


def test_a_step_edge_is_not_a_stripe():
    on, _ = _scene()
    rows = slice(0, 20)  # a lit door edge at column 110, brighter than the stripe, falling off to the right
    j = np.arange(W)
    on[rows] += np.where(j >= 110, 220.0 * np.exp(-(j - 110) / 25.0), 0.0)
    a = _ask(on, settings=StripeTest(continuity_rows=None))
    assert np.all(np.argmax(on[rows], axis=1) >= 110)
    assert not a.yes[rows].any() and a.said_no("ridge")[rows].all()
    assert a.yes[20:].all()
    # the same frame asked without the ridge test and the width test: the edge passes
    loose = _ask(on, settings=StripeTest(flank_level=None, width_ratio=None, continuity_rows=None))
    assert loose.yes.all()


def test_a_wide_glow_is_not_a_stripe():
    on, _ = _scene()
    rows = slice(30, 50)
    on[rows] += stripe_profile(np.full(20, 120.0), W, 8.0, 200.0)  # a glow (a lamp, a window) 8x the stripe's width
    a = _ask(on, settings=StripeTest(flank_level=None, continuity_rows=None))
    assert not a.yes[rows].any() and a.said_no("width")[rows].all()
    assert a.yes[:30].all() and a.yes[50:].all()
    assert _ask(on, settings=StripeTest(continuity_rows=None)).said_no("ridge")[rows].all()  # its flanks stay up


def test_a_coloured_object_is_not_a_stripe_where_colour_is_given():
    on, off = _scene()
    rows = slice(10, 40)
    bump = np.zeros((H, W))
    bump[rows] = stripe_profile(np.full(30, 120.0), W, 1.5, 220.0)  # skin-coloured: a narrow, bright ridge
    on = on + bump
    off = off + bump  # it is there with the laser off as well; the colour test is asked alone
    rgb = _rgb(on, off - bump, other=(0.95, 0.62, 0.5))
    settings = StripeTest(off_ratio=None, continuity_rows=None)
    a = _ask(on, settings=settings, colour=colour_evidence(rgb))
    assert not a.yes[rows].any() and a.said_no("colour")[rows].all()
    assert 0.2 < np.nanmax(a.colour[rows]) < 0.5
    assert a.yes[40:].all() and a.yes[:10].all()
    assert _ask(on, settings=settings).yes.all()  # without colour, a ridge of the right width passes


def test_a_drawn_line_is_not_a_stripe():
    on, off = _scene()
    on[:, 130:132] = 200.0  # a grey line drawn on the recording: in both frames, a ridge 2 px wide
    off[:, 130:132] = 200.0
    on[:, 60] = on[:, 59] = 10.0  # the stripe is gone: the line is each row's peak
    rgb = np.repeat(on[..., None], 3, axis=2)
    a = _ask(on, image=on, background=off, colour=colour_evidence(rgb))
    assert not a.yes.any()
    assert a.said_no("colour").all() and a.said_no("off").all() and not a.said_no("ridge").any()


def test_led_dots_are_not_a_stripe_by_continuity():
    on, _ = _scene()
    on[:, 55:66] = 10.0  # no stripe at all
    for r0, c0 in ((5, 20), (25, 100), (45, 40), (65, 130)):  # LED dots, 3 rows tall, 2 px wide
        on[r0:r0 + 3, c0:c0 + 2] = 180.0
    cols = np.full(H, np.nan)
    for r0, c0 in ((5, 20), (25, 100), (45, 40), (65, 130)):
        cols[r0:r0 + 3] = c0
    a = _ask(on, cols)
    assert a.asked.sum() == 12 and not a.yes.any()
    assert a.said_no("continuity")[a.asked].all()
    assert (a.reasons[a.asked] == REASONS["continuity"]).all()  # each dot is a ridge of the right width


def test_a_dim_wide_stripe_among_noise_peaks_as_strong_is_measured_on_its_own_rows():
    # A dark 8-bit frame: a stripe 7 px wide and 4 DN over a 1 DN floor in rows 0-29, and in every
    # fourth row below, a one-pixel peak of noise as strong as the stripe at a random column (what a
    # detector's candidates hold in a dim render). The stripe's width is measured on its own rows, in
    # line, not on the noise's, which outnumber them among the strongest.
    rng = np.random.default_rng(3)
    f = np.ones((H, W), np.uint8)
    f[:30, 57:64] = 5
    noise_rows = np.arange(32, H, 4)
    noise_cols = rng.integers(5, W - 5, noise_rows.size)
    f[noise_rows, noise_cols] = 5
    cols = np.full(H, np.nan)
    cols[:30] = STRIPE_COL
    cols[noise_rows] = noise_cols
    a = ask(StripeTest(), f, cols)
    assert a.stripe_width_px == 7.0
    assert a.yes[:30].all() and not a.yes[30:].any()
    assert a.said_no("continuity")[noise_rows].all()
    # measured on every asked row, the noise's 1 px would make the stripe too wide and its flanks part of it
    off = ask(StripeTest(continuity_rows=None), f, cols)
    assert off.stripe_width_px == 1.0 and not off.yes[:30].any()


def test_a_stripe_on_the_frames_edge_has_one_flank_and_a_short_frame_asks_for_all_its_rows():
    on, _ = _scene()
    edge = np.roll(on, -int(STRIPE_COL), axis=1)  # the stripe centred on column 0: its left flank is outside
    a = _ask(edge, np.zeros(H))
    assert a.yes.all() and np.all(a.flank < 0.2)  # read on its one side in the frame
    right = _ask(edge[:, ::-1], np.full(H, W - 1.0))  # and on the last column
    assert right.yes.all()
    # a frame of 3 rows cannot hold 4 rows in line: its other 2 rows are asked for; a row out of line fails
    short = on[:3].copy()
    assert _ask(short, np.full(3, STRIPE_COL)).yes.all()
    short[1] = on[1, np.r_[30:W, 0:30]]  # row 1's stripe moved 30 px
    b = _ask(short)
    assert not b.yes.any() and b.said_no("continuity").all()


def test_a_peak_in_the_laser_off_frame_is_not_the_laser():
    on, off = _scene()
    rows = slice(50, 70)
    lamp = np.zeros((H, W))
    lamp[rows] = stripe_profile(np.full(20, 30.0), W, 1.2, 200.0)  # ambient light, stripe-like, brighter
    a = _ask(on + lamp, image=on + lamp, background=off + lamp)
    assert not a.yes[rows].any() and a.said_no("off")[rows].all()
    assert a.yes[:50].all() and a.yes[70:].all()
    assert _ask(on + lamp).yes.all()  # without the laser-off frame, nothing tells them apart


def test_rows_without_a_column_are_not_asked_and_the_answer_is_flip_and_dtype_invariant():
    on, off = _scene(3)
    on[:20, 120:] += 120.0  # a lit plateau
    cols = np.argmax(on, axis=1).astype(float)
    cols[70:] = np.nan
    a = _ask(on, cols)
    assert not a.asked[70:].any() and not a.yes[70:].any() and (a.width_px[70:] == 0).all()
    flipped = _ask(on[::-1].copy(), cols[::-1].copy())
    np.testing.assert_array_equal(flipped.yes, a.yes[::-1])
    u8 = np.clip(np.rint(on), 0, 255).astype(np.uint8)
    np.testing.assert_array_equal(_ask(u8, cols).yes, _ask(u8.astype(np.float64), cols).yes)


def test_a_dim_ridge_is_not_the_stripe_where_the_level_is_asked():
    on, _ = _scene()
    rows = slice(0, 25)  # rows with no stripe: a poster's ridge in a dark room, a tenth as bright as the stripe
    on[rows] = 10.0 + np.random.default_rng(1).normal(0.0, 1.5, (25, W))
    on[rows] += stripe_profile(np.full(25, 110.0), W, 1.2, 15.0)
    shape_only = StripeTest(continuity_rows=None)
    assert _ask(on, settings=shape_only).yes.all()  # a ridge of the stripe's width: the shape tests pass it
    a = _ask(on, settings=StripeTest(continuity_rows=None, level_min=0.3))
    assert not a.yes[rows].any() and a.said_no("level")[rows].all()
    assert a.yes[25:].all() and not a.said_no("level")[25:].any()
    assert 130.0 < a.stripe_contrast < 160.0  # the stripe's rows, the strongest half of the rows asked
    # a level below the ridge's share passes it: the test compares with the stripe's own rows
    assert _ask(on, settings=StripeTest(continuity_rows=None, level_min=0.05)).yes.all()


def test_the_level_is_not_asked_by_default_and_is_checked():
    assert StripeTest().level_min is None and as_test({}).level_min is None
    assert StripeTest(level_min=0.3).label() == "level_min=0.3"
    with pytest.raises(ValueError, match="`level_min` must be None or a number in \\[0, 1\\]"):
        StripeTest(level_min=1.5)
    f = np.zeros((4, 6))
    assert np.isnan(ask(StripeTest(level_min=0.3), f, np.full(4, np.nan)).stripe_contrast)


def test_settings_are_checked_and_read_from_a_table():
    assert as_test(None) is None and as_test({}) == StripeTest()
    assert as_test({"colour_min": None}).colour_min is None
    with pytest.raises(ValueError, match="unknown setting"):
        as_test({"width": 3})
    with pytest.raises(ValueError, match="`stripe_test`: `continuity_min` must be an integer >= 1"):
        as_test({"continuity_min": 0})
    with pytest.raises(ValueError, match="at most 2 \\* continuity_rows"):
        StripeTest(continuity_rows=2, continuity_min=5)
    with pytest.raises(ValueError, match="`stripe_test` must be None or a table"):
        trackers.make("dp4", stripe_test="on").track(np.zeros((4, 5)))
    assert StripeTest(width_ratio=4.0, off_ratio=None).label() == "width_ratio=4,off_ratio=none"


def _distractor_frame(seed=0):
    """A stripe in the lower rows only (rows 40-119) and a lit door edge in the upper rows, brighter than
    the stripe, with its laser-off frame and the colour evidence of the photograph."""
    rng = np.random.default_rng(seed)
    h, w = 120, 160
    off = 8.0 + rng.normal(0.0, 1.5, (h, w))
    j = np.arange(w)
    off[:40] += np.where(j >= 110, 160.0 * np.exp(-(j - 110) / 20.0), 0.0)[None, :]
    truth = np.full(h, np.nan)
    truth[40:] = 60.0 + 10.0 * np.sin(np.arange(80) / 15.0)
    on = off.copy()
    on[40:] += stripe_profile(truth[40:], w, 1.2, 140.0)
    rgb = off[..., None] + (on - off)[..., None] * np.array([1.0, 0.08, 0.08])
    to8 = lambda a: np.clip(np.rint(a), 0, 255).astype(np.uint8)  # noqa: E731
    return to8(on), to8(off), colour_evidence(to8(rgb)), truth


@pytest.mark.parametrize("name", ["threshold", "centroid", "gauss3", "com_bg", "steger", "dp4", "dp8",
                                  "dp8_subpixel", "dp_gap", "learned"])
def test_every_tracker_reads_the_question(name):
    on, off, colour, truth = _distractor_frame()
    plain = trackers.make(name, stripe_test=None)
    asked = trackers.make(name, stripe_test={})
    # without a laser-off frame, as a one-frame tracker sees it
    a = plain.track(on, colour=colour).columns
    b = asked.track(on, colour=colour).columns
    np.testing.assert_array_equal(a, plain.track(on).columns)  # not asked: colour changes nothing
    stripe = np.isfinite(truth)
    assert not np.isfinite(b[~stripe]).any(), f"{name} still reports on the lit edge"
    assert np.isfinite(b[stripe]).mean() > 0.9
    assert np.nanmax(np.abs(b[stripe] - truth[stripe])) < 3.0
    # stripe_test=None, the default, does not ask; {} the defaults; the answer's rows only remove reports
    assert trackers.make(name).get_params() == plain.get_params()
    assert not (np.isfinite(b) & ~np.isfinite(a)).any()
