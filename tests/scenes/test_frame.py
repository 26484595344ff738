import dataclasses

import numpy as np
import pytest

from scenes.frame import Frame, Truth


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
