import numpy as np
import pytest

from bench.evaluate.restore import fill_depth_map, fill_rows


def test_fill_rows():
    assert fill_rows([np.nan, 2.0, np.nan, np.nan, 5.0]).tolist() == [2.0, 2.0, 3.0, 4.0, 5.0]
    assert np.isnan(fill_rows([np.nan, np.nan])).all()


def test_fill_depth_map_takes_the_nearest_frame_for_empty_frames():
    d = np.array([[1.0, np.nan], [np.nan, np.nan], [np.nan, np.nan], [7.0, 9.0]])
    out, filled = fill_depth_map(d)
    assert out.tolist() == [[1.0, 1.0], [1.0, 1.0], [7.0, 9.0], [7.0, 9.0]]
    assert filled.tolist() == [[False, True], [True, True], [True, True], [False, False]]
    with pytest.raises(ValueError, match=r"`depth` must be 2-D"):
        fill_depth_map(np.zeros(3))
