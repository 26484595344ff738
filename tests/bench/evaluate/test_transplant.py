"""A photograph's own stripe found (bench.evaluate.stripe, colourguide), moved to a known place (transplant) and its rows
read as a reference reads them (rowstates), on synthetic frames with known stripes."""

import numpy as np
import pytest

from bench.evaluate import colourguide as cg
from bench.evaluate import conditions as cond
from bench.evaluate import rowstates as rs
from bench.evaluate import stripe as sp
from bench.evaluate import transplant as tp
from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.evaluate.outcomes import NO_STRIPE, STRIPE, UNSURE

H, W = 80, 160


def _frame(centre, *, sigma=1.5, amp=150.0, level=30.0, noise=2.0, seed=0, rows=slice(None), rgb=False):
    """A textured-free frame with a Gaussian stripe at ``centre`` (px, per row or scalar) in ``rows``."""
    rng = np.random.default_rng(seed)
    x = np.arange(W, dtype=float)
    c = np.broadcast_to(np.asarray(centre, float), (H,))
    stripe = amp * np.exp(-0.5 * ((x[None, :] - c[:, None]) / sigma) ** 2)
    mask = np.zeros(H, bool)
    mask[rows] = True
    img = level + np.where(mask[:, None], stripe, 0.0) + rng.normal(0, noise, (H, W))
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    if rgb:  # a red laser on a grey scene
        grey = np.clip(np.rint(level + rng.normal(0, noise, (H, W))), 0, 255).astype(np.uint8)
        return np.stack([img, grey, grey], axis=-1)
    return img


@pytest.mark.parametrize("estimate", sp.ESTIMATES)
def test_extents_find_a_slanted_stripe_and_its_centre(estimate):
    centre = 60.0 + 0.2 * np.arange(H)
    ext = sp.stripe_extents(_frame(centre), estimate=estimate)
    assert ext.visible.all()
    assert np.max(np.abs(ext.centre - centre)) < 0.3
    assert np.all(ext.lo <= np.floor(centre) - 2) and np.all(ext.hi >= np.ceil(centre) + 2)
    assert ext.noise_dn == pytest.approx(2.0, rel=0.25)


@pytest.mark.parametrize("estimate", sp.ESTIMATES)
def test_a_stray_bright_pixel_does_not_guide_the_stripe(estimate):
    img = _frame(60.0)
    img[40, 120] = 255  # one hot pixel, brighter than the stripe, in one row
    ext = sp.stripe_extents(img, estimate=estimate)
    assert ext.visible.all() and abs(ext.centre[40] - 60.0) < 0.3


def test_moving_the_stripe_cleans_its_place_and_keeps_its_profile():
    img = _frame(60.3, amp=120.0)
    ext = sp.stripe_extents(img)
    moved, truth = tp.transplant(img, ext, 30, seed=1)
    assert moved.dtype == img.dtype and moved.shape == img.shape
    assert np.allclose(truth, ext.centre + 30)
    m = moved.astype(float)
    # the old place is plain background (within the noise); the new place holds the stripe's peak
    assert np.abs(m[:, 56:66].mean() - 30.0) < 1.0
    assert np.all(np.abs(np.argmax(m, axis=1) - 90) <= 1)
    # the moved profile is the old one: peak heights agree row by row within the noise
    assert np.abs(m[:, 90].mean() - img[:, 60].astype(float).mean()) < 2.0
    # the other columns are untouched
    assert np.array_equal(moved[:, :50], img[:, :50]) and np.array_equal(moved[:, 110:], img[:, 110:])


def test_a_laser_off_frame_is_the_clean_plate():
    img = _frame(60.0)
    off = _frame(60.0, amp=0.0, seed=5)
    ext = sp.stripe_extents(img, off)
    moved, _ = tp.transplant(img, ext, -25, background_original=off)
    a, b = int(ext.lo[0]), int(ext.hi[0])
    assert np.array_equal(moved[:, a:b + 1], off[:, a:b + 1])


def test_colour_photographs_move_all_channels_and_clip_to_the_dtype():
    rgb = _frame(60.0, amp=240.0, rgb=True)  # a red stripe clipped at 255
    ext = sp.stripe_extents(rgb[..., 0].astype(float) - rgb[..., 1:].mean(axis=-1))
    moved, truth = tp.transplant(rgb, ext, 20, seed=0)
    assert moved.shape == rgb.shape and moved.dtype == np.uint8
    assert (moved[:, 80, 0] == 255).mean() > 0.9 and np.all(np.isfinite(truth))


def test_a_stripe_within_its_noise_of_the_top_stays_clipped_when_it_moves_onto_a_darker_surface():
    """A JPEG's clipped core decodes a few DN below the top: moved onto a darker surface, it is not its observed
    excess over a bright surface (the clipping hid the rest) but clipped, as it was (``CLIP_NOISE_K``)."""
    rng = np.random.default_rng(2)
    img = np.where(np.arange(W)[None, :] < 70, 230.0, 150.0) + rng.normal(0, 1.0, (H, W))  # bright left, dark right
    img[:, 40] = 254.0  # the core, 254: within 2 noise units of 255
    img[:, 39] = img[:, 41] = 245.0
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img)
    assert np.all(ext.visible) and np.nanmedian(ext.centre) == pytest.approx(40.0, abs=0.1)
    moved, _ = tp.transplant(img, ext, 60, seed=0)
    assert np.all(moved[:, 100] == 255)  # the core stays at the top
    assert np.all(moved[:, 99] < 175)  # its flank adds its own excess (about 15 DN) to the darker surface


def test_rows_that_cannot_move_are_cleaned_and_have_no_truth():
    img = _frame(10.0)
    ext = sp.stripe_extents(img)
    moved, truth = tp.transplant(img, ext, -20, seed=0)  # would leave the frame on the left
    assert np.isnan(truth).all()
    assert moved[:, 5:16].astype(float).mean() < 35.0  # the stripe is gone, not moved


def test_row_states_read_the_moved_stripe_like_a_reference():
    img = _frame(60.0, rows=slice(10, 40))
    ext = sp.stripe_extents(img)
    assert ext.visible[10:40].all() and not ext.visible[50:].any()
    moved, truth = tp.transplant(img, ext, 30, seed=0)
    st = rs.row_states(ext, truth, moved)
    assert (st[10:40] == STRIPE).all()
    assert (st[:10] == UNSURE).all() or (st[:10] != STRIPE).all()
    # the guide reaches GUIDE_ROWS rows past the last visible row; GAP_ROWS beyond it a report is false
    last = int(np.flatnonzero(np.isfinite(ext.centre))[-1])
    assert 39 <= last <= 39 + DEFAULT.guide_rows
    assert (st[last + 15:] == NO_STRIPE).all() and (st[40:last + 15] == UNSURE).all()


def test_rows_far_dimmer_than_the_stripe_are_not_scored():
    """A stripe 150 DN high whose rows 30-39 stand 20 DN (10 noise units: seen by the reference rule, but under
    DIM_SHARE of the stripe's typical height): moved, those rows are UNSURE, as a reference leaves unclear rows out; the
    rest are stripe rows. A stripe 40 DN high there (over DIM_SHARE) is scored throughout."""
    for amp, dim in ((20.0, True), (40.0, False)):
        img = _frame(60.0).astype(float)
        x = np.arange(W, dtype=float)
        img[30:40] -= (150.0 - amp) * np.exp(-0.5 * ((x - 60.0) / 1.5) ** 2)
        img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
        ext = sp.stripe_extents(img)
        assert ext.visible.all() and rs.dim_rows(ext)[30:40].all() == dim and not rs.dim_rows(ext)[:30].any()
        moved, truth = tp.transplant(img, ext, 30, seed=0)
        st = rs.row_states(ext, truth, moved)
        assert (st[30:40] == (UNSURE if dim else STRIPE)).all()
        assert (st[:30] == STRIPE).all() and (st[40:] == STRIPE).all()


def test_shift_clears_the_extent_and_bad_input_is_refused():
    ext = sp.stripe_extents(_frame(60.0, sigma=4.0))
    s = tp.shift_for(ext)
    assert s >= 12 and s > int(np.max(ext.hi - ext.lo)) + DEFAULT.side_px
    with pytest.raises(ValueError, match="shift_px"):
        tp.transplant(_frame(60.0), ext, 0)
    with pytest.raises(ValueError, match="original"):
        tp.transplant(np.zeros((5, W)), ext, 20)
    with pytest.raises(ValueError, match="frame"):
        sp.stripe_extents(np.zeros(10))


def test_the_path_follows_the_stripe_past_a_brighter_rival_that_the_argmax_takes():
    img = _frame(60.0).astype(float)
    x = np.arange(W, dtype=float)
    img[:12] += 220.0 * np.exp(-0.5 * ((x - 130.0) / 1.5) ** 2)  # a rival ridge over the stripe's first 12 rows
    img = np.clip(img, 0, 255).astype(np.uint8)
    path = sp.stripe_extents(img, estimate="path")
    argmax = sp.stripe_extents(img, estimate="argmax")
    assert np.all(np.abs(path.centre[:12] - 60.0) < 0.5)  # the continuous stripe, not the short rival
    assert np.all(np.abs(argmax.centre[:8] - 130.0) < 0.5)  # each row's maximum, where the rival has support
    with pytest.raises(ValueError, match="estimate"):
        sp.stripe_extents(img, estimate="guess")


def test_the_argmax_guide_takes_a_thin_stripe_over_a_brighter_glow_wider_than_the_reference_window():
    img = _frame(60.0, sigma=0.8, amp=80.0).astype(float)
    img[:, 95:135] += 160.0  # a lit patch 40 px wide, brighter than the stripe in every row
    img = np.clip(img, 0, 255).astype(np.uint8)
    assert np.all(np.argmax(img, axis=1) >= 95)  # each row's maximum is in the patch
    ext = sp.stripe_extents(img, estimate="argmax")
    assert np.all(np.abs(ext.centre - 60.0) < 0.5)  # the highest over the window around it is the stripe
    assert np.all(ext.visible)


def _hand_frame(*, seed=0):
    """A clipped core (cols 70-76) in a glow 200-240 DN wide of the window, a dip to 185 at its left edge (cols
    66-68) and a glow's shoulder standing 8 DN over its surroundings beside the dip (col 63), as on ``bb_hand``."""
    rng = np.random.default_rng(seed)
    x = np.arange(W, dtype=float)
    row = 110 + 130 * np.exp(-0.5 * ((x - 70) / 14.0) ** 2)
    row[63] += 10.0
    row[66:69] = 185.0
    row[70:77] = 258.0
    img = row[None, :] + rng.normal(0, 0.7, (H, W))
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def test_a_clipped_core_outranks_the_glow_s_shoulder_beside_a_dip():
    from bench.evaluate.conditions import row_smoothed

    img = _hand_frame()
    lift = sp.window_lift(row_smoothed(img.astype(float)))
    assert np.all(np.abs(np.argmax(lift, axis=1) - 64) <= 2)  # the shoulder stands highest over its window
    ext = sp.stripe_extents(img, estimate="argmax")
    assert np.all((ext.centre >= 70) & (ext.centre <= 76))  # on the clipped core, as a reference is
    guide = sp.estimate_guide(img, estimate="argmax")
    assert np.all(np.abs(guide - 73.0) <= 3.5)
    # the same frame a float (no known top): nothing counts as clipped, the shoulder guides
    assert np.all(np.abs(sp.estimate_guide(img.astype(float), estimate="argmax") - 64.0) <= 2)


def test_argmax_pick_takes_the_highest_clipped_pixel_standing_out_and_refuses_a_mask_of_another_shape():
    lift = np.array([[0.0, 9.0, 1.0, 5.0, 3.0], [0.0, 9.0, 1.0, 5.0, 3.0], [0.0, 9.0, 1.0, 2.0, 3.0]])
    clipped = np.array([[0, 0, 1, 1, 1], [0, 0, 0, 0, 0], [0, 0, 1, 1, 1]], bool)
    # row 0: clipped pixels 3 and 4 stand at least 3, 3 the highest; row 1: none clipped; row 2: none standing 3
    assert sp.argmax_pick(lift, clipped, 3.0).tolist() == [3, 1, 4]
    assert sp.argmax_pick(lift, None, 3.0).tolist() == [1, 1, 1]
    with pytest.raises(ValueError, match="`clipped` must have the shape of `lift`"):
        sp.argmax_pick(lift, clipped[:, :4], 3.0)
    assert sp.clipped_pixels(np.array([[250, 253, 254, 255]], np.uint8), 0.4).tolist() == [[False, False, True, True]]
    assert sp.clipped_pixels(np.array([[250, 253, 254, 255]], np.uint8), 1.0).tolist() == [[False, True, True, True]]


@pytest.mark.parametrize("sigma, chosen", [(0.8, "argmax"), (3.0, "path")])
def test_auto_takes_the_argmax_for_a_narrow_stripe_and_the_path_for_a_wide_one(sigma, chosen):
    img = _frame(60.0, sigma=sigma).astype(float)
    x = np.arange(W, dtype=float)
    img[:12] += 220.0 * np.exp(-0.5 * ((x - 130.0) / sigma) ** 2)  # a rival the two estimates tell apart
    img = np.clip(img, 0, 255).astype(np.uint8)
    width = cond.measure(img).width_px
    assert (width <= DEFAULT.auto_width_px) == (chosen == "argmax")  # FWHM = 2.355 sigma
    auto, other = sp.stripe_extents(img, estimate="auto"), sp.stripe_extents(img, estimate=chosen)
    assert np.array_equal(auto.centre, other.centre, equal_nan=True) and np.array_equal(auto.visible, other.visible)
    unchosen = sp.stripe_extents(img, estimate="path" if chosen == "argmax" else "argmax")
    assert not np.array_equal(auto.centre, unchosen.centre, equal_nan=True)


@pytest.mark.parametrize("noise, guarded", [(0.0, True), (2.0, False)])
def test_auto_takes_the_argmax_where_the_paths_score_is_capped_over_much_of_the_frame(noise, guarded):
    # a wide stripe (FWHM 5.9 px) with a 2-row gap every 10 rows, beside a pale wall 6 DN up, unbroken
    rows = (np.arange(H) % 10) < 8
    img = _frame(40.0, sigma=2.5, noise=noise, rows=rows).astype(float)
    img[:, 110:] += 6.0
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    m = cond.measure(img)
    assert m.width_px > DEFAULT.auto_width_px  # the width rule alone would take the path
    sm = img.astype(float)
    sm[:, 1:-1] = 0.25 * sm[:, :-2] + 0.5 * sm[:, 1:-1] + 0.25 * sm[:, 2:]
    share = sp.capped_share(sm, np.median(img.astype(float), axis=1), m.noise_dn)
    assert (share >= DEFAULT.auto_capped) == guarded
    auto = sp.stripe_extents(img, estimate="auto")
    same = sp.stripe_extents(img, estimate="argmax" if guarded else "path")
    assert np.array_equal(auto.centre, same.centre, equal_nan=True)
    assert np.all(np.abs(auto.centre[rows] - 40.0) < 0.5)  # the stripe, wherever it is
    if guarded:  # without noise the cap is 3.5 DN: the wall scores as high as the stripe, and the path takes it
        assert np.mean(np.abs(sp.stripe_extents(img, estimate="path").centre[rows] - 40.0) < 0.5) < 0.5


def test_a_guide_of_the_wrong_length_is_refused():
    img = np.full((20, 30), 10.0)
    with pytest.raises(ValueError,
                       match=r"`guide` must have one column per row of `frame`, shape \(20,\), got \(19,\)"):
        sp.stripe_extents(img, guide=np.zeros(19))


def test_laser_evidence_needs_brightness_and_colour_and_subtracts_the_laser_off_frame():
    red = np.full((4, 100), 100.0)
    excess = np.zeros((4, 100))
    red[:, 8] = 250.0  # white: bright, no colour
    excess[:, 20] = 90.0  # the laser's hue, no brighter than its row
    red[:, 31:34] = [180.0, 255.0, 180.0]
    excess[:, 31:34] = [50.0, 0.0, 50.0]  # the stripe: a clipped core with a coloured fringe
    ev = cg.laser_evidence(red, excess)
    assert ev[:, 8].max() == 0.0 and ev[:, 20].max() == 0.0
    assert np.all(np.isin(np.argmax(ev, axis=1), [31, 32, 33]))  # the stripe: its core and fringe, both bright
    assert np.all(ev[:, 32] == ev.max(axis=1))
    assert ev[0, 32] == pytest.approx(min(155.0, 50.0))
    assert not cg.laser_evidence(red, excess, red, excess).any()  # the laser-off frame holds it all
    with pytest.raises(ValueError, match=r"`laser_channel` and `excess` must be 2-D of one shape, got \(4, 100\) and"):
        cg.laser_evidence(red, excess[:, :5])
    with pytest.raises(ValueError, match=r"`excess_background` must have the shape of `laser_channel` \(4, 100\)"):
        cg.laser_evidence(red, excess, None, excess[:2])


def test_arbitrate_keeps_the_first_guide_unless_the_other_has_more_evidence_far_enough_away():
    ev = np.zeros((4, 30))
    ev[:, 20] = 3.0
    ev[:, 5] = 3.0
    guide = np.array([5.0, 5.0, 18.0, np.nan])
    other = np.array([20.0, 8.0, 22.0, 20.0])
    ev[0, 5] = 1.0  # row 0: the other guide has more evidence
    # row 1: the guides lie within conditions.JUMP_PX: kept; row 2: a tie within ARBITER_HALF_PX: kept; row 3: filled
    assert cg.arbitrate(guide, other, ev).tolist() == [20.0, 5.0, 18.0, 20.0]
    with pytest.raises(ValueError, match=r"one entry per row of `evidence` \(4, 30\), got \(4,\) and \(3,\)"):
        cg.arbitrate(guide, other[:3], ev)


def test_a_moved_stripe_does_not_land_on_a_rival():
    """A rival brighter than the stripe 15 px to its right: the shift to the right passes it (the moved stripe would
    be found where the rival is, which the photograph's stripe is not), the shift to the left stays the least
   ."""
    img = _frame(60.0).astype(float)
    c = int(round(float(np.nanmedian(sp.stripe_extents(img).centre))))
    img[:, c + 14:c + 17] += 200.0  # the rival, brighter than the stripe
    img = np.clip(img, 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img, guide=np.full(img.shape[0], float(c)))
    rivals = tp.rival_mask(img, None, ext)
    assert rivals[:, c + 15].all() and not rivals[:, c - 3:c + 4].any()
    right, left = tp.shifts_for(ext, rivals)
    base = tp.shift_for(ext)
    assert left == base and right > base
    for r in np.flatnonzero(ext.visible):  # no moved extent (with its sides) meets the rival
        assert not (ext.lo[r] + right - DEFAULT.side_px <= c + 15 <= ext.hi[r] + right + DEFAULT.side_px)


def test_a_clipped_core_in_a_glow_filling_the_window_is_seen_and_a_faint_row_is_not():
    """Rows 10-19: a clipped core 3 px wide in a glow of 240 DN 40 px wide (the reference window's median is the glow's,
    so the rule does not see the core); rows 30-34 a 4 DN stripe; elsewhere a 150 DN stripe. With the clipped peaks
    the core rows are stripe rows, the faint ones still not."""
    from bench.evaluate.outcomes import STRIPE, UNSURE, referenced_states

    rng = np.random.default_rng(12)
    img = rng.normal(30.0, 2.0, (50, 80))
    img[:, 40] += 150.0
    img[10:20, 20:60] = 240.0 + rng.normal(0, 2.0, (10, 40))
    img[10:20, 39:42] = 255.0
    img[30:35, 40] = 34.0
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    truth = np.full(50, 40.0)
    ext = sp.stripe_extents(img, guide=truth)
    clipped = rs.clipped_peaks(img, ext)
    assert clipped[10:20].all() and not clipped[30:35].any()
    assert (referenced_states(img, truth)[10:20] == UNSURE).all()
    states = rs.seen_states(img, truth, clipped)
    assert (states[10:20] == STRIPE).all() and (states[30:35] == UNSURE).all() and (states[:10] == STRIPE).all()
    assert np.array_equal(rs.seen_states(img, truth), referenced_states(img, truth))
    with pytest.raises(ValueError, match=r"`clipped` must have one entry per row, shape \(50,\), got \(49,\)"):
        rs.seen_states(img, truth, clipped[1:])


def test_a_clipped_core_in_a_glow_of_the_surface_s_is_a_stripe_row_of_the_frames_and_one_in_a_dim_glow_is_not():
    """Rows 10-19: a core clipped at 255 in a glow of 250 DN over 30 px (0.98 of the top), which the reference rule
    does not see; rows 30-39: the same core in a glow of 120 DN; elsewhere a clear stripe on 30 DN."""
    rng = np.random.default_rng(9)
    img = rng.normal(30.0, 1.0, (50, 80))
    img[:, 40] += 150.0
    img[10:20, 25:56] = 250.0 + rng.normal(0, 1.0, (10, 31))
    img[30:40, 25:56] = 120.0 + rng.normal(0, 1.0, (10, 31))
    img[10:20, 39:42] = img[30:40, 39:42] = 255.0
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    truth = np.full(50, 40.0)
    ext = sp.stripe_extents(img, guide=truth)
    glow = rs.glow_rows(img, ext)
    assert glow[10:20].all() and not glow[:10].any() and not glow[20:].any()
    seen = rs.clipped_peaks(img, ext) & glow
    plain = rs.row_states(ext, truth, img, unclear=np.zeros(50, bool))
    read = rs.row_states(ext, truth, img, unclear=np.zeros(50, bool), seen=seen)
    assert (plain[10:20] == UNSURE).all() and (read[10:20] == STRIPE).all()
    assert np.array_equal(np.delete(plain, range(10, 20)), np.delete(read, range(10, 20)))  # no other row changes
    assert (read[30:40] == plain[30:40]).all()
    # an unclear row stays out, as a reference leaves it out
    unclear = np.zeros(50, bool)
    unclear[12] = True
    assert rs.row_states(ext, truth, img, unclear=unclear, seen=seen)[12] == UNSURE
    assert not rs.glow_rows(img.astype(float), ext).any()  # a float frame has no known top
    with pytest.raises(ValueError, match=r"`seen` must have one entry per row, shape \(50,\), got \(49,\)"):
        rs.row_states(ext, truth, img, seen=seen[1:])
    with pytest.raises(ValueError, match="`frame` must be 2-D"):
        rs.glow_rows(np.zeros((50, 80, 3), np.uint8), ext)


def test_guided_dim_rows_also_count_the_faint_rows_the_extent_does_not_call_visible():
    """Rows 10-14 of a 100 DN stripe stand 3 DN up, under 6 noise units (not visible) and under a fifth of its
    height: ``guided`` counts them dim, as a reference leaves them out; by default only visible rows can be dim."""
    rng = np.random.default_rng(8)
    img = rng.normal(30.0, 1.0, (40, 60))
    height = np.full(40, 100.0)
    height[10:15] = 3.0
    img[:, 30] += height
    ext = sp.stripe_extents(img, guide=np.full(40, 30.0))
    assert not ext.visible[10:15].any() and ext.visible[15:].all()
    assert not rs.dim_rows(ext).any()
    want = np.zeros(40, bool)
    want[10:15] = True
    assert np.array_equal(rs.dim_rows(ext, guided=True), want)
    assert np.array_equal(rs.unclear_rows(ext, img.astype(np.uint8), guided=True), want)


def test_dim_rows_are_the_stripe_s_rows_standing_under_a_fifth_of_its_typical_height():
    """:func:`dim_rows` along a known stripe: 100 DN over the background in most rows, 15 DN (visible, but under
    :data:`DIM_SHARE` of the median) in rows 10-14, 40 DN (over it) in rows 20-24."""
    rng = np.random.default_rng(3)
    img = rng.normal(30.0, 1.0, (40, 60))
    height = np.full(40, 100.0)
    height[10:15], height[20:25] = 15.0, 40.0
    img[:, 30] += height
    ext = sp.stripe_extents(img, guide=np.full(40, 30.0))
    assert ext.visible.all()
    want = np.zeros(40, bool)
    want[10:15] = True
    assert np.array_equal(rs.dim_rows(ext), want)
    assert not rs.dim_rows(sp.Extents(ext.peak, ext.visible, ext.lo, ext.hi, ext.centre, ext.noise_dn)).any()


def test_the_path_follows_a_curved_stripe_s_core_within_a_glow_that_caps_its_score():
    """A stripe inside a wide glow (light scattered under a translucent surface), both far over the path's cap: every
    column of the glow ties, and the path keeps to the stripe's core (``PATH_TIE``), not to the glow's left edge."""
    rng = np.random.default_rng(4)
    x = np.arange(W, dtype=float)[None, :]
    # curved: a straight path inside the glow is cheaper
    centre = 80.0 + 8.0 * np.sin(np.arange(H) / H * np.pi)[:, None]
    img = (20.0 + 60.0 * np.exp(-0.5 * ((x - centre) / 8.0) ** 2) + 150.0 * np.exp(-0.5 * ((x - centre) / 1.5) ** 2)
           + rng.normal(0, 1.0, (H, W)))
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img, estimate="path")
    assert ext.visible.all()
    assert np.max(np.abs(ext.centre - centre[:, 0])) < 0.5


def test_the_tie_break_adds_less_than_a_tenth_of_one_clear_row_over_the_whole_frame():
    lift = np.random.default_rng(0).uniform(0, 300, (H, W))
    t = sp.tie_break(lift)
    assert t.min() >= 0.0 and t.sum(axis=0).max() <= DEFAULT.path_tie + 1e-12
    assert not sp.tie_break(np.zeros((H, W))).any()


def test_a_clipped_peak_is_not_dim_however_low_it_stands_over_its_window():
    """A clipped core (255 DN) in a glow that fills the reference window (230 DN) stands 25 DN over the window's
    median, under DIM_SHARE of a clear stripe's 150: :func:`clipped_peaks` finds its rows, and with them
    :func:`dim_rows` does not count them dim; a faint unclipped stretch still is."""
    img = _frame(60.0).astype(float)
    x = np.arange(W, dtype=float)
    img[10:20] = 20.0 + 210.0 * np.exp(-0.5 * ((x - 60.0) / 12.0) ** 2) + 60.0 * np.exp(-0.5 * ((x - 60.0) / 1.5) ** 2)
    img[30:40] -= 130.0 * np.exp(-0.5 * ((x - 60.0) / 1.5) ** 2)  # a faint stretch, 20 DN high
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img, guide=np.full(H, 60.0))
    clipped = rs.clipped_peaks(img, ext)
    assert clipped[10:20].all() and not clipped[:10].any() and not clipped[20:].any()
    assert rs.dim_rows(ext)[10:20].all() and rs.dim_rows(ext)[30:40].all()
    assert not rs.dim_rows(ext, clipped=clipped)[10:20].any() and rs.dim_rows(ext, clipped=clipped)[30:40].all()
    assert not rs.clipped_peaks(img.astype(float), ext).any()  # a float image has no known top
    with pytest.raises(ValueError, match="`clipped` must have one entry per row"):
        rs.dim_rows(ext, clipped=np.zeros(H + 1, bool))
    # the convention's one home: dim, less the clipped peaks; the row states read it as given
    assert np.array_equal(rs.unclear_rows(ext, img), rs.dim_rows(ext, clipped=clipped))
    assert np.array_equal(rs.unclear_rows(ext), rs.dim_rows(ext))
    with pytest.raises(ValueError, match="`unclear` must have one entry per row"):
        rs.row_states(ext, np.full(H, np.nan), img, unclear=np.zeros(H + 1, bool))


def test_a_stripe_split_by_its_white_core_moves_whole():
    # a laser-colour frame of a stripe whose core is clipped white: two humps either side of a dip to the background
    rng = np.random.default_rng(3)
    img = 20.0 + rng.normal(0, 1.5, (H, W))
    img[:, 57:65] += [40.0, 190.0, 230.0, 0.0, 0.0, 220.0, 150.0, 20.0]
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img)
    assert ext.visible.all()
    assert np.all(ext.lo <= 57) and np.all(ext.hi >= 64)  # both humps, across the dip
    moved, _ = tp.transplant(img, ext, 30, seed=1)
    m = moved.astype(float)
    assert np.abs(m[:, 55:67].mean() - 20.0) < 1.5  # neither hump is left in place
    assert np.all(m[:, 88:92].max(axis=1) > 180.0) and np.all(m[:, 92:94].max(axis=1) > 180.0)


def test_a_white_bar_with_a_little_colour_does_not_outweigh_a_faint_stripe():
    # a red stripe 22 DN over its row, 22 DN of colour; a white bar 235 DN over its row, 3 DN of colour at its edge
    red = np.full((30, 80), 20.0)
    excess = np.zeros((30, 80))
    red[:, 20] += 22.0
    excess[:, 20] = 22.0
    red[:, 50] = 255.0
    excess[:, 53] = 3.0
    ev = cg.laser_evidence(red, excess)
    assert np.all(ev[:, 20] > ev[:, 50])
    # where the two guides part, the stripe's is kept
    assert np.all(cg.arbitrate(np.full(30, 20.0), np.full(30, 50.0), ev) == 20.0)
    assert np.all(cg.arbitrate(np.full(30, 50.0), np.full(30, 20.0), ev) == 20.0)


def test_a_rival_is_something_else_than_the_stripe_s_own_glow():
    # rows 0-19: a stripe in a glow as high as it is over its window; rows 20-39: the stripe and a separate bright bar
    rng = np.random.default_rng(7)
    x = np.arange(W, dtype=float)
    img = 20.0 + rng.normal(0, 1.0, (40, W))
    img[:20] += 120.0 * np.exp(-0.5 * ((x - 60.0) / 10.0) ** 2) + 60.0 * np.exp(-0.5 * ((x - 60.0) / 1.2) ** 2)
    img[20:] += 100.0 * np.exp(-0.5 * ((x - 60.0) / 1.2) ** 2) + 150.0 * np.exp(-0.5 * ((x - 100.0) / 1.5) ** 2)
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img, guide=np.full(40, 60.0))
    r = tp.rival_mask(img, None, ext)
    assert not r[:20].any()  # the glow runs on from the stripe's extent: its own light, not a rival
    assert r[20:, 98:103].any(axis=1).all() and not r[20:, :90].any()  # the bar, apart from it, is one
    landed = tp.landed_rows(ext, r, 40)
    assert landed[20:].all() and not landed[:20].any() and not tp.landed_rows(ext, r, -40).any()


def test_a_glare_clipped_in_two_channels_has_no_hue_and_does_not_take_a_row_where_the_stripe_is_not_seen():
    """As on ``al_room7`` (green laser): a stripe in rows 0-99 and none below, where the colour's guide stays on the
    stripe's column with no laser evidence and the frame's own guide takes a window's glare, green and blue clipped
    and red under the top. Its green over the mean of red and blue is of the stripe's order, so read with the excess
    the arbiter keeps the glare; its hue is hidden (hue_hidden), its flanks are bluer than green, and read so neither
    guide has evidence there and the rows are dropped."""
    from bench.evaluate.pixels import select_channel

    rng = np.random.default_rng(21)
    x = np.arange(160.0)
    rgb = np.full((160, 160, 3), 60.0) + rng.normal(0, 2.0, (160, 160, 3))
    rgb[:100, :, 1] += 40.0 * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)  # the stripe, green
    # the glare, down rows 100-159 at columns 106-114: a window pane, green and blue clipped and red under the top,
    # with sky-blue flanks (as al_room7's window panes; there they are greener, and the rule moves only two rows)
    rgb[100:, 106:115] = [[150, 190, 235], [150, 190, 235]] + [[200, 255, 255]] * 5 + [[150, 190, 235]] * 2
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    hidden = cg.hue_hidden(rgb, "green")
    assert hidden[100:, 108:113].all() and not hidden[:, 106:108].any()  # the clipped core only, not its flanks
    assert not hidden[:100].any() and not hidden[:, :100].any()
    green = rgb[..., 1].astype(float)
    excess = select_channel(rgb, "excess", "green")
    colour = np.full(160, 50.0)  # the colour's guide, on the stripe's column throughout
    own = np.where(np.arange(160) < 100, 50.0, 110.0)  # the frame's own, on the glare below (its middle)
    with_excess = cg.arbitrate(colour, own, cg.laser_evidence(green, excess))
    assert np.all(with_excess[100:] == 110.0)  # read with the excess, the glare keeps the rows
    seen = cg.arbitrate(colour, own, cg.laser_evidence(green, np.where(hidden, 0.0, excess)))
    assert np.all(seen[:100] == 50.0) and np.isnan(seen[100:]).all()  # the stripe kept, the glare's rows dropped


def test_a_near_clipped_laser_channel_rises_at_least_as_much_as_the_others_when_moved():
    """As on ``bb_dark`` (red laser): a whitish core (248 / 241 / 205 DN) in a red glow (85 / 4 / 11), moved onto a
    dark wall. Its red rose less than its green only because it stood near the top; moved as each channel's own lift,
    the core would turn green-white there. With the laser's channel given, red lifts at least as much as green, so the
    moved core stays red-white."""
    rng = np.random.default_rng(5)
    H, W = 60, 120
    rgb = np.full((H, W, 3), [9.0, 4.0, 4.0]) + rng.normal(0, 1.0, (H, W, 3))
    rgb[:, 20:41] = [85.0, 4.0, 11.0]  # the red glow around the stripe
    rgb[:, 28:33] = [[120, 3, 15], [216, 102, 91], [248, 241, 205], [228, 107, 99], [127, 2, 11]]  # the stripe
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    frame = rgb[..., 0].astype(float)
    ext = sp.stripe_extents(frame)
    assert np.isfinite(ext.centre).all() and np.allclose(ext.centre, 30.0, atol=0.5)
    plain, truth = tp.transplant(rgb, ext, 50, seed=1)
    raised, truth2 = tp.transplant(rgb, ext, 50, seed=1, laser_channel=0)
    assert np.array_equal(truth, truth2, equal_nan=True)
    core = plain[:, 80].astype(int), raised[:, 80].astype(int)
    assert np.all(core[0][:, 0] < core[0][:, 1] - 40)  # each channel's own lift: green-white on the dark wall
    assert np.all(core[1][:, 0] >= core[1][:, 1] - 2)  # the laser's channel rises at least as much: red-white
    assert np.array_equal(plain[..., 1:], raised[..., 1:])  # the other channels as before
    below = plain[:, 79].astype(int)  # a pixel under the knee keeps its own lift
    assert np.array_equal(below, raised[:, 79].astype(int))
    grey, _ = tp.transplant(rgb[..., 0], ext, 50, seed=1, laser_channel=0)  # a grey photograph: unchanged
    assert np.array_equal(grey, tp.transplant(rgb[..., 0], ext, 50, seed=1)[0])
    with pytest.raises(ValueError, match="`laser_channel` must be a channel of `original` \\(0-2\\), got 3"):
        tp.transplant(rgb, ext, 50, laser_channel=3)


def test_the_frame_s_own_guide_on_a_glare_wider_than_the_window_has_no_evidence_read_over_both():
    """As on ``al_room7`` (green laser, rows 169-248, which its reference leaves out): the stripe runs on into rows
    where it lies on a dark patch of a row that is mostly a bright wall (nothing over its row's median), and the
    frame's own guide takes a greenish glare 30 px wide on the wall. Read over its row, the glare has the evidence and
    the arbiter keeps it; read on the lesser of its row's and its window's evidence, as colour_guide reads the frame's
    own guide, it has none there, and with the stripe unseen in its row neither guides those rows."""
    from bench.evaluate.pixels import select_channel

    rng = np.random.default_rng(35)
    H, W = 120, 200
    x = np.arange(W, dtype=float)
    rgb = np.full((H, W, 3), [60.0, 62.0, 58.0]) + rng.normal(0, 2.0, (H, W, 3))
    rgb[60:, :120] = [195.0, 160.0, 135.0]  # rows 60-119: most of the row a bright wall
    rgb[60:, 120:] = [102.0, 120.0, 143.0]  # and a dark patch, where the stripe runs on
    rgb[:, :, 1] += np.where(np.arange(H)[:, None] < 60, 40.0, 20.0) * np.exp(-0.5 * ((x - 150.0) / 1.2) ** 2)
    rgb[60:, 30:60] = [205.0, 250.0, 240.0]  # a glare 30 px wide on the wall, greenish
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    green = rgb[..., 1].astype(float)
    excess = np.where(cg.hue_hidden(rgb, "green"), 0.0, select_channel(rgb, "excess", "green"))
    colour = np.full(H, 150.0)  # the colour's guide on the stripe throughout
    own = np.where(np.arange(H) < 60, 150.0, 45.0)  # the frame's own on the glare's middle below
    row = cg.laser_evidence(green, excess)
    both = np.minimum(row, cg.laser_evidence(green, excess, over="window"))  # as colour_guide reads the frame's own
    assert cg.evidence_near(row, own)[60:].min() > 20.0 and cg.evidence_near(both, own)[60:].max() < 2.0
    assert np.all(cg.arbitrate(colour, own, row)[60:] == 45.0)  # read over its row, the glare keeps the rows
    kept = cg.arbitrate(colour, own, row, both)
    assert np.all(kept[:60] == 150.0) and np.isnan(kept[60:]).all()  # over both: the rows are left without a guide
    with pytest.raises(ValueError, match="`over` must be 'row' or 'window', got 'frame'"):
        cg.laser_evidence(green, excess, over="frame")
    with pytest.raises(ValueError, match="`other_evidence` must have the shape of `evidence` \\(120, 200\\)"):
        cg.arbitrate(colour, own, row, both[:10])


def test_evidence_near_is_the_most_within_the_arbiter_s_half_width_at_the_edges_too():
    """evidence_near, the one home of how arbitrate and the rival-fringe family read a guide's evidence: the most of
    each row's evidence within ARBITER_HALF_PX px of the guide's rounded column, the window cut at the frame's edges."""
    rng = np.random.default_rng(3)
    ev = rng.uniform(0, 50, (40, 30))
    guide = rng.uniform(0, 29, 40)
    guide[[0, 1, 2]] = [0.0, 29.0, np.nan]  # both edges, and a row without a guide
    got = cg.evidence_near(ev, guide)
    h = DEFAULT.arbiter_half_px
    for r in range(40):
        if np.isnan(guide[r]):
            assert np.isnan(got[r])
            continue
        c = int(round(guide[r]))
        assert got[r] == ev[r, max(c - h, 0):min(c + h, 29) + 1].max()
    with pytest.raises(ValueError, match="`guide` must have one entry per row of `evidence`"):
        cg.evidence_near(ev, guide[:5])
