"""A photograph's frames with truth (bench.run.predict_frames): its stripe moved both ways, in place and with its ends
cut off, each scored as a photograph is."""

import numpy as np
import pytest

from bench.evaluate import conditions as cond
from bench.evaluate import rowstates as rs
from bench.evaluate import stripe as sp
from bench.evaluate import transplant as tp
from bench.evaluate.predict_settings import DEFAULT
from bench.run import predict_frames as pf



def test_score_frame_scores_stripe_rows_it_sees_and_stripe_less_rows():
    """One synthetic frame: a stripe on the top 80 rows at column 40, none below. The stripe rows are hits,
    the stripe-less rows quiet or false reports, and a row whose stripe is too faint to see is not scored."""
    from bench.config import parse_trackers
    from bench.evaluate import outcomes as oc
    from bench.run.track import build_trackers

    rng = np.random.default_rng(0)
    x = np.arange(96.0)
    img = 20.0 + rng.normal(0, 1.0, (120, 96))
    img[:80] += 150.0 * np.exp(-0.5 * ((x - 40.0) / 1.2) ** 2)
    img[10] = 20.0 + rng.normal(0, 1.0, 96)  # a row whose stripe cannot be seen
    truth = np.where(np.arange(120) < 80, 40.0, np.nan)
    codes = pf.score_frame(build_trackers(parse_trackers(["threshold"])), np.clip(img, 0, 255), truth)["threshold"]
    assert codes.shape == (120,)
    assert codes[10] == oc.UNKNOWN
    assert np.all(codes[np.r_[0:10, 11:80]] == oc.HIT)
    assert set(np.unique(codes[80:])) <= {oc.QUIET, oc.FALSE}


def test_transplant_frames_need_enough_rows_of_the_moved_stripe_seen():
    """A clear stripe over 40 rows gives two moved frames and the photograph in place; the same stripe in 4 rows gives
    none (out of range)."""
    from pathlib import Path

    from bench.evaluate import transplant as tp

    rng = np.random.default_rng(3)
    x = np.arange(96.0)

    def photo(n_rows):
        img = 30.0 + rng.normal(0, 2.0, (40, 96))
        img[:n_rows] += 150.0 * np.exp(-0.5 * ((x - 40.0) / 1.2) ** 2)
        img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
        return pf.Photo("p", Path("p.png"), img, None, img)

    made = pf.transplant_frames(photo(40))
    shift = made[0][4]
    assert len(made) == pf.N_FULL == 3 and [s for *_, s in made] == [shift, -shift, 0] and shift >= 12
    for image, truth, states, moved, s in made:
        assert np.nanmedian(truth) == pytest.approx(40.0 + s, abs=0.3) and (states == 1).sum() >= DEFAULT.min_rows
    assert pf.transplant_frames(photo(4)) == []


def test_a_long_stripe_also_gives_two_false_report_frames_with_its_ends_cut_off():
    """Frames 4 and 5 move the stripe only between the cut ends (bench.evaluate.transplant.cut_ends) and score no
    stripe row: the cut rows, cleaned and left without a stripe, are stripe-less rows where 15 or more from it."""
    from pathlib import Path

    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import NO_STRIPE, STRIPE

    rng = np.random.default_rng(4)
    x = np.arange(96.0)
    img = 30.0 + rng.normal(0, 2.0, (160, 96)) + 150.0 * np.exp(-0.5 * ((x - 40.0) / 1.2) ** 2)
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    made = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img))
    assert len(made) == 5 and [m[4] for m in made[pf.N_FULL:]] == [m[4] for m in made[:pf.N_MOVED]]
    keep = tp.cut_ends(sp.stripe_extents(img))
    assert keep is not None and 100 <= keep.sum() <= 120
    for image, truth, states, moved, s in made[pf.N_FULL:]:
        assert not (states == STRIPE).any() and (states == NO_STRIPE).sum() >= 2 * 5
        assert np.isnan(truth[~keep]).all() and np.isfinite(truth[keep]).mean() > 0.9
        cut = np.flatnonzero(~keep)
        assert moved[cut].max() < 60  # neither the old stripe nor a moved one in the cut rows
    assert all((m[2] == STRIPE).sum() >= 150 for m in made[:pf.N_FULL])  # the first three score the whole stripe


def test_the_photograph_in_place_is_scored_against_the_estimate_with_its_own_surroundings():
    """The third frame is the photograph itself, untouched (its glow, rivals and surroundings where they are), its
    truth the estimated centre read by the reference rule, and its outcomes count towards the hit rate
   ."""
    from pathlib import Path

    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE

    rng = np.random.default_rng(6)
    x = np.arange(128.0)
    img = 30.0 + rng.normal(0, 2.0, (100, 128)) + 150.0 * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    photo = pf.Photo("p", Path("p.png"), img, None, img)
    made = pf.transplant_frames(photo)
    image, truth, states, moved, shift = made[pf.N_MOVED]
    assert shift == 0 and np.array_equal(image, photo.frame) and np.array_equal(moved, img)
    ext = sp.stripe_extents(img)
    assert np.array_equal(truth, tp.in_place_truth(ext), equal_nan=True)
    assert np.nanmax(np.abs(truth - 50.0)) < 0.3 and (states == STRIPE).sum() >= 90


def test_collect_photos_refuses_a_bad_downscale(tmp_path):
    with pytest.raises(ValueError, match="`downscale` must be an integer >= 1, got 0"):
        pf.collect_photos(tmp_path, downscale=0)


def test_collect_photos_says_in_one_line_which_file_asks_to_be_shown_turned(tmp_path):
    import io

    from PIL import Image

    exif = Image.Exif()
    exif[0x0112] = 8
    Image.new("RGB", (30, 20), (20, 20, 20)).save(tmp_path / "phone.jpg", exif=exif)
    Image.new("RGB", (30, 20), (20, 20, 20)).save(tmp_path / "plain.jpg")
    err = io.StringIO()
    photos = pf.collect_photos(tmp_path, err=err)
    assert [p.name for p in photos] == ["phone", "plain"] and photos[0].frame.shape == (20, 30)  # as stored
    lines = err.getvalue().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("stripebench predict: phone.jpg") and "--rotate 90" in lines[0]
    err = io.StringIO()
    pf.collect_photos(tmp_path, rotate_deg=90, err=err)
    assert err.getvalue() == ""
    Image.new("RGB", (30, 20)).save(tmp_path / "plain_off.png")  # paired: said nothing of
    Image.new("RGB", (30, 20)).save(tmp_path / "alone_off.png")  # no alone.*: one line
    err = io.StringIO()
    assert [p.name for p in pf.collect_photos(tmp_path, rotate_deg=90, err=err)] == ["phone", "plain"]
    assert err.getvalue() == ("stripebench predict: alone_off.png: a laser-off frame with no photograph alone.* beside "
                              "it: not predicted for\n")


def _white_bar_and_green_stripe() -> np.ndarray:
    """A greenish wall (an excess above 0) with a clipped white bar at columns 34-36 (a window's frame) and a green
    stripe at column 130, fainter than the bar in the tracker's frame: uint8 (60, 192, 3)."""
    rng = np.random.default_rng(6)
    rgb = np.array([30.0, 60.0, 30.0]) + rng.normal(0, 2.0, (60, 192, 3))
    rgb[:, 34:37, :] = 255.0
    rgb[..., 1] += 150.0 * np.exp(-0.5 * ((np.arange(192.0) - 130.0) / 1.2) ** 2)
    return np.clip(np.rint(rgb), 0, 255).astype(np.uint8)


def test_auto_finds_a_colour_photograph_s_guide_where_the_laser_s_colour_is():
    """A clipped white bar (a window's frame) is brighter in the tracker's frame than the green stripe: on the colour
    photograph ``auto`` moves the stripe (its guide found on the colour excess, where white has none); on the same
    frame without its colours it moves the bar."""
    from pathlib import Path

    from bench.evaluate.pixels import select_channel

    rgb = _white_bar_and_green_stripe()
    frame = select_channel(rgb, "auto", "green")
    assert frame[:, 35].mean() > frame[:, 130].mean() + 50  # the bar is the brightest line the trackers see
    for original, column in ((rgb, 130.0), (frame, 35.0)):
        made = pf.transplant_frames(pf.Photo("p", Path("p.png"), frame, None, original, "green"))
        assert len(made) >= pf.N_MOVED
        for _, truth, _, _, s in made[:pf.N_MOVED]:
            assert np.nanmedian(truth) == pytest.approx(column + s, abs=0.5)


def test_auto_guides_a_plain_channel_photograph_by_its_own_frame():
    """Where the trackers see a plain channel (a rig's software reading one, or a real set's photograph whose stripe's
    core is clipped white), the guide is that frame's own: the colour guide serves the laser-colour blend only. The
    scene of the test above, seen in the green channel: the white bar is its brightest line, and the bar is moved
   ."""
    from pathlib import Path

    from bench.evaluate.pixels import select_channel

    rgb = _white_bar_and_green_stripe()
    for channel, column in (("auto", 130.0), ("g", 35.0)):
        photo = pf.Photo("p", Path("p.png"), select_channel(rgb, channel, "green"), None, rgb, "green", channel=channel)
        made = pf.transplant_frames(photo)
        assert len(made) >= pf.N_MOVED
        for _, truth, _, _, s in made[:pf.N_MOVED]:
            assert np.nanmedian(truth) == pytest.approx(column + s, abs=0.5)


def test_auto_keeps_a_clipped_stripe_beside_a_surface_more_of_the_laser_s_hue():
    """A red print more red than a stripe clipped nearly white (``ag_tape``'s case): the colour excess alone is
    strongest on the print, the tracker's frame on the stripe; where the two guides part, ``auto`` keeps the one
    that is both bright in the laser's channel and of its colour, so it moves the stripe, not the print
   ."""
    from pathlib import Path

    from bench.evaluate import transplant as tp
    from bench.evaluate.pixels import select_channel

    rng = np.random.default_rng(7)
    rgb = np.full((60, 192, 3), 150.0) + rng.normal(0, 2.0, (60, 192, 3))  # a grey wall
    rgb[:, 30:41] = [140.0, 60.0, 40.0]  # the print: red excess 90, darker than the wall in red
    rgb[:, 128:133] = [[255.0, 215.0, 215.0], [255.0, 235.0, 235.0], [255.0, 240.0, 240.0],
                       [255.0, 235.0, 235.0], [255.0, 215.0, 215.0]]  # the stripe: clipped red, excess 15-40
    rgb = np.clip(np.rint(rgb + rng.normal(0, 1.0, rgb.shape)), 0, 255).astype(np.uint8)
    excess = select_channel(rgb, "excess", "red")
    assert excess[:, 30:41].mean() > excess[:, 128:133].max() + 30  # the print is the most red
    frame = select_channel(rgb, "auto", "red")
    assert 28 <= np.nanmedian(sp.estimate_guide(excess)) <= 42  # the colour guide alone takes the print
    made = pf.transplant_frames(pf.Photo("p", Path("p.png"), frame, None, rgb, "red"))
    assert len(made) >= pf.N_MOVED
    for _, truth, _, _, s in made[:pf.N_MOVED]:
        assert np.nanmedian(truth) == pytest.approx(130.0 + s, abs=0.5)


def test_moved_rows_of_a_clipped_core_in_a_glow_are_scored_and_a_faint_stretch_is_not():
    """A stripe 150 DN high whose rows 40-59 are a clipped core in a glow as wide as the reference window (its peak
    stands some 20 DN over the window's median, under DIM_SHARE of 150) and rows 100-109 a faint stretch (20 DN): in
    the moved frames the clipped rows are stripe rows, as a reference scores a bright stripe, and the faint ones are
    not scored."""
    from pathlib import Path

    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE, UNSURE

    rng = np.random.default_rng(5)
    x = np.arange(120.0)
    amp = np.full((160, 1), 150.0)
    amp[100:110] = 20.0
    img = 30.0 + rng.normal(0, 2.0, (160, 120)) + amp * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)
    img[40:60] = (30.0 + rng.normal(0, 2.0, (20, 120)) + 210.0 * np.exp(-0.5 * ((x - 50.0) / 12.0) ** 2)
                  + 80.0 * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2))
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img)
    assert ext.visible[40:60].all() and rs.dim_rows(ext)[40:60].all()  # dim by height alone
    made = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img))
    for _, truth, states, _, _ in made[:pf.N_MOVED]:
        assert (states[40:60] == STRIPE).all() and (states[100:110] == UNSURE).all()


def test_a_moved_faint_stretch_under_the_visible_level_is_not_scored_even_where_the_reference_rule_sees_it(
        monkeypatch):
    """Rows 100-109 of a 150 DN stripe stand 9 DN up: under 6 of the frame's noise units (2 DN), so the extent does not
    call them visible, and under a fifth of the stripe's height. With the reference rule's noise unit at 1 DN (as on a
    frame of flat dark background) the rule sees them in the moved frames; they are left out all the same, as the
    references leave out such rows."""
    from pathlib import Path

    from bench.evaluate import outcomes
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE, UNSURE, referenced_states

    monkeypatch.setattr(outcomes, "reference_noise", lambda frame: 1.0)
    rng = np.random.default_rng(9)
    x = np.arange(120.0)
    amp = np.full((160, 1), 150.0)
    amp[100:110] = 9.0
    img = 30.0 + rng.normal(0, 2.0, (160, 120)) + amp * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    ext = sp.stripe_extents(img)
    assert not ext.visible[100:110].any() and ext.visible[:100].all()
    made = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img))
    for image, truth, states, _, _ in made[:pf.N_FULL]:
        assert np.isfinite(truth[100:110]).all()
        assert (referenced_states(image, truth)[100:110] == STRIPE).sum() >= 8  # the rule sees most of them ...
        assert (states[100:110] == UNSURE).all() and (states[:100] == STRIPE).sum() >= 95  # ... they are not scored


def _stripe_with_a_faint_stretch(rows=200, faint=(60, 140), faint_dn=4.0, seed=3) -> np.ndarray:
    """A 150 DN stripe at column 50 whose rows ``faint`` stand ``faint_dn`` up, under the visible level, uint8."""
    rng = np.random.default_rng(seed)
    x = np.arange(120.0)
    amp = np.full((rows, 1), 150.0)
    amp[faint[0]:faint[1]] = faint_dn
    img = 30.0 + rng.normal(0, 2.0, (rows, 120)) + amp * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)
    return np.clip(np.rint(img), 0, 255).astype(np.uint8)


def test_a_set_without_row_states_is_predicted_with_the_rows_far_from_the_stripe_scored_as_none():
    """A faint stretch (rows 60-139) between two bright ones: read as the shipped set's given states are, the rows it
    crosses are not scored; with ``fallback_rows`` (a set whose references have no ``state`` column, as ``real``
    then scores it) every row 15 or more from a scored stripe row has no stripe, in every frame, the photograph in
    place and the false-report frames included."""
    from pathlib import Path

    from bench.evaluate.outcomes import NO_STRIPE, STRIPE, UNSURE

    img = _stripe_with_a_faint_stretch()
    given = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img))
    fallback = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img, fallback_rows=True))
    assert len(given) == len(fallback) == 5
    for (_, t0, s0, _, _), (_, t1, s1, _, _) in zip(given, fallback):
        np.testing.assert_array_equal(t0, t1)  # the frames and their truth are the same ...
        assert (s0[60:140] == UNSURE).all()  # ... read as given, the faint stretch is not scored
        assert (s1 == STRIPE).sum() == (s0 == STRIPE).sum()  # the stripe rows are the same
        stripe = np.flatnonzero(s1 == STRIPE)
        far = np.min(np.abs(np.arange(200)[:, None] - stripe[None, :]), axis=1) >= 15 if stripe.size else None
        if far is not None:
            assert (s1[far] == NO_STRIPE).all() and (s1[~far & (s1 != STRIPE)] == UNSURE).all()
    assert (fallback[2][2][80:120] == NO_STRIPE).all()  # in place: the faint stretch's middle has no stripe


def test_collect_photos_reads_whether_a_set_s_references_give_row_states(tmp_path):
    import csv

    import imageio.v3 as iio

    img = _stripe_with_a_faint_stretch(rows=40, faint=(10, 20))
    for folder, header, cells in (("given", "row,col,state", lambda r: f"{r},50.0,stripe"),
                                  ("fallback", "row,col", lambda r: f"{r},50.0")):
        root = tmp_path / folder
        root.mkdir()
        iio.imwrite(root / "a.png", img)
        (root / "a_ref.csv").write_text("\n".join([header] + [cells(r) for r in range(40)]) + "\n")
        with open(root / "manifest.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerows([["name", "has_background", "laser_colour"], ["a", 0, "red"]])
        photos = pf.collect_photos(root)
        assert [p.fallback_rows for p in photos] == [folder == "fallback"]
        assert pf.collect_photos(root, downscale=2)[0].fallback_rows == (folder == "fallback")
    iio.imwrite(tmp_path / "loose.png", img)  # a folder of photographs without references: as given
    assert [p.fallback_rows for p in pf.collect_photos(tmp_path) if p.name == "loose"] == [False]


def test_where_the_colour_shows_no_stripe_the_frame_s_guide_on_a_white_bar_is_dropped():
    """A red stripe in rows 0-99 and none in rows 100-159, and a white bar (bright in every channel, of no colour)
    down the whole frame: the colour guide has the stripe in rows 0-99 and nothing below; the frame's own guide takes
    the bar below. The guide keeps the stripe and drops the bar's rows, whose laser evidence is under
    EVIDENCE_SHARE of the stripe's."""
    from pathlib import Path

    from bench.evaluate import conditions as cnd
    from bench.evaluate import transplant as tp
    from bench.evaluate.pixels import select_channel

    rng = np.random.default_rng(8)
    x = np.arange(160.0)
    rgb = np.full((160, 160, 3), 60.0) + rng.normal(0, 2.0, (160, 160, 3))
    rgb[:100, :, 0] += 150.0 * np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)  # the stripe, red
    rgb += (230.0 * np.exp(-0.5 * ((x - 110.0) / 1.2) ** 2))[None, :, None]  # the bar, white and clipped
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    frame = select_channel(rgb, "auto", "red")
    own = sp.estimate_guide(frame)
    assert np.nanmedian(np.abs(own[110:150] - 110.0)) <= 1  # the frame's own guide takes the bar below
    photo = pf.Photo("p", Path("p.png"), frame, None, rgb, "red")
    guide = pf.colour_guide(photo, rgb, None, cnd.measure(frame))
    assert np.nanmax(np.abs(guide[5:95] - 50.0)) <= 1  # the stripe kept
    assert np.isnan(guide[110:150]).all()  # the bar's rows dropped


def test_where_the_stripe_turns_white_the_colour_s_guide_does_not_wander_onto_a_red_print():
    """A red stripe down the frame that turns white on a white patch in rows 60-99 (clipped in every channel, of no
    colour), and a thin red print line, coloured but no brighter than its row, at column 120 in those rows: the colour's
    guide takes the print there, the frame's own guide the white stripe. Neither has laser evidence (bright *and* of
    the laser's colour) there, so neither guides those rows; the white stretch, between visible rows, still moves with
    the stripe and is not scored."""
    from pathlib import Path

    from bench.evaluate import conditions as cnd
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE
    from bench.evaluate.pixels import select_channel

    rng = np.random.default_rng(12)
    x = np.arange(160.0)
    rgb = np.full((160, 160, 3), 60.0) + rng.normal(0, 2.0, (160, 160, 3))
    line = np.exp(-0.5 * ((x - 50.0) / 1.2) ** 2)
    rgb[:, :, 0] += 150.0 * line  # the stripe, red
    rgb[60:100, :, :] += 130.0  # the white patch ...
    rgb[60:100, :, 1:] += (150.0 * line)[:, None]  # ... where the stripe is white, clipped in every channel
    rgb[60:100, 119:122, 1:] -= 40.0  # the red print: coloured, no brighter than its row in the red channel
    rgb = np.clip(np.rint(rgb), 0, 255).astype(np.uint8)
    frame = select_channel(rgb, "auto", "red")
    excess = select_channel(rgb, "excess", "red")
    assert np.nanmedian(np.abs(sp.estimate_guide(excess)[65:95] - 120.0)) <= 1  # the colour's guide takes the print
    assert np.nanmedian(np.abs(sp.estimate_guide(frame)[65:95] - 50.0)) <= 1  # the frame's own, the white stripe
    photo = pf.Photo("p", Path("p.png"), frame, None, rgb, "red")
    guide = pf.colour_guide(photo, rgb, None, cnd.measure(frame))
    assert np.nanmax(np.abs(guide[np.r_[5:55, 105:155]] - 50.0)) <= 1  # the red stripe kept
    assert np.isnan(guide[65:95]).all()  # neither the print nor the white stretch guides
    for image, truth, states, _, shift in pf.transplant_frames(photo)[:pf.N_MOVED]:
        assert not (states[65:95] == STRIPE).any()  # not scored ...
        assert image[65:95, 50].max() < image[65:95, 50 + shift].min()  # ... but moved with the stripe


def test_rows_where_a_moved_stripe_lands_on_a_rival_are_not_scored():
    """A stripe with a bright block 12-60 px right of it in rows 30-49: every shift to the right lands the stripe on the
    block there, where the photograph's stripe stands beside it, so those rows of the frame moved right are not scored;
    the frame moved left scores them."""
    from pathlib import Path

    from bench.evaluate.outcomes import STRIPE, UNSURE

    rng = np.random.default_rng(11)
    x = np.arange(160.0)
    img = 30.0 + rng.normal(0, 2.0, (120, 160)) + 120.0 * np.exp(-0.5 * ((x - 60.0) / 2.5) ** 2)
    img[30:50, 75:121] += 140.0  # as high over the row as the stripe: a rival; the estimate keeps to the stripe
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    made = pf.transplant_frames(pf.Photo("p", Path("p.png"), img, None, img))
    (_, _, right, _, s_right), (_, _, left, _, s_left), (_, _, here, _, s_here) = made[:pf.N_FULL]
    assert s_right > 0 > s_left and s_here == 0
    assert (here[30:50] == STRIPE).all()  # in place the stripe is where it stands beside the block
    assert (right[30:50] == UNSURE).all() and (right[60:100] == STRIPE).all()
    assert (left[30:50] == STRIPE).all()
