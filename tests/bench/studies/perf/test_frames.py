import doctest

import numpy as np
import pytest

from bench.studies.perf import frames as F


def test_docstring_examples():
    result = doctest.testmod(F, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_every_kind_at_every_size_seeded():
    a = F.varied_frames(2, seed=3, sizes=((60, 64), (30, 96)))
    b = F.varied_frames(2, seed=3, sizes=((60, 64), (30, 96)))
    c = F.varied_frames(2, seed=4, sizes=((60, 64), (30, 96)))
    assert len(a) == 2 * len(F.KINDS) * 2
    assert [label for label, _ in a[:2]] == ["clean 64x60"] * 2 and a[-1][0] == f"{F.KINDS[-1]} 96x30"
    assert all(x[1].dtype == np.uint8 for x in a)
    assert all(np.array_equal(x[1], y[1]) for x, y in zip(a, b))
    assert not all(np.array_equal(x[1], y[1]) for x, y in zip(a, c))


def test_the_kinds_differ_as_named():
    frames = dict(F.varied_frames(1, sizes=((120, 128),)))
    assert (frames["saturated 128x120"] == 255).sum(axis=1).min() >= 3  # a wide clipped stripe in every row
    assert frames["gradient 128x120"].astype(float).mean() > frames["clean 128x120"].astype(float).mean() + 30
    side = np.s_[:, :8]  # beside the stripe
    assert frames["noisy 128x120"][side].astype(float).std() > 3 * frames["clean 128x120"][side].astype(float).std()
    # the brightest column jumps sideways by more than 1/8 of the width between two rows (a clean stripe
    # moves less than a column per row)
    peak = np.argmax(frames["jumps 128x120"], axis=1)
    assert np.abs(np.diff(peak)).max() > 128 / 8 and np.abs(np.diff(np.argmax(frames["clean 128x120"], axis=1))).max() <= 2
    # saturated glints beside the stripe: rows holding two bright runs more than 8 px apart
    streaks = frames["streaks 128x120"]
    assert (streaks == 255).any() and not (frames["clean 128x120"] == 255).any()
    runs = [np.flatnonzero(row >= 100) for row in streaks]
    assert sum(1 for c in runs if c.size and c.max() - c.min() > 8) >= 10


@pytest.mark.parametrize("per_kind", [0, -1, 1.5, True])
def test_per_kind_is_validated(per_kind):
    with pytest.raises(ValueError, match=r"`per_kind` must be an integer >= 1, got"):
        F.varied_frames(per_kind)
