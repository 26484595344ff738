import numpy as np
import pytest

import scenes
from scenes import rows

pytestmark = pytest.mark.slow


def test_part_rows_match_the_rendered_truth():
    s = scenes.make("cone", support="table", width=64, height=60, spp=1, ambient_spp=1, cache=False)
    angles = [float(s.default_angles()[0]), 0.0]
    found = rows.part_rows(s, angles)
    parts = [s.render(a).truth.part for a in angles]
    for k, name in enumerate(scenes.frame.PARTS):
        expected = sorted(set(np.nonzero(np.any([p == k for p in parts], axis=0))[0].tolist()))
        assert found[name].tolist() == expected
    assert len(found["object"]) > 40 and len(found["support"]) > 0
    assert found["support"].max() == 59 and found["support"].min() > 0
    assert np.array_equal(s.truth(0.0).columns, s.render(0.0).truth.columns, equal_nan=True)


def test_rows_command(capsys):
    assert rows.main(["--objects", "sphere", "--width", "64", "--height", "60", "--n-angles", "3",
                      "--background", "none", "--support", "table"]) == 0
    out = capsys.readouterr().out
    assert "sphere" in out and "support" in out and "background - (0)" in out
    with pytest.raises(SystemExit):
        rows.main(["--objects", "hand", "--background-distance-cm", "20", "--width", "64", "--height", "60"])
