"""The tuning frames and objective (bench.studies.tuning): the eligibility rule, colour evidence."""

import numpy as np

from bench.studies import tuning
from bench.studies.tuning import EASY_ARGMAX, Tally, TuningFrame


def _frame(group, name, plain=True, h=8, w=20):
    """A frame whose stripe (column 5) is each row's brightest pixel (``plain``), or a frame whose brightest
    pixel is at column 15 in every row (not plain)."""
    img = np.zeros((h, w))
    img[:, 5] = 50.0
    if not plain:
        img[:, 15] = 90.0
    truth = np.full(h, 5.0)
    return TuningFrame(group, name, "k", img, None, truth, np.ones(h, np.int8))


def _tally():
    """Three settings: ``A`` blind on a plain photograph (best objective), ``B`` blind on two plain synthetic
    frames, ``C`` blind on nothing but the worst; every frame's stripe at column 5."""
    photo, s1, s2, hard = (_frame("real", "photo"), _frame("synthetic", "s1"), _frame("synthetic", "s2"),
                           _frame("real", "hard", plain=False))
    t = Tally(1, 3.0)
    nan = np.full(8, np.nan)
    right = np.full(8, 5.0)
    wrong = np.full(8, 12.0)
    for setting, cols in (("A", {photo: nan, s1: right, s2: right, hard: nan}),
                          ("B", {photo: right, s1: nan, s2: nan, hard: nan}),
                          ("C", {photo: right, s1: wrong, s2: wrong, hard: nan})):
        for f, c in cols.items():
            t.add(setting, "threshold", f, c)
    return t


def test_a_plain_frame_is_one_whose_argmax_is_right():
    assert _frame("real", "a").easy and not _frame("real", "b", plain=False).easy
    assert EASY_ARGMAX == 0.75


def test_blindness_on_a_photograph_disqualifies_whatever_the_other_groups_say():
    t = _tally()
    scores = {"A": 0.9, "B": 0.8, "C": 0.5}
    assert t.blind["A"] == ["threshold on real/photo"] and len(t.blind["B"]) == 2
    # A goes blind on one plain frame, B on two; but A's is a photograph: B and C are eligible, and of
    # those the one blind on fewest plain frames in all
    assert t.eligible(scores, lambda s: s) == {"C": 0.5}
    assert set(t.eligible({"A": 0.9, "B": 0.8}, lambda s: s)) == {"B"}
    # a photograph that is not plain (its argmax is wrong) does not count
    assert t.blind_photos["B"] == [] and t.unavoidable("B") == []
    # when every setting goes blind on a photograph, none is disqualified by it, and the procedures name it
    t.add("B", "threshold", _frame("real", "photo2"), np.full(8, np.nan))
    t.add("C", "threshold", _frame("real", "photo2"), np.full(8, np.nan))
    assert set(t.eligible({"A": 0.9, "B": 0.8, "C": 0.5}, lambda s: s)) == {"A", "C"}
    assert t.unavoidable("C") == ["threshold on real/photo2"]


def test_colour_evidence_of_a_tuning_frame():
    from bench.studies.hard_frames import hard_frame

    hf = hard_frame("skin", 2)
    f = tuning.synthetic_frames(["skin"], [2])[0]
    assert f.colour is not None and f.colour.shape == f.image.shape
    assert 0.0 <= np.nanmin(f.colour) and np.nanmax(f.colour) <= 1.0
    rows = np.nonzero(np.isfinite(hf.truth))[0]
    c = np.rint(hf.truth[rows]).astype(int)
    on_stripe = np.max([f.colour[rows, c + d] for d in (-1, 0, 1)], axis=0)
    assert np.median(on_stripe) > 0.7  # the laser's own light is laser-coloured (the stripe's core or flank)
    grey = TuningFrame("real", "g", "k", f.image, None, hf.truth, np.ones(f.image.shape[0], np.int8),
                       np.repeat(f.image[..., None], 3, axis=2))
    assert grey.colour is None  # a grey photograph has no colour evidence
    assert TuningFrame("real", "m", "k", f.image, None, hf.truth, np.ones(f.image.shape[0], np.int8)).colour is None
