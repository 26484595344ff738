"""Conformance suite for trackers, in the manner of scikit-learn's ``check_estimator``.

Third-party authors run every check on their tracker::

    from trackers.testing import check_tracker
    check_tracker(MyTracker())

or, with pytest, one test per check::

    from trackers.testing import parametrize_with_checks

    @parametrize_with_checks([MyTracker(), MyTracker(param=2)])
    def test_conformance(tracker, check):
        check(tracker)

Each check raises ``AssertionError`` with a message naming the tracker and
what failed. The synthetic data are generated from fixed seeds.
"""

from __future__ import annotations

import copy
from functools import partial
from typing import Callable, Iterator

import numpy as np
from scipy.special import erf

from ._base import Track, Tracker

__all__ = ["check_tracker", "parametrize_with_checks", "all_checks", "make_stripe_image", "make_ambient_pair",
           "make_score_image", "stripe_profile", "check_background_use", "check_parameter_constraints",
           "check_score_meaning", "check_colour_use", "check_pixel_range", "check_border_stripe", "PIXEL_RANGES"]


def stripe_profile(centre, width: int, sigma_px: float, peak: float) -> np.ndarray:
    """A Gaussian line profile integrated over each pixel's width, one row per centre.

    Pixel ``j`` spans columns ``j - 0.5 .. j + 0.5``; the continuous profile
    peaks at ``peak`` (image units) at ``centre[r]``.

    Parameters
    ----------
    centre : array_like, shape (H,)
        The stripe's centre in each row (pixel-centre convention, px).
    width : int
        Columns.
    sigma_px, peak : float
        Standard deviation (px) and peak height of the profile.

    Returns
    -------
    ndarray of float64, shape (H, width)

    Examples
    --------
    >>> p = stripe_profile([4.0], 9, 1.0, 10.0)  # the whole profile: sum = peak * sqrt(2 pi) * sigma
    >>> int(np.argmax(p[0])), round(float(p[0].sum()), 3), round(float(10.0 * np.sqrt(2 * np.pi)), 3)
    (4, 25.066, 25.066)
    """
    centre = np.asarray(centre, dtype=np.float64)
    edges = np.arange(width + 1) - 0.5
    z = (edges[None, :] - centre[:, None]) / (np.sqrt(2.0) * sigma_px)
    return peak * np.sqrt(2.0 * np.pi) * sigma_px * 0.5 * np.diff(erf(z), axis=1)


def make_stripe_image(
    height: int = 96,
    width: int = 128,
    *,
    sigma_px: float = 1.5,
    peak: float = 180.0,
    background: float = 10.0,
    noise: float = 2.0,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """A synthetic 8-bit frame with one Gaussian stripe, and its true columns.

    The stripe's centre wanders smoothly (a sine plus a random sub-pixel
    phase per frame); each pixel holds the Gaussian line profile integrated
    over the pixel's width (pixel j spans columns j - 0.5 .. j + 0.5), plus a
    constant background and Gaussian noise, rounded and clipped to 0..255.

    Returns
    -------
    image : ndarray of uint8, shape (height, width)
    columns : ndarray of float64, shape (height,)
        True stripe centre per row (pixel-centre convention).
    """
    rng = np.random.default_rng(seed)
    rows = np.arange(height)
    centre = width / 2 + 0.15 * width * np.sin(2 * np.pi * rows / height + rng.uniform(0, 2 * np.pi))
    centre = centre + rng.uniform(-0.5, 0.5)
    img = background + stripe_profile(centre, width, sigma_px, peak) + rng.normal(0.0, noise, (height, width))
    return np.clip(np.rint(img), 0, 255).astype(np.uint8), centre


def _name(tracker: Tracker) -> str:
    return f"{type(tracker).__name__} ({tracker.name!r})"


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return np.array_equal(a, b, equal_nan=True)


def _accuracy(tracker: Tracker, tracks) -> tuple[int, int, float, float]:
    """Over ``tracks``, (columns, truth) pairs of frames with a clear stripe: the rows reported, the
    rows in all, the mean absolute error of the reported rows (px) and the limit it must keep (0.1 px
    for a sub-pixel tracker, 0.6 px for the others)."""
    errors = []
    reported = total = 0
    for cols, truth in tracks:
        ok = ~np.isnan(cols)
        reported += int(ok.sum())
        total += cols.size
        errors.append(np.abs(cols[ok] - truth[ok]))
    err = np.concatenate(errors)
    return reported, total, float(err.mean()), 0.1 if tracker.subpixel else 0.6


def check_output_types(tracker: Tracker) -> None:
    """`track` returns a Track with float64 (H,) columns and score, NaN together,
    columns inside the image."""
    img, _ = make_stripe_image(seed=1)
    out = tracker.track(img)
    assert isinstance(out, Track), f"{_name(tracker)}.track returned {type(out).__name__}, not Track"
    for field in ("columns", "score"):
        arr = getattr(out, field)
        assert arr.dtype == np.float64, f"{_name(tracker)}: {field} has dtype {arr.dtype}, not float64"
        assert arr.shape == (img.shape[0],), f"{_name(tracker)}: {field} has shape {arr.shape}, not {(img.shape[0],)}"
    assert _same(np.isnan(out.columns), np.isnan(out.score)), f"{_name(tracker)}: score NaN where columns is not"
    cols = out.columns[~np.isnan(out.columns)]
    assert cols.size > 0, f"{_name(tracker)} found no stripe in a clear synthetic frame"
    assert np.all((cols >= -0.5) & (cols <= img.shape[1] - 0.5)), (
        f"{_name(tracker)}: columns outside the image [{cols.min()}, {cols.max()}]"
    )


def check_blank_image(tracker: Tracker) -> None:
    """A blank frame (all zeros, or constant) gives all-NaN without an exception."""
    for value in (0, 37):
        for dtype in (np.uint8, np.float64):
            img = np.full((40, 50), value, dtype=dtype)
            out = tracker.track(img)
            assert np.all(np.isnan(out.columns)), (
                f"{_name(tracker)} reported a stripe in a constant {dtype.__name__} frame of value {value}"
            )


def check_bad_input(tracker: Tracker) -> None:
    """3-D, empty, non-numeric and non-finite images and a background of
    another shape raise ValueError naming the argument."""
    good = make_stripe_image(height=20, width=30, seed=2)[0]
    nan_img = good.astype(np.float64)
    nan_img[3, 4] = np.nan
    inf_img = good.astype(np.float64)
    inf_img[0, 0] = np.inf
    cases = [
        ("3-D image", np.zeros((3, 4, 5)), None, "image"),
        ("1-D image", np.zeros(5), None, "image"),
        ("empty image", np.zeros((0, 10)), None, "image"),
        ("string image", np.array([["a", "b"], ["c", "d"]]), None, "image"),
        ("complex image", np.ones((4, 4), dtype=complex), None, "image"),
        ("object image", np.array([[object(), object()]]), None, "image"),
        ("NaN image", nan_img, None, "image"),
        ("infinite image", inf_img, None, "image"),
        ("background of another shape", good, np.zeros((5, 5)), "background"),
        ("3-D background", good, np.zeros(good.shape + (2,)), "background"),
        ("NaN background", good, np.full(good.shape, np.nan), "background"),
    ]
    for what, img, bg, arg in cases:
        try:
            tracker.track(img, background=bg)
        except ValueError as exc:
            assert f"`{arg}`" in str(exc), f"{_name(tracker)}: the error for a {what} does not name `{arg}`: {exc}"
        else:
            raise AssertionError(f"{_name(tracker)} accepted a {what}")


def check_dtype_invariance(tracker: Tracker) -> None:
    """uint8 and float64 copies of one frame give the same columns."""
    img, _ = make_stripe_image(seed=3)
    a = tracker.track(img).columns
    b = tracker.track(img.astype(np.float64)).columns
    assert _same(a, b), f"{_name(tracker)}: uint8 and float64 copies of a frame give different columns"


#: The copies of a clear 8-bit frame :func:`check_pixel_range` tracks: other cameras' and pipelines' units.
PIXEL_RANGES = (
    ("16-bit (x 257)", lambda a: a.astype(np.uint16) * np.uint16(257)),
    ("float minus 300", lambda a: a.astype(np.float64) - 300.0),
    ("float times 1e300", lambda a: a.astype(np.float64) * 1e300),
    ("float times 1e-300", lambda a: a.astype(np.float64) * 1e-300),
)


def check_pixel_range(tracker: Tracker) -> None:
    """The same clear stripe in other pixel units (:data:`PIXEL_RANGES`: 16-bit, shifted below zero,
    scaled to near the largest and the smallest normal floats) is found as
    :func:`check_synthetic_accuracy` asks of the 8-bit frame: at least 95 % of the rows, within the
    tracker's accuracy limit. Scale and offset of the pixel values carry no information about where the
    stripe is."""
    img, truth = make_stripe_image(seed=3)
    for what, convert in PIXEL_RANGES:
        cols = tracker.track(convert(img)).columns
        reported = int(np.count_nonzero(~np.isnan(cols)))
        assert reported >= 0.95 * cols.size, (f"{_name(tracker)} reported only {reported} of {cols.size} rows of a "
                                              f"clear stripe in a {what} frame")
        _, _, mae, limit = _accuracy(tracker, [(cols, truth)])
        assert mae <= limit, f"{_name(tracker)}: mean absolute error {mae:.3f} px > {limit} px in a {what} frame"


def check_border_stripe(tracker: Tracker) -> None:
    """A clear stripe centred on the first column, and one on the last, is found in at least 95 % of the
    rows, each within 1 px (half of it lies outside the frame)."""
    H, W = 60, 80
    rng = np.random.default_rng(11)
    for centre in (0.0, W - 1.0):
        img = 10.0 + stripe_profile(np.full(H, centre), W, 1.5, 180.0) + rng.normal(0.0, 2.0, (H, W))
        cols = tracker.track(np.clip(np.rint(img), 0, 255).astype(np.uint8)).columns
        ok = ~np.isnan(cols)
        where = "first" if centre == 0 else "last"
        assert ok.sum() >= 0.95 * H, (f"{_name(tracker)} reported only {int(ok.sum())} of {H} rows of a stripe "
                                      f"on the {where} column")
        worst = float(np.max(np.abs(cols[ok] - centre)))
        assert worst <= 1.0, f"{_name(tracker)}: a stripe on the {where} column tracked {worst:.2f} px off"


def check_readonly_input(tracker: Tracker) -> None:
    """Read-only inputs work and are not modified."""
    img, _ = make_stripe_image(seed=4)
    bg = np.full_like(img, 10)
    for arr in (img, bg):
        arr.flags.writeable = False
    keep_img, keep_bg = img.copy(), bg.copy()
    tracker.track(img, background=bg)
    flt = img.astype(np.float64)
    flt.flags.writeable = False
    tracker.track(flt)
    assert np.array_equal(img, keep_img) and np.array_equal(bg, keep_bg), f"{_name(tracker)} modified its input"


def _equal(a, b) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.dtype == b.dtype and _same(a, b)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    try:
        return bool(a == b) or (a != a and b != b)
    except Exception:  # objects without a usable ==
        return a is b


def check_no_state_change(tracker: Tracker) -> None:
    """`track` leaves the tracker unchanged and is deterministic."""
    img, _ = make_stripe_image(seed=5)
    before = copy.deepcopy(vars(tracker))
    params = copy.deepcopy(tracker.get_params())
    first = tracker.track(img)
    second = tracker.track(img)
    assert _equal(vars(tracker), before), f"{_name(tracker)}: track() changed the tracker's state"
    assert repr(tracker.get_params()) == repr(params), f"{_name(tracker)}: track() changed get_params()"
    assert _same(first.columns, second.columns) and _same(first.score, second.score), (
        f"{_name(tracker)} is not deterministic"
    )


def check_get_params(tracker: Tracker) -> None:
    """`get_params` returns the constructor's parameters; a tracker rebuilt
    from them tracks the same; the tracker has a registered-style name."""
    assert isinstance(tracker.name, str) and tracker.name, f"{type(tracker).__name__} has no `name`"
    params = tracker.get_params()
    assert isinstance(params, dict), f"{_name(tracker)}: get_params() returned {type(params).__name__}"
    clone = type(tracker)(**params)
    img, _ = make_stripe_image(seed=6)
    assert _same(clone.track(img).columns, tracker.track(img).columns), (
        f"{_name(tracker)}: a tracker rebuilt from get_params() tracks differently"
    )


def check_synthetic_accuracy(tracker: Tracker) -> None:
    """On synthetic Gaussian stripes with noise: mean absolute error within
    0.1 px for sub-pixel trackers, 0.6 px for the others; at least 95 % of
    the rows reported."""
    images = (make_stripe_image(seed=100 + seed) for seed in range(4))
    reported, total, mae, limit = _accuracy(tracker, ((tracker.track(img).columns, truth) for img, truth in images))
    assert reported >= 0.95 * total, f"{_name(tracker)} reported only {reported} of {total} rows of a clear stripe"
    assert mae <= limit, f"{_name(tracker)}: mean absolute error {mae:.3f} px > {limit} px on synthetic stripes"


def check_vertical_flip(tracker: Tracker) -> None:
    """Flipping the frame upside down flips the result."""
    img, _ = make_stripe_image(seed=7)
    a = tracker.track(img).columns
    b = tracker.track(img[::-1]).columns
    assert np.allclose(a[::-1], b, rtol=0, atol=1e-9, equal_nan=True), (
        f"{_name(tracker)}: the track of the flipped frame is not the flipped track"
    )


def make_score_image(height: int = 120, width: int = 128, *, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A synthetic 8-bit frame for the score contract, and its true columns.

    The stripe is bright (peak 180 DN) in the top third of the rows, faint (peak
    45 DN) in the middle third and absent in the bottom third (truth NaN), on a
    10 DN background with 2 DN of Gaussian noise.

    Examples
    --------
    >>> img, truth = make_score_image()
    >>> img.shape, int(np.isnan(truth).sum())
    ((120, 128), 40)
    """
    rng = np.random.default_rng(seed)
    rows = np.arange(height)
    centre = width / 2 + 0.1 * width * np.sin(2 * np.pi * rows / height) + rng.uniform(-0.5, 0.5)
    peak = np.where(rows < height // 3, 180.0, 45.0)
    present = rows < 2 * (height // 3)
    prof = stripe_profile(centre, width, 1.5, 1.0) * (peak * present)[:, None]
    img = 10.0 + prof + rng.normal(0.0, 2.0, (height, width))
    return np.clip(np.rint(img), 0, 255).astype(np.uint8), np.where(present, centre, np.nan)


def check_score_meaning(tracker: Tracker) -> None:
    """The score contract: finite wherever a column is reported, higher is more
    confident. On :func:`make_score_image` (bright, faint and no stripe), unless
    every report has the same score (allowed: a single operating point), the
    median score of the reported bright rows exceeds that of the reported faint
    rows, and a reported stripe row outscores a reported stripe-less row in at
    least 90 % of such pairs (the ranking average precision is built on)."""
    img, truth = make_score_image(seed=3)
    out = tracker.track(img)
    rep = ~np.isnan(out.columns)
    assert np.all(np.isfinite(out.score[rep])), f"{_name(tracker)}: a reported row has a non-finite score"
    if not rep.any() or np.ptp(out.score[rep]) == 0:
        return
    H = img.shape[0]
    rows = np.arange(H)
    bright = rep & (rows < H // 3)
    faint = rep & (rows >= H // 3) & (rows < 2 * (H // 3))
    if bright.sum() >= 5 and faint.sum() >= 5:
        sb, sf = float(np.median(out.score[bright])), float(np.median(out.score[faint]))
        assert sb > sf, (f"{_name(tracker)}: the median score of bright stripe rows ({sb:.4g}) is not above that of "
                         f"faint ones ({sf:.4g}); higher must mean more confident")
    empty = rep & np.isnan(truth)
    stripe = rep & ~np.isnan(truth)
    if empty.any() and stripe.any():
        a, b = out.score[stripe], out.score[empty]
        auc = float(np.mean(a[:, None] > b[None, :]) + 0.5 * np.mean(a[:, None] == b[None, :]))
        assert auc >= 0.9, (f"{_name(tracker)}: a reported stripe row outscores a reported stripe-less row in only "
                            f"{auc:.0%} of pairs")


def check_parameter_constraints(tracker: Tracker) -> None:
    """Every parameter has a constraint in ``parameter_constraints``, the tracker's own
    values satisfy it, and each value the constraint calls invalid is refused by
    :meth:`~trackers.Tracker.track` with a ``ValueError`` naming the parameter (for
    trackers that declare constraints)."""
    table = type(tracker).parameter_constraints
    params = tracker.get_params()
    missing = sorted(set(params) - set(table))
    assert not missing, f"{_name(tracker)}: parameter(s) {missing} have no entry in parameter_constraints"
    extra = sorted(set(table) - set(params))
    assert not extra, f"{_name(tracker)}: parameter_constraints names {extra}, which are not parameters"
    img, _ = make_stripe_image(20, 30, seed=3)
    tracker.track(img)  # its own values pass
    for name, constraint in table.items():
        for bad in constraint.invalid():
            t = copy.deepcopy(tracker)
            setattr(t, name, bad)
            try:
                t.track(img)
            except ValueError as exc:
                assert f"`{name}`" in str(exc), (
                    f"{_name(tracker)}: {name}={bad!r} was refused, but the message does not name `{name}`: {exc}")
            else:
                raise AssertionError(f"{_name(tracker)}: {name}={bad!r} violates its constraint but was accepted")


def make_ambient_pair(
    height: int = 96, width: int = 128, *, peak: float = 120.0, ambient: float = 230.0, noise: float = 2.0, seed: int = 0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A laser-on / laser-off pair of 8-bit frames with an ambient distractor, and the true columns.

    Both frames hold the same ambient light: a constant level of 10, a
    bright vertical bar (Gaussian, sigma 2 px, ``ambient`` above the level,
    at 12 % of the width, brighter than the stripe) and a bright blob
    (``ambient`` high, radius about 6 px, at 85 % of the width); each frame
    has its own Gaussian noise. Only the laser-on frame holds the stripe of
    :func:`make_stripe_image` (peak ``peak``, sigma 1.5 px; same seed, same
    columns), between 35 % and 65 % of the width.

    Returns
    -------
    image, background : ndarray of uint8, shape (height, width)
        Laser-on and laser-off frames (0..255, rounded and clipped).
    columns : ndarray of float64, shape (height,)
        True stripe centre per row (pixel-centre convention, px).

    Examples
    --------
    >>> on, off, truth = make_ambient_pair(seed=1)
    >>> bool(on.max(axis=1).mean() > 200), int(np.argmax(on[0])) < 0.2 * on.shape[1]  # the bar is the brightest
    (True, True)
    """
    rng = np.random.default_rng(seed)
    _, truth = make_stripe_image(height, width, noise=0.0, seed=seed)
    jj = np.arange(width)[None, :]
    rr = np.arange(height)[:, None]
    amb = 10.0 + ambient * np.exp(-0.5 * ((jj - 0.12 * width) / 2.0) ** 2)
    amb = amb + ambient * np.exp(-0.5 * ((jj - 0.85 * width) ** 2 + (rr - 0.5 * height) ** 2) / 6.0 ** 2)
    stripe = stripe_profile(truth, width, 1.5, peak)
    on = amb + stripe + rng.normal(0.0, noise, (height, width))
    off = amb + rng.normal(0.0, noise, (height, width))
    to8 = lambda a: np.clip(np.rint(a), 0, 255).astype(np.uint8)  # noqa: E731
    return to8(on), to8(off), truth


def check_background_use(tracker: Tracker) -> None:
    """With a laser-off frame (trackers whose ``uses_background`` is True):
    an ambient bar and blob brighter than the stripe, present in both
    frames, are not tracked (at least 95 % of the rows reported, mean
    absolute error within the synthetic-accuracy limit); a laser-off frame
    equal to the laser-on frame gives all-NaN; uint8 and float64 copies of
    the pair give the same columns; flipping both frames flips the result."""
    pairs = (make_ambient_pair(seed=200 + seed) for seed in range(3))
    reported, total, mae, limit = _accuracy(
        tracker, ((tracker.track(on, background=off).columns, truth) for on, off, truth in pairs))
    assert reported >= 0.95 * total, (
        f"{_name(tracker)} reported only {reported} of {total} rows of a clear stripe given its laser-off frame"
    )
    assert mae <= limit, (
        f"{_name(tracker)}: mean absolute error {mae:.3f} px > {limit} px given the laser-off frame "
        "(an ambient distractor present in both frames was tracked?)"
    )
    on, off, _ = make_ambient_pair(seed=210)
    same = tracker.track(on, background=on).columns
    assert np.all(np.isnan(same)), f"{_name(tracker)} reported a stripe with a laser-off frame equal to the image"
    a = tracker.track(on, background=off).columns
    b = tracker.track(on.astype(np.float64), background=off.astype(np.float64)).columns
    assert _same(a, b), f"{_name(tracker)}: uint8 and float64 copies of a frame pair give different columns"
    c = tracker.track(on[::-1], background=off[::-1]).columns
    assert np.allclose(a[::-1], c, rtol=0, atol=1e-9, equal_nan=True), (
        f"{_name(tracker)}: the track of the flipped frame pair is not the flipped track"
    )


def check_colour_use(tracker: Tracker) -> None:
    """With colour evidence (trackers whose ``uses_colour`` is True): evidence that carries no
    information (every pixel fully laser-coloured) changes nothing, with or without a laser-off frame;
    evidence of another shape is refused with a ``ValueError`` naming ``colour``; and the tracker's
    :meth:`~trackers.Tracker.find_stripe` takes the evidence as its third argument."""
    img, _ = make_stripe_image(seed=8)
    on, off, _ = make_ambient_pair(seed=9)
    full = np.ones(img.shape)
    a, b = tracker.track(img), tracker.track(img, colour=full)
    assert _same(a.columns, b.columns) and _same(a.score, b.score), (
        f"{_name(tracker)}: colour evidence that says every pixel has the laser's colour changed the track")
    a, b = tracker.track(on, background=off), tracker.track(on, background=off, colour=np.ones(on.shape))
    assert _same(a.columns, b.columns), (
        f"{_name(tracker)}: uninformative colour evidence changed the track of a frame pair")
    try:
        tracker.track(img, colour=np.ones((img.shape[0], img.shape[1] + 1)))
    except ValueError as exc:
        assert "`colour`" in str(exc), f"{_name(tracker)}: a bad `colour` was refused without naming it: {exc}"
    else:
        raise AssertionError(f"{_name(tracker)}: colour evidence of the wrong shape was accepted")


_CHECKS: tuple[Callable[[Tracker], None], ...] = (
    check_output_types,
    check_blank_image,
    check_bad_input,
    check_dtype_invariance,
    check_pixel_range,
    check_border_stripe,
    check_readonly_input,
    check_no_state_change,
    check_get_params,
    check_synthetic_accuracy,
    check_vertical_flip,
    check_score_meaning,
)


#: Checks that apply only to trackers with a property, chosen by it (scikit-learn's tags).
_TAGGED: tuple[tuple[Callable[[Tracker], bool], Callable[[Tracker], None]], ...] = (
    (lambda t: bool(getattr(t, "uses_background", False)), check_background_use),
    (lambda t: bool(getattr(t, "uses_colour", False)), check_colour_use),
    (lambda t: bool(type(t).parameter_constraints), check_parameter_constraints),
)


def all_checks() -> tuple[Callable[[Tracker], None], ...]:
    """Every conformance check, in the order they run (the tagged ones last)."""
    return _CHECKS + tuple(check for _, check in _TAGGED)


def _checks_for(tracker: Tracker) -> Iterator[Callable[[Tracker], None]]:
    """The checks for ``tracker``: every general one, then those its properties call for."""
    yield from _CHECKS
    for applies, check in _TAGGED:
        if applies(tracker):
            yield check


def check_tracker(tracker: Tracker) -> None:
    """Run every conformance check on ``tracker``; raise ``AssertionError`` at
    the first failure.

    Examples
    --------
    >>> import trackers
    >>> check_tracker(trackers.make("centroid"))
    """
    if not isinstance(tracker, Tracker):
        raise TypeError(f"`tracker` must be a trackers.Tracker instance, got {type(tracker).__name__}")
    for check in _checks_for(tracker):
        check(tracker)


def parametrize_with_checks(trackers_):
    """A ``pytest.mark.parametrize`` over (tracker, check) pairs.

    Parameters
    ----------
    trackers_ : iterable of Tracker
        Instances to check.

    Returns
    -------
    pytest mark decorator with arguments ``tracker`` and ``check``; the test
    ids read ``ClassName(params)-check_name``.
    """
    import pytest

    items = list(trackers_)
    for t in items:
        if not isinstance(t, Tracker):
            raise TypeError(f"`trackers_` must hold Tracker instances, got {type(t).__name__}")
    params = []
    ids = []
    for t in items:
        for check in _checks_for(t):
            params.append((t, partial(check)))
            ids.append(f"{t!r}-{check.__name__}")
    return pytest.mark.parametrize("tracker, check", params, ids=ids)
