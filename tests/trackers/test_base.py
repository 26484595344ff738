import numpy as np
import pytest

from trackers import Track, Tracker


class _Echo(Tracker):
    """Reports the argmax of every row; used to test the base class."""

    name = "echo"

    def __init__(self, offset=0.0, label="x"):
        self.offset = offset
        self.label = label

    def _validate_params(self):
        if self.offset < 0:
            raise ValueError(f"`offset` must be >= 0, got {self.offset!r}")

    def _track(self, image, background):
        cols = np.argmax(image, axis=1).astype(float) + self.offset
        return Track(cols, np.ones_like(cols))


def test_track_is_frozen_read_only_and_float64():
    t = Track([1, 2, np.nan], [0.5, 1, np.nan])
    assert t.columns.dtype == np.float64 and t.score.dtype == np.float64
    assert t.height == 3 and t.detected.tolist() == [True, True, False]
    with pytest.raises(ValueError):
        t.columns[0] = 5.0
    with pytest.raises(AttributeError):
        t.columns = np.zeros(3)


def test_track_copies_its_inputs():
    cols = np.array([1.0, 2.0])
    t = Track(cols, np.ones(2))
    cols[0] = 9.0
    assert t.columns[0] == 1.0


@pytest.mark.parametrize(
    "columns, score, message",
    [
        (np.zeros((2, 2)), np.zeros((2, 2)), r"`columns` must be 1-D, got shape \(2, 2\)"),
        (np.zeros(3), np.zeros(2), r"`score` must have the shape of `columns` \(3,\), got \(2,\)"),
        ([1.0, np.inf], [1.0, 1.0], "`columns` must be finite or NaN"),
        ([1.0, 2.0], [1.0, -np.inf], "`score` must be finite or NaN"),
        ([1.0, np.nan], [1.0, 1.0], "`score` must be NaN exactly where `columns` is NaN"),
        ([1.0, 2.0], [1.0, np.nan], "`score` must be NaN exactly where `columns` is NaN"),
    ],
)
def test_track_validates(columns, score, message):
    with pytest.raises(ValueError, match=message):
        Track(columns, score)


def test_empty_track():
    t = Track.empty(4)
    assert np.isnan(t.columns).all() and np.isnan(t.score).all() and t.height == 4


def test_get_params_repr_and_constructor_only_stores():
    t = _Echo(offset=-1.0)  # invalid, but constructors do not validate
    assert t.get_params() == {"offset": -1.0, "label": "x"}
    assert repr(t) == "_Echo(offset=-1.0, label='x')"
    with pytest.raises(ValueError, match=r"`offset` must be >= 0, got -1.0"):
        t.track(np.zeros((2, 2)))


def test_track_validates_image_and_background():
    t = _Echo()
    with pytest.raises(ValueError, match=r"`image` must be 2-D, got shape \(3, 4, 5\)"):
        t.track(np.zeros((3, 4, 5)))
    with pytest.raises(ValueError, match="`background` must have the shape"):
        t.track(np.zeros((2, 3)), background=np.zeros((3, 2)))
    out = t.track([[0, 5, 1], [9, 0, 0]])
    assert out.columns.tolist() == [1.0, 0.0]


def test_wrong_row_count_is_an_error():
    class Bad(_Echo):
        def _track(self, image, background):
            return Track.empty(image.shape[0] + 1)

    with pytest.raises(RuntimeError, match="returned 3 rows for an image of 2"):
        Bad().track(np.zeros((2, 2)))


def test_varargs_constructor_is_refused():
    class Loose(_Echo):
        def __init__(self, **kw):
            self.kw = kw

    with pytest.raises(TypeError, match="explicit keyword parameters"):
        Loose().get_params()


def test_tracker_is_abstract():
    with pytest.raises(TypeError):
        Tracker()


def test_a_tracker_without_parameters():
    class Bare(Tracker):
        name = "bare"

        def _track(self, image, background):
            return Track.empty(image.shape[0])

    assert Bare().get_params() == {} and repr(Bare()) == "Bare()"


def test_an_old_plugin_overriding_only_the_private_hooks_still_works():
    # _Echo overrides only `_track` and `_validate_params` (the contract before find_stripe)
    img = np.zeros((3, 8), np.uint8)
    img[:, 5] = 200
    t = _Echo(offset=0.5)
    assert t.track(img).columns.tolist() == [5.5, 5.5, 5.5]
    assert t.find_stripe(img, None).columns.tolist() == [5.5, 5.5, 5.5]  # the public hook calls `_track`
    with pytest.raises(ValueError, match=r"`offset` must be >= 0, got -1"):
        _Echo(offset=-1).track(img)  # track() still calls the overridden `_validate_params`


def test_a_plugin_on_the_public_contract_works():
    from trackers._params import Int, Real
    from trackers.testing import check_parameter_constraints

    class Shifted(Tracker):
        name = "shifted"
        parameter_constraints = {"offset": Real(low=0), "step": Int(low=1)}

        def __init__(self, offset=0.0, step=1):
            self.offset, self.step = offset, step

        def validate_params(self):
            super().validate_params()
            if self.offset >= self.step:
                raise ValueError(f"`offset` must be < `step` ({self.step}), got {self.offset!r}")

        def find_stripe(self, image, background):
            cols = np.argmax(image, axis=1).astype(float) + self.offset
            return Track(cols, np.ones_like(cols))

    img = np.zeros((2, 8), np.uint8)
    img[:, 2] = 90
    assert Shifted(offset=0.25).track(img).columns.tolist() == [2.25, 2.25]
    with pytest.raises(ValueError, match=r"`offset` must be >= 0, got -0.5"):  # the table
        Shifted(offset=-0.5).track(img)
    with pytest.raises(ValueError, match=r"`offset` must be < `step` \(1\), got 1.5"):  # the cross rule
        Shifted(offset=1.5).track(img)
    check_parameter_constraints(Shifted())


def test_every_built_in_tracker_is_on_the_public_contract():
    import trackers

    for name in trackers.available(unlisted=True):
        cls = type(trackers.make(name))
        hooks = [k for c in cls.__mro__ if c is not Tracker for k in vars(c) if k in ("_track", "_validate_params")]
        assert not hooks, f"{name} still overrides the private hook(s) {hooks}"
        assert cls.find_stripe is not Tracker.find_stripe, name
        assert cls.parameter_constraints, name
