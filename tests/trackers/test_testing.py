"""The conformance suite, applied to every registered tracker, and shown to
catch broken trackers."""

import numpy as np
import pytest

import trackers
from trackers import Track, Tracker
from trackers.testing import all_checks, check_tracker, make_stripe_image, parametrize_with_checks


@parametrize_with_checks([trackers.make(name) for name in trackers.available()])
def test_registered_trackers_conform(tracker, check):
    check(tracker)


def test_make_stripe_image_truth():
    img, truth = make_stripe_image(height=50, width=70, noise=0.0, seed=3)
    assert img.dtype == np.uint8 and img.shape == (50, 70) and truth.shape == (50,)
    # noise-free: the intensity centroid of the background-subtracted row is the truth
    w = img.astype(float) - 10.0
    centroid = (w * np.arange(70)).sum(1) / w.sum(1)
    assert np.abs(centroid - truth).max() < 0.05


class _Good(Tracker):
    name = "good"
    subpixel = True

    def __init__(self, half=3):
        self.half = half

    def _track(self, image, background):
        img = image.astype(float)
        bg = np.median(img)
        peak = img.argmax(1)
        cols = np.full(img.shape[0], np.nan)
        for r, p in enumerate(peak):
            if img[r, p] - bg > 0.1 * np.ptp(img):  # relative to the frame's range: any pixel units
                lo, hi = max(p - self.half, 0), min(p + self.half + 1, img.shape[1])
                w = np.clip(img[r, lo:hi] - bg, 0, None)
                cols[r] = (w * np.arange(lo, hi)).sum() / w.sum()
        return Track(cols, np.where(np.isnan(cols), np.nan, 1.0))


def test_a_correct_tracker_passes():
    check_tracker(_Good())


def _negated(track, image):
    return Track(track.columns, np.where(np.isnan(track.columns), np.nan, -image.max(1).astype(float)))


def _absolute(track, image):
    keep = np.asarray(image, float).max(1) - np.median(image, axis=1) > 20
    return Track(np.where(keep, track.columns, np.nan), np.where(keep, track.score, np.nan))


def _inner(track, image):
    peak = np.argmax(image, axis=1)
    keep = (peak > 0) & (peak < image.shape[1] - 1)
    return Track(np.where(keep, track.columns, np.nan), np.where(keep, track.score, np.nan))


def _broken(params=None, **overrides):
    return type("Broken", (_Good,), overrides)(**(params or {}))


@pytest.mark.parametrize(
    "tracker, failing_check, message",
    [
        (
            _broken(_track=lambda self, image, background: Track(np.full(image.shape[0], 1e6), np.ones(image.shape[0]))),
            "check_output_types",
            "columns outside the image",
        ),
        (
            _broken(_track=lambda self, image, background: Track(np.zeros(image.shape[0]), np.ones(image.shape[0]))),
            "check_blank_image",
            "reported a stripe in a constant",
        ),
        (_broken({"half": 0}), "check_synthetic_accuracy", "mean absolute error"),
        (
            _broken(_validate_params=lambda self: setattr(self, "half", self.half + 1)),
            "check_no_state_change",
            "changed the tracker's state",
        ),
        (  # lower means more confident: the score is the peak's darkness
            _broken(_track=lambda self, image, background: _negated(_Good._track(self, image, background), image)),
            "check_score_meaning",
            "higher must mean more confident",
        ),
        (  # every row reported, stripe-less rows scored as high as stripe rows
            _broken(_track=lambda self, image, background: Track(np.full(image.shape[0], 3.0), np.select(
                [np.arange(image.shape[0]) < image.shape[0] // 3, np.arange(image.shape[0]) < 2 * (image.shape[0] // 3)],
                [100.0, 50.0], 200.0))),
            "check_score_meaning",
            "outscores a reported stripe-less row",
        ),
        (  # a threshold in 8-bit DN: nothing stands 20 units out of a frame times 1e-300
            _broken(_track=lambda self, image, background: _absolute(_Good._track(self, image, background), image)),
            "check_pixel_range",
            "in a float times 1e-300 frame",
        ),
        (  # only interior peaks: a stripe on the border column is never reported
            _broken(_track=lambda self, image, background: _inner(_Good._track(self, image, background), image)),
            "check_border_stripe",
            "on the first column",
        ),
    ],
)
def test_the_checks_catch_broken_trackers(tracker, failing_check, message):
    check = {c.__name__: c for c in all_checks()}[failing_check]
    with pytest.raises(AssertionError, match=message):
        check(tracker)


def test_check_catches_input_modification():
    class Scribbler(_Good):
        def track(self, image, *, background=None):
            out = super().track(image, background=background)
            if isinstance(image, np.ndarray) and image.flags.writeable:
                image[0, 0] = 99
            return out

    check = {c.__name__: c for c in all_checks()}["check_readonly_input"]
    check(Scribbler())  # read-only inputs cannot be scribbled on ...
    with pytest.raises(AssertionError, match="uint8 and float64 copies"):
        # ... but a writable copy is, and the dtype check sees the difference
        {c.__name__: c for c in all_checks()}["check_dtype_invariance"](
            type("Order", (_Good,), {"_track": lambda self, image, background: Track(
                np.full(image.shape[0], 1.0 if image.dtype == np.uint8 else 2.0), np.ones(image.shape[0]))})()
        )


def test_check_catches_missing_validation_and_flip_asymmetry():
    class Lax(_Good):
        def track(self, image, *, background=None):
            img = np.atleast_2d(np.asarray(image, dtype=float).reshape(image.shape[0], -1)) if np.ndim(image) else image
            return super().track(np.nan_to_num(img.real if np.iscomplexobj(img) else img))

    with pytest.raises(AssertionError, match="accepted a"):
        {c.__name__: c for c in all_checks()}["check_bad_input"](Lax())

    class TopDown(_Good):
        def _track(self, image, background):
            out = super()._track(image, background)
            cols = out.columns.copy()
            cols[: image.shape[0] // 2] += 0.25
            return Track(cols, out.score)

    with pytest.raises(AssertionError, match="flipped"):
        {c.__name__: c for c in all_checks()}["check_vertical_flip"](TopDown())


def test_check_tracker_refuses_non_trackers():
    with pytest.raises(TypeError, match="`tracker` must be a trackers.Tracker instance, got int"):
        check_tracker(3)


def test_the_constraint_check_finds_a_missing_entry_and_an_accepted_bad_value():
    import numpy as np

    from trackers import Track, Tracker
    from trackers._params import Int, Real
    from trackers.testing import all_checks, check_parameter_constraints

    class Good(Tracker):
        name = "good"
        parameter_constraints = {"k": Real(low=0), "n": Int(low=1)}

        def __init__(self, k=1.0, n=2):
            self.k, self.n = k, n

        def find_stripe(self, image, background):
            return Track(np.argmax(image, axis=1).astype(float), np.ones(image.shape[0]))

    class Missing(Good):
        parameter_constraints = {"k": Real(low=0)}

    class Lax(Good):
        parameter_constraints = {"k": Real(low=0), "n": Int(low=1)}

        def validate_params(self):  # forgets the table
            pass

    check_parameter_constraints(Good())
    with pytest.raises(AssertionError, match=r"parameter\(s\) \['n'\] have no entry"):
        check_parameter_constraints(Missing())
    with pytest.raises(AssertionError, match="violates its constraint but was accepted"):
        check_parameter_constraints(Lax())
    assert check_parameter_constraints in all_checks()


class _GoodWithBackground(_Good):
    """_Good on the laser-on minus laser-off difference."""

    uses_background = True

    def _track(self, image, background):
        if background is not None:
            diff = image.astype(float) - background
            if not (diff > 20).any():
                return Track.empty(image.shape[0])
            image = diff
        return super()._track(image, None)


def test_the_background_check_runs_only_on_trackers_that_use_it():
    from trackers.testing import _checks_for, check_background_use

    assert check_background_use in all_checks()
    assert check_background_use not in list(_checks_for(_Good()))
    assert check_background_use in list(_checks_for(_GoodWithBackground()))
    check_tracker(_GoodWithBackground())
    assert all(check_background_use in list(_checks_for(trackers.make(n))) for n in ("com_bg", "dp4", "dp8",
                                                                                 "dp8_subpixel", "dp_gap"))


def test_the_background_check_catches_a_tracker_that_ignores_its_background():
    from trackers.testing import check_background_use

    liar = type("Liar", (_Good,), {"uses_background": True})()
    with pytest.raises(AssertionError, match="given the laser-off frame"):
        check_background_use(liar)
    # one that subtracts but then reports noise where laser-on equals laser-off
    noisy = type("Noisy", (_GoodWithBackground,), {"_track": lambda self, image, background: _Good._track(
        self, image.astype(float) - background + np.arange(image.shape[1]) if background is not None else image,
        None)})()
    with pytest.raises(AssertionError, match="laser-off frame equal to the image|mean absolute error"):
        check_background_use(noisy)


class _GoodWithColour(_Good):
    """_Good that reads colour evidence: a row whose peak is not laser-coloured reports nothing."""

    uses_colour = True

    def find_stripe(self, image, background, colour=None):
        out = self._track(image, background)
        if colour is None:
            return out
        peak = image.argmax(1)
        keep = colour[np.arange(image.shape[0]), peak] >= 0.5
        cols = np.where(keep, out.columns, np.nan)
        return Track(cols, np.where(keep, out.score, np.nan))


def test_the_colour_check_runs_on_trackers_that_read_colour_and_catches_one_that_misreads_it():
    from trackers.testing import _checks_for, check_colour_use

    assert check_colour_use in all_checks()
    assert check_colour_use not in list(_checks_for(_Good()))
    assert check_colour_use in list(_checks_for(_GoodWithColour()))
    check_tracker(_GoodWithColour())
    for n in ("threshold", "centroid", "com_bg", "steger", "dp4", "dp_gap", "learned"):
        assert check_colour_use in list(_checks_for(trackers.make(n, stripe_test={})))
        check_colour_use(trackers.make(n, stripe_test={}))  # the stripe question reads uninformative evidence as such
    # a tracker that goes blind whenever colour is given
    blind = type("Blind", (_GoodWithColour,), {"find_stripe": lambda self, image, background, colour=None: (
        Track.empty(image.shape[0]) if colour is not None else self._track(image, background))})()
    with pytest.raises(AssertionError, match="every pixel has the laser's colour changed the track"):
        check_colour_use(blind)
    # a subclass of a built-in tracker with the two-argument hook runs as before without evidence
    old_style = type("OldStyle", (type(trackers.make("dp4")),), {
        "find_stripe": lambda self, image, background: trackers.make("dp4").find_stripe(image, background)})()
    img, _ = make_stripe_image(seed=2)
    np.testing.assert_array_equal(old_style.track(img).columns, trackers.make("dp4").track(img).columns)
    # a tracker without uses_colour never sees the evidence, and a bad one is refused all the same
    with pytest.raises(ValueError, match="`colour` must have the frame's shape"):
        _Good().track(np.zeros((4, 5)), colour=np.zeros((4, 4)))
    with pytest.raises(ValueError, match="laser shares in \\[0, 1\\]"):
        _Good().track(np.zeros((4, 5)), colour=np.full((4, 5), 2.0))
