import numpy as np
import pytest

from trackers._validation import check_background, check_image


def test_uint8_is_passed_through_without_copy():
    img = np.zeros((3, 4), np.uint8)
    assert check_image(img) is img


def test_float64_is_passed_through_and_others_become_float64():
    img = np.zeros((3, 4))
    assert check_image(img) is img
    for dtype in (np.uint16, np.int32, np.float32):
        out = check_image(np.ones((2, 2), dtype))
        assert out.dtype == np.float64 and out.tolist() == [[1.0, 1.0], [1.0, 1.0]]


def test_non_contiguous_input_is_made_contiguous():
    img = np.arange(24, dtype=np.uint8).reshape(4, 6)[:, ::2]
    out = check_image(img)
    assert out.flags.c_contiguous and np.array_equal(out, img)


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.zeros((3, 4, 5)), r"`image` must be 2-D, got shape \(3, 4, 5\)"),
        (np.zeros(7), r"`image` must be 2-D, got shape \(7,\)"),
        (np.zeros((0, 5)), r"`image` must not be empty, got shape \(0, 5\)"),
        (np.array([["a"]]), r"`image` must hold real numbers .* got dtype <U1"),
        (np.ones((2, 2), bool), r"`image` must hold real numbers .* got dtype bool"),
        (np.ones((2, 2), complex), r"`image` must hold real numbers .* got dtype complex128"),
        (np.array([[1.0, np.nan], [np.inf, 0]]), r"`image` must be finite, got 2 NaN or infinite value\(s\)"),
        ([[1, 2], [3]], r"`image` must be a 2-D numeric array"),
    ],
)
def test_bad_images_are_refused_naming_the_argument(bad, message):
    with pytest.raises(ValueError, match=message):
        check_image(bad)


def test_background_shape_must_match():
    assert check_background(None, (2, 3)) is None
    with pytest.raises(ValueError, match=r"`background` must have the shape of `image` \(2, 3\), got \(3, 2\)"):
        check_background(np.zeros((3, 2)), (2, 3))
    with pytest.raises(ValueError, match="`background` must be finite"):
        check_background(np.full((2, 3), np.nan), (2, 3))
