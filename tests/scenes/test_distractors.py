"""Distractors in rendered frames (scenes.distractors, the `distractor` scene parameter)."""

import numpy as np
import pytest

import scenes
from scenes import distractors as D
from scenes.render_key import cache_fields

KINDS = D.DISTRACTORS[1:]


@pytest.mark.parametrize("kind", KINDS)
def test_each_distractor_is_seeded_and_leaves_stripeless_rows(kind):
    a, b, c = D.build(kind, 4, (120, 128)), D.build(kind, 4, (120, 128)), D.build(kind, 5, (120, 128))
    np.testing.assert_array_equal(a.light_dn, b.light_dn)
    np.testing.assert_array_equal(a.cut, b.cut)
    assert a.light_dn.shape == (120, 128, 3) and a.hide.shape == (120, 128) and a.cut.shape == (120,)
    differs = not np.array_equal(a.cut, c.cut) or not np.array_equal(a.light_dn, c.light_dn) or any(
        not np.array_equal(m1, m2) for (m1, _), (m2, _) in zip(a.drawn, c.drawn))
    assert differs
    truth = np.full(120, 64.0)  # a stripe down the middle of every row
    gone = a.stripe_less(truth)
    assert 0.3 * 120 - 1 <= a.cut.sum() <= 0.55 * 120 and (a.cut[0] or a.cut[-1]) and gone[a.cut].all()
    rows = np.nonzero(a.cut)[0]
    if kind == "overlay":  # the drawn frame's bars hide the stripe
        bars = a.drawn[0][0][:, 64]
        assert bars.any() and gone[bars].all()
    elif kind != "short":  # the distractor stands (mostly) in the rows without the stripe
        assert a.light_dn[rows].max() > 30


def test_no_distractor_changes_nothing():
    assert D.build("none", 0, (4, 5)) is None and D.for_scene(scenes.make("cone").params) is None
    laser, ambient, img = np.ones((4, 5), np.float32), np.zeros((4, 5), np.float32), np.zeros((4, 5), np.uint8)
    out = D.apply(None, laser, ambient, np.array([1.0]))
    assert out[0] is laser and out[1] is ambient and D.draw(None, img) is img
    truth = object()
    assert D.truth_without(truth, None) is truth
    with pytest.raises(ValueError, match="`distractor` must be one of"):
        scenes.make("cone", distractor="ghost")


def test_the_distractor_is_not_in_the_render_cache_key():
    # applied after the cache: every distractor reuses the scene's cached renders, and the paper run's keys
    # (distractor "none") are what they were
    base = scenes.make("sphere", width=64, height=60, spp=2)
    want = cache_fields("sphere", base.params, base.rig, 1.5, 2, 0, "llvm_ad_mono")
    for kind in KINDS:
        s = scenes.make("sphere", width=64, height=60, spp=2, distractor=kind)
        assert cache_fields("sphere", s.params, s.rig, 1.5, 2, 0, "llvm_ad_mono") == want
    assert "distractor" not in str(want)


def test_apply_cuts_the_laser_and_hides_the_scene():
    d = D.build("sphere", 2, (60, 64))
    laser = np.ones((60, 64), np.float32)
    ambient = np.full((60, 64), 0.5, np.float32)
    lz, am = D.apply(d, laser, ambient, np.array([0.01]))
    assert (lz[d.cut] == 0).all() and (lz[d.hide] == 0).all() and (lz[~d.cut[:, None] & ~d.hide] == 1).all()
    np.testing.assert_allclose(am[d.hide], 0.01 * d.light_dn[..., 0][d.hide], rtol=1e-6)
    rgb = D.apply(d, np.ones((60, 64, 3), np.float32), np.zeros((60, 64, 3), np.float32), np.array([1.0, 2.0, 3.0]))[1]
    np.testing.assert_allclose(rgb[..., 2], 3.0 * d.light_dn[..., 2], rtol=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("camera", ["mono", "rgb"])
def test_each_family_renders_with_truth_that_has_its_stripeless_rows(camera):
    kw = dict(width=64, height=60, spp=2, ambient_spp=2, seed=3, camera=camera)
    f0 = scenes.make("sphere", **kw).render(0.0)
    none0 = np.isnan(f0.truth.columns)
    assert none0.mean() < 0.2  # the sphere before the wall: a stripe on nearly every row
    for kind in KINDS:
        s = scenes.make("sphere", distractor=kind, **kw)
        f = s.render(0.0)
        none = np.isnan(f.truth.columns)
        d = D.for_scene(s.params)
        assert none.sum() > none0.sum() + 2, kind
        np.testing.assert_array_equal(none, none0 | d.stripe_less(f0.truth.columns))
        assert np.isnan(f.truth.points_cm[none]).all() and not f.truth.on_object[none].any()
        img = f.rgb if camera == "rgb" else f.image
        assert not np.array_equal(img, f0.rgb if camera == "rgb" else f0.image), kind
        if kind == "overlay":  # drawn on the recording: the same grey in both frames
            mask, grey = d.drawn[0]
            bg = f.rgb_background if camera == "rgb" else f.background
            assert (img[mask] == round(grey)).all() and (bg[mask] == round(grey)).all()
        elif kind != "short":  # light in the rows without the stripe, present with the laser off too
            cut = d.cut
            lit = f.background[cut].astype(float) - f0.background[cut].astype(float)
            assert lit.max() > 20, kind
    # "none" is the frame as rendered
    f1 = scenes.make("sphere", distractor="none", **kw).render(0.0)
    np.testing.assert_array_equal(f1.image, f0.image)
    np.testing.assert_array_equal(f1.truth.columns, f0.truth.columns)
