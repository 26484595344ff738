"""The none-row check: a sign of the stripe in a row marked stripe-less is found; clutter that is not one is not."""

import numpy as np
import pytest

from bench.evaluate.nonerows import REASONS, NoneRowCheck, doubtful_rows, path_guess, stripe_profile


def _frame(seed=0, H=200, W=160, noise=2.0):
    """A bright stripe down rows 0-79 near column 60 (slanting right), stripe-less rows 80-199."""
    rng = np.random.default_rng(seed)
    img = rng.normal(40.0, noise, (H, W))
    cols = np.full(H, np.nan)
    for r in range(80):
        c = 60.0 + 0.1 * r
        x = np.arange(W)
        img[r] += 80.0 * np.exp(-0.5 * ((x - c) / 1.0) ** 2)
        cols[r] = c
    states = np.r_[np.full(80, 1), np.full(H - 80, 0)].astype(np.int8)
    return img, cols, states


def _add_line(img, rows, col0, slope, height, sigma=1.0):
    x = np.arange(img.shape[1])
    for r in rows:
        img[r] += height * np.exp(-0.5 * ((x - (col0 + slope * (r - rows[0]))) / sigma) ** 2)


def test_clean_stripe_less_rows_pass():
    img, cols, states = _frame()
    flags = doubtful_rows(img, cols, states)
    assert set(flags) == set(REASONS)
    assert not any(v.any() for v in flags.values())


def test_a_planted_faint_continuation_of_the_stripe_is_refused():
    img, cols, states = _frame()
    # the stripe carries on down rows 80-199 at 5 DN (2.5 noise units: hard to see in one row), along its own path
    _add_line(img, range(80, 200), 68.0, 0.1, 5.0)
    flags = doubtful_rows(img, cols, states)
    assert flags["continuation"][80:].mean() > 0.8
    # the same faint line far from the stripe's path is no continuation (and too faint for a reflection)
    img2, cols2, states2 = _frame()
    _add_line(img2, range(80, 200), 140.0, 0.0, 5.0)
    assert not doubtful_rows(img2, cols2, states2)["continuation"].any()


def test_a_reflection_as_narrow_as_the_stripe_is_refused_and_a_step_edge_or_a_wide_glow_is_not():
    img, cols, states = _frame()
    _add_line(img, range(120, 140), 130.0, 0.0, 30.0)            # a narrow highlight, 3/8 of the stripe's height
    img[150:170, 100:] += 60.0                                     # a lit door edge: a step
    x = np.arange(img.shape[1])
    img[175:195] += 60.0 * np.exp(-0.5 * ((x - 120.0) / 15.0) ** 2)  # a wide glow
    flags = doubtful_rows(img, cols, states)
    assert flags["reflection"][120:140].all()
    assert not flags["reflection"][140:200].any()


def test_a_laser_coloured_ridge_is_refused_on_a_colour_photograph_only():
    img, cols, states = _frame()
    colour = np.zeros_like(img)
    colour[:80] = np.clip(img[:80] - 40.0, 0, None)                 # the stripe is laser-coloured
    _add_line(colour, range(100, 110), 20.0, 0.0, 20.0)              # a red mark in rows 100-109, grey in the frame
    flags = doubtful_rows(img, cols, states, colour=colour)
    assert flags["laser_colour"][100:110].all() and flags["laser_colour"].sum() == 10
    assert not doubtful_rows(img, cols, states)["laser_colour"].any()


def test_only_none_rows_are_judged_and_bad_shapes_are_refused():
    img, cols, states = _frame()
    _add_line(img, range(100, 200), 70.0, 0.1, 3.0)
    states[80:] = -1                                                  # unknown rows: nothing to verify
    assert not any(v.any() for v in doubtful_rows(img, cols, states).values())
    with pytest.raises(ValueError):
        doubtful_rows(img, cols[:-1], states)
    with pytest.raises(ValueError):
        doubtful_rows(img, cols, states, colour=np.zeros((3, 3)))
    with pytest.raises(ValueError):
        NoneRowCheck(faint_rows=4)


def test_the_stripe_profile_and_the_carried_path():
    img, cols, states = _frame(noise=0.01)
    h, w = stripe_profile(img, cols)
    assert h == pytest.approx(80.0 * 0.99, rel=0.05) and 2.0 <= w <= 3.0
    c, reach = path_guess(cols)
    assert c[150] == pytest.approx(60.0 + 0.1 * 150, abs=0.5)       # the fitted line carried on
    assert reach[79] == 6.0 and reach[150] > reach[90]


def test_with_a_laser_off_frame_only_the_laser_s_light_counts():
    img, cols, states = _frame()
    off = np.random.default_rng(5).normal(40.0, 2.0, img.shape)
    _add_line(img, range(120, 140), 130.0, 0.0, 30.0)              # a lamp's narrow stem, lit with the laser off too
    _add_line(off, range(120, 140), 130.0, 0.0, 30.0)
    assert doubtful_rows(img, cols, states)["reflection"][120:140].all()
    flags = doubtful_rows(img, cols, states, background=off)
    assert not any(v.any() for v in flags.values())
    _add_line(img, range(150, 160), 100.0, 0.0, 30.0)              # a glint of the laser: only in the laser-on frame
    assert doubtful_rows(img, cols, states, background=off)["reflection"][150:160].all()
    with pytest.raises(ValueError):
        doubtful_rows(img, cols, states, background=off[:-1])
