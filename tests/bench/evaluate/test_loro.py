"""Leave one rig out: the folds, a choice run fold by fold, and the null prediction."""

import numpy as np
import pytest

from bench.evaluate.loro import choose_by_fold, null_prediction, pooled_counts, rig_folds


def test_no_rig_lies_on_both_sides_of_a_fold_and_every_item_is_held_out_once():
    rigs = ["x", "y", "x", "z", "y", "y", "w"]
    folds = rig_folds(rigs)
    assert [f.rig for f in folds] == ["w", "x", "y", "z"]
    held = np.zeros(len(rigs), int)
    for f in folds:
        assert not (f.test & f.train).any()
        assert (f.test | f.train).all()
        train_rigs = {r for r, t in zip(rigs, f.train) if t}
        test_rigs = {r for r, t in zip(rigs, f.test) if t}
        assert test_rigs == {f.rig} and f.rig not in train_rigs
        held += f.test
    assert (held == 1).all()


@pytest.mark.parametrize("rigs", [["a", "a"], [], ["a", ""]])
def test_folds_refuse_one_rig_or_a_nameless_one(rigs):
    with pytest.raises(ValueError):
        rig_folds(rigs)


def _f1(c):
    c = np.asarray(c, float)
    d = 2 * c[0] + 2 * c[1] + c[2] + c[3]
    return 2 * c[0] / d if d else 0.0


def test_a_choice_that_fits_one_planted_rig_is_caught_leave_one_rig_out():
    # candidate "fit" is perfect on the planted rig and poor elsewhere; "plain" is good everywhere but the planted
    # rig, which is so large that in sample it wins the pooled objective for "fit"
    counts = {
        "fit": {"planted": np.array([900, 0, 0, 0, 300, 0]), "p": np.array([5, 0, 5, 10, 0, 0]),
                "q": np.array([5, 0, 5, 10, 0, 0])},
        "plain": {"planted": np.array([600, 0, 300, 0, 300, 0]), "p": np.array([10, 0, 0, 0, 10, 0]),
                  "q": np.array([10, 0, 0, 0, 10, 0])},
    }
    def choose(held_out):
        keep = [r for r in ("planted", "p", "q") if r != held_out]
        return max(sorted(counts), key=lambda k: _f1(pooled_counts(counts[k], keep)))

    fc = choose_by_fold(counts, choose)
    assert fc.in_sample == "fit"
    # held out, the planted rig is scored under "plain" (chosen on p and q) and p, q under "fit" (chosen with the
    # planted rig in): the pooled held-out F1 is below the in-sample one
    assert fc.by_rig == {"planted": "plain", "p": "fit", "q": "fit"}
    assert not fc.stable
    assert fc.loro["f1"] < fc.in_sample_figures["f1"]
    expected = counts["plain"]["planted"] + counts["fit"]["p"] + counts["fit"]["q"]
    assert fc.loro_counts.tolist() == expected.tolist()


def test_each_rig_is_held_out_once_and_scored_under_its_own_fold_s_choice():
    seen = []
    counts = {c: {r: np.array([c, 0, 0, 0, 1, 0]) for r in "abc"} for c in (1, 2)}

    def choose(held_out):
        seen.append(held_out)
        return 2 if held_out == "b" else 1

    fc = choose_by_fold(counts, choose)
    assert seen == [None, "a", "b", "c"]
    assert fc.loro_counts.tolist() == [1 + 2 + 1, 0, 0, 0, 3, 0]
    assert fc.in_sample_counts.tolist() == [3, 0, 0, 0, 3, 0]


def test_the_null_prediction_is_the_mean_of_the_other_rigs_each_rig_weighing_the_same():
    values = np.array([[0.9], [0.7], [0.5], [0.1]])
    p = null_prediction(values, ["a", "a", "b", "c"])
    assert p["a"][0] == pytest.approx(0.3)  # (0.5 + 0.1) / 2
    assert p["b"][0] == pytest.approx((0.8 + 0.1) / 2)  # rig a's two photographs are one rig's figure
    assert p["c"][0] == pytest.approx((0.8 + 0.5) / 2)
    with pytest.raises(ValueError):
        null_prediction(values, ["a"])


def test_rig_figures_pool_each_rig_and_give_the_interval_over_rigs():
    from bench.evaluate.loro import rig_figures

    counts = np.array([[90, 0, 10, 0, 0, 0], [80, 0, 20, 5, 45, 0], [50, 0, 50, 0, 0, 0], [60, 0, 40, 0, 10, 0]])
    r = rig_figures(counts, ["a", "a", "b", "c"], n_boot=500, seed=3)
    a = r["rigs"]["a"]
    assert a["recall"] == pytest.approx(170 / 200) and a["false_report_rate"] == pytest.approx(5 / 50)
    assert a["recall_lo"] <= a["recall"] <= a["recall_hi"] and a["recall_lo"] < a["recall_hi"]
    assert np.isnan(r["rigs"]["b"]["f1_lo"])                      # one photograph: no interval
    allr = r["all"]
    assert allr["n_rigs"] == 3 and allr["recall"] == pytest.approx(280 / 400)
    # over rigs the interval reaches down towards rig b's 0.5 and up towards rig a's 0.85
    assert allr["recall_lo"] < 0.62 and allr["recall_hi"] > 0.78
    assert np.isnan(rig_figures(counts, ["a"] * 4, n_boot=50)["all"]["recall_lo"])  # one rig: none over rigs
    with pytest.raises(ValueError):
        rig_figures(counts, ["a", "b"])
