import dataclasses

import numpy as np
import pytest

from scenes.frame import Frame, Truth, false_columns


def test_truth_valid_rows_and_immutability():
    t = Truth(np.array([1.5, np.nan, 3.0]), np.zeros((3, 3)), np.array([True, False, False]))
    assert t.valid.tolist() == [True, False, True]
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.columns = np.zeros(3)
    f = Frame(np.zeros((3, 4), np.uint8), np.zeros((3, 4), np.uint8), np.zeros((3, 4), np.float32),
              np.zeros((3, 4), np.float32), t, 0.5, "scalar_rgb")
    with pytest.raises(dataclasses.FrozenInstanceError):
        f.mirror_angle_deg = 1.0


def test_truth_part_defaults_from_on_object():
    t = Truth(np.array([1.5, np.nan, 3.0]), np.zeros((3, 3)), np.array([True, False, False]))
    assert t.part.tolist() == [1, -1, 0] and t.part.dtype == np.int8
    part = np.array([1, -1, 2], np.int8)
    assert Truth(t.columns, t.points_cm, t.on_object, part).part is part
def test_false_columns_pad_each_row_with_nan():
    mask = np.zeros((3, 6), bool)
    mask[0, [1, 4]] = True
    mask[2, 5] = True
    t = Truth(np.full(3, np.nan), np.full((3, 3), np.nan), np.zeros(3, bool), false_mask=mask)
    expected = np.array([[1.0, 4.0], [np.nan, np.nan], [5.0, np.nan]])
    assert np.array_equal(t.false_columns, expected, equal_nan=True)
    assert t.false_columns.dtype == np.float64
    none = Truth(np.full(3, np.nan), np.full((3, 3), np.nan), np.zeros(3, bool))
    assert none.false_mask is None and none.false_columns.shape == (3, 0)
    assert false_columns(np.zeros((2, 4), bool)).shape == (2, 0)


def test_docstring_examples_run():
    import doctest
    import importlib

    module = importlib.import_module("scenes.frame")
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0
