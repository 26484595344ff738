"""The training procedure's data (``bench.studies.train``; the network and the tiny training run are in
tests/trackers/test_learned.py, which needs JAX)."""

import numpy as np

from bench.studies import train as tr


def test_load_frames_adds_one_seeded_shrunk_copy_per_frame_and_view(tmp_path, tiny_trainset):
    row, img, _ = tiny_trainset(tmp_path, rgb=True)
    plain = tr._load_frames(tmp_path, [row], ("auto", "laser"))
    assert len(plain) == 2 and all(f[0].shape == (6, 8) for f in plain)
    shrunk = tr._load_frames(tmp_path, [row], ("auto", "laser"), (2, 3), seed=4)
    assert len(shrunk) == 4
    assert [f[0].shape[0] for f in shrunk[::2]] == [6, 6]
    assert all(f[0].shape in ((3, 4), (2, 2)) for f in shrunk[1::2])
    again = tr._load_frames(tmp_path, [row], ("auto", "laser"), (2, 3), seed=4)
    assert all(np.array_equal(a[0], b[0]) for a, b in zip(shrunk, again))
    # draws differ between seeds somewhere over a few seeds (both factors are used)
    sizes = {tr._load_frames(tmp_path, [row], ("auto",), (2, 3), seed=s)[1][0].shape for s in range(8)}
    assert sizes == {(3, 4), (2, 2)}
    assert tr.HyperParams().shrink == (2, 4)
