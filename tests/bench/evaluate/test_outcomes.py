"""Row outcomes, detection figures (bench.evaluate.outcomes) and average precision (bench.evaluate.ranking)."""

import itertools

import numpy as np
import pytest

from bench.evaluate.outcomes import (FALSE, HIT, MISSED, NO_STRIPE, OUTCOMES, QUIET, STRIPE, UNKNOWN, UNSURE, WRONG,
                                     detection_figures, distant_states, fallback_of, fallback_states, outcome_counts,
                                     referenced_columns, referenced_states, row_outcomes, truth_states, window_centre)
from bench.evaluate.ranking import average_precision, bootstrap_frames, pr_curve


def _frame():
    """A hand-made frame of 10 rows with every outcome: truth, a tracker's columns, the rows' states."""
    truth = np.array([10.0, 10.0, 10.0, 12.0, 13.0, np.nan, np.nan, np.nan, np.nan, np.nan])
    pred = np.array([11.5, 17.0, np.nan, 15.0, np.nan, 40.0, np.nan, 3.0, np.nan, 8.0])
    state = np.array([1, 1, 1, 1, 1, 0, 0, 0, 0, -1])
    want = [HIT, WRONG, MISSED, HIT, MISSED, FALSE, QUIET, FALSE, QUIET, UNKNOWN]
    return pred, truth, state, want


def test_every_outcome_on_a_hand_made_frame():
    pred, truth, state, want = _frame()
    codes = row_outcomes(pred, truth, state)
    assert codes.tolist() == want
    assert outcome_counts(codes) == {"n_hit": 2, "n_wrong": 1, "n_missed": 2, "n_false": 2, "n_quiet": 2,
                                     "n_unknown": 1}
    f = detection_figures(outcome_counts(codes))
    assert f["precision"] == pytest.approx(2 / 5)  # 2 hits among 5 reports of known state
    assert f["recall"] == pytest.approx(2 / 5)  # 2 hits among 5 stripe rows
    assert f["f1"] == pytest.approx(2 * 2 / (2 * 2 + 2 * 1 + 2 + 2))
    assert f["false_report_rate"] == pytest.approx(2 / 4)
    # the hit rule's edge: exactly 3 px is a hit, just over is wrong
    assert row_outcomes([13.0, 13.0001], [10.0, 10.0]).tolist() == [HIT, WRONG]


def test_exact_truth_states_and_their_default():
    pred = np.array([1.0, np.nan, 5.0, np.nan])
    truth = np.array([1.0, 2.0, np.nan, np.nan])
    assert truth_states(truth).tolist() == [STRIPE, STRIPE, NO_STRIPE, NO_STRIPE]
    assert [OUTCOMES[c] for c in row_outcomes(pred, truth)] == ["hit", "missed", "false", "quiet"]


def test_states_are_checked():
    with pytest.raises(ValueError, match="`state` must hold"):
        row_outcomes([1.0], [1.0], [2])
    with pytest.raises(ValueError, match="says stripe where `truth` has no column"):
        row_outcomes([1.0], [np.nan], [1])
    with pytest.raises(ValueError, match="must have one shape"):
        row_outcomes([1.0, 2.0], [1.0])


def test_distant_states_leave_out_the_stripe_less_rows_near_the_stripe_only():
    t = np.full(60, np.nan)
    t[20:30] = 7.0
    states = truth_states(t)
    states[25] = UNSURE  # a stripe row the reference rule does not see stays as it is
    s = distant_states(states, t, gap_rows=15)
    assert (s[20:25] == STRIPE).all() and s[25] == UNSURE and (s[26:30] == STRIPE).all()
    assert (s[6:20] == UNSURE).all() and (s[30:44] == UNSURE).all()  # near: not scored
    assert (s[:6] == NO_STRIPE).all() and (s[44:] == NO_STRIPE).all()  # far: as before
    assert (distant_states(truth_states(np.full(8, np.nan)), np.full(8, np.nan)) == NO_STRIPE).all()
    with pytest.raises(ValueError, match="`states` and `truth` must have one shape"):
        distant_states(states, t[:10])


def test_the_fallback_rule_and_the_explicit_third_state():
    ref = np.full(60, np.nan)
    ref[20:30] = 7.0
    s = fallback_states(ref, gap_rows=15)
    assert (s[20:30] == STRIPE).all()
    assert (s[6:20] == UNSURE).all() and (s[30:44] == UNSURE).all()  # fewer than 15 rows from a stripe row
    assert (s[:6] == NO_STRIPE).all() and (s[44:] == NO_STRIPE).all()  # 15 rows or more
    assert fallback_states(np.full(5, np.nan)).tolist() == [NO_STRIPE] * 5  # no stripe anywhere
    two = fallback_states(np.stack([ref, np.full(60, 1.0)]))
    assert two.shape == (2, 60) and (two[1] == STRIPE).all() and (two[0] == s).all()
    # an unknown row never counts, reported or not; a none row counts either way
    assert row_outcomes([5.0, 5.0], [np.nan, np.nan], [UNSURE, NO_STRIPE]).tolist() == [UNKNOWN, FALSE]
    with pytest.raises(ValueError, match="`gap_rows` must be an integer >= 1"):
        fallback_states(ref, gap_rows=0)


def test_fallback_of_reads_the_rows_around_the_stripe_rows_as_a_reference_without_states():
    ref = np.full(60, np.nan)
    ref[20:30] = 7.0
    given = fallback_states(ref)
    given[:6] = UNSURE  # rows a reference with states calls unknown: read again by the rule
    given[40:] = UNSURE
    assert (fallback_of(given) == fallback_states(ref)).all()
    assert (fallback_of(np.stack([given, truth_states(np.full(60, 1.0))]))[1] == STRIPE).all()
    assert (fallback_of(np.full(5, UNSURE)) == NO_STRIPE).all()  # no stripe row: none anywhere
    with pytest.raises(ValueError, match="`gap_rows` must be an integer >= 1"):
        fallback_of(given, gap_rows=0)


def _brute_force_ap(scores, codes):
    """All-point interpolated AP by its definition, with explicit loops: at every threshold t (each
    distinct score), the reports scoring >= t; interpolated precision at recall r = the best
    precision of any threshold reaching recall >= r; summed over the recall steps."""
    scores = np.asarray(scores, float)
    codes = np.asarray(codes)
    n_pos = sum(1 for c in codes if c in (HIT, WRONG, MISSED))
    reported = [i for i, c in enumerate(codes) if c in (HIT, WRONG, FALSE)]
    key = {i: (scores[i] if np.isfinite(scores[i]) else -np.inf) for i in reported}
    points = []
    for t in sorted(set(key.values()), reverse=True):
        taken = [i for i in reported if key[i] >= t]
        tp = sum(1 for i in taken if codes[i] == HIT)
        points.append((tp / n_pos, tp / len(taken)))
    ap, prev = 0.0, 0.0
    for r, _ in sorted(points):
        if r > prev:
            ap += (r - prev) * max(p for rr, p in points if rr >= r)
            prev = r
    return ap


def test_ap_equals_a_brute_force_reference():
    rng = np.random.default_rng(4)
    for trial in range(60):
        n = int(rng.integers(5, 80))
        codes = rng.choice([HIT, WRONG, MISSED, FALSE, QUIET, UNKNOWN], n, p=[0.4, 0.1, 0.1, 0.2, 0.15, 0.05])
        scores = np.round(rng.normal(0, 1, n), 1) + 1.5 * (codes == HIT)  # rounded: ties happen
        scores[np.isin(codes, (MISSED, QUIET))] = np.nan  # nothing reported there
        if trial % 7 == 0:
            scores[np.isin(codes, (HIT, WRONG, FALSE))] = 2.0  # one operating point
        if not np.isin(codes, (HIT, WRONG, MISSED)).any():
            continue
        got = average_precision(scores, codes)
        assert got["ap"] == pytest.approx(_brute_force_ap(scores, codes), abs=1e-12)
        if trial % 7 == 0:
            f = detection_figures(outcome_counts(codes))
            assert got["constant"] and got["ap"] == pytest.approx(f["recall"] * f["precision"])


def test_ap_equals_sklearn_where_the_definitions_coincide():
    """scikit-learn's AP is sum (R_n - R_n-1) P_n over every positive it is given, without interpolation:
    the two agree when every stripe row is reported (no miss, no wrong) and precision never rises
    along the ranking (interpolation then changes nothing)."""
    from sklearn.metrics import average_precision_score

    for order in ([1, 1, 0, 1, 0, 0, 1, 0], [1, 0, 1, 0, 0, 1], [1, 1, 1, 0, 0], [0, 1, 1, 0, 1, 0, 0, 0, 1]):
        y = np.array(order)
        scores = np.arange(len(y), 0, -1, dtype=float)  # the listed order, best first
        codes = np.where(y == 1, HIT, FALSE)
        precision = np.cumsum(y)[y == 1] / (np.flatnonzero(y == 1) + 1)
        if np.all(np.diff(precision) <= 0):
            assert average_precision(scores, codes)["ap"] == pytest.approx(average_precision_score(y, scores))
    # and a case where they differ: precision rises after a false report, which interpolation keeps
    y = np.array([0, 1, 1])
    assert average_precision([3.0, 2.0, 1.0], [FALSE, HIT, HIT])["ap"] == pytest.approx(2 / 3)
    assert average_precision_score(y, [3.0, 2.0, 1.0]) == pytest.approx((0.5 + 2 / 3) / 2)


def test_pr_curve_ties_nan_scores_and_no_stripe():
    c = pr_curve([2.0, 2.0, np.nan, np.nan], [HIT, FALSE, HIT, FALSE])
    assert c["recall"].tolist() == [0.5, 1.0] and c["precision"].tolist() == [0.5, 0.5] and not c["constant"]
    assert np.isnan(average_precision([1.0], [FALSE])["ap"])  # no stripe row: AP undefined
    assert average_precision([np.nan], [MISSED])["ap"] == 0.0  # a stripe never reported
    with pytest.raises(ValueError, match="must be finite where a column is reported"):
        average_precision([np.inf], [HIT])


def test_bootstrap_over_frames():
    frames = [np.array([HIT, HIT, QUIET, FALSE]), np.array([HIT, MISSED, QUIET, QUIET]),
              np.array([WRONG, HIT, QUIET, QUIET])]
    scores = [np.array([5.0, 4.0, np.nan, 1.0]), np.array([3.0, np.nan, np.nan, np.nan]),
              np.array([2.0, 6.0, np.nan, np.nan])]
    r = bootstrap_frames(frames, scores, n_boot=400, seed=3)
    allc = np.concatenate(frames)
    assert r["n_frames"] == 3 and r["n_hit"] == 4 and r["n_false"] == 1
    assert r["ap"] == pytest.approx(average_precision(np.concatenate(scores), allc)["ap"])
    for k in ("precision", "recall", "f1", "false_report_rate", "ap"):
        assert r[f"{k}_lo"] <= r[k] <= r[f"{k}_hi"], k
    assert r == bootstrap_frames(frames, scores, n_boot=400, seed=3)  # seeded
    # one frame: no interval; frames drawn with replacement pool their rows
    one = bootstrap_frames(frames[:1], scores[:1], n_boot=10)
    assert np.isnan(one["ap_lo"]) and one["recall"] == 1.0
    with pytest.raises(ValueError, match="`n_boot` must be an integer >= 1"):
        bootstrap_frames(frames, n_boot=0)
    with pytest.raises(ValueError, match="one array per frame"):
        bootstrap_frames(frames, scores[:2])


def test_bootstrap_ap_matches_the_ap_of_each_resample():
    """The vectorised resampled AP equals average_precision on the pooled rows of the same draw."""
    from bench.evaluate.ranking import _bootstrap_ap

    rng = np.random.default_rng(8)
    frames = [rng.choice([HIT, WRONG, MISSED, FALSE, QUIET], 30) for _ in range(5)]
    scores = [np.where(np.isin(c, (HIT, WRONG, FALSE)), np.round(rng.normal(0, 1, 30), 1), np.nan) for c in frames]
    for draw in ([0, 0, 1, 3, 4], [2, 2, 2, 2, 2], [4, 3, 2, 1, 0]):
        w = np.bincount(draw, minlength=5)[None, :]
        got = _bootstrap_ap(frames, scores, w)[0]
        pooled = average_precision(np.concatenate([scores[i] for i in draw]), np.concatenate([frames[i] for i in draw]))
        assert got == pytest.approx(pooled["ap"], abs=1e-12)


@pytest.mark.parametrize("codes", list(itertools.product([HIT, WRONG, MISSED, FALSE, QUIET], repeat=2)))
def test_figures_are_nan_only_where_undefined(codes):
    f = detection_figures(outcome_counts(np.array(codes)))
    stripe = any(c in (HIT, WRONG, MISSED) for c in codes)
    reports = any(c in (HIT, WRONG, FALSE) for c in codes)
    none = any(c in (FALSE, QUIET) for c in codes)
    assert np.isnan(f["recall"]) == (not stripe)
    assert np.isnan(f["precision"]) == (not reports)
    assert np.isnan(f["false_report_rate"]) == (not none)


def test_referenced_states_follow_the_reference_rule():
    from bench.evaluate.outcomes import (NO_STRIPE, REFERENCE_MIN_CONTRAST, STRIPE, UNSURE, reference_noise,
                                         referenced_states)

    rng = np.random.default_rng(3)
    img = rng.normal(40.0, 3.0, (6, 60))
    noise = reference_noise(img)
    assert 2.0 < noise < 4.0  # the frame's robust spread: its sensor noise here
    level = REFERENCE_MIN_CONTRAST * noise
    img[0, 30] += 3.0 * level           # well above the rule: seen
    img[1, 30] += 0.3 * level           # well below: not scored
    img[2, 37] += 3.0 * level           # 7 px off the truth, outside the 6-px window: not seen
    img[3, 1] += 3.0 * level            # at the edge (window 1-8 px wide): seen
    truth = np.array([30.0, 30.0, 30.0, 0.6, 59.4, np.nan])
    img[4, 59] += 3.0 * level
    s = referenced_states(img, truth)
    assert s.tolist() == [STRIPE, UNSURE, UNSURE, STRIPE, STRIPE, NO_STRIPE]
    # a larger window sees row 2's stripe; a lower contrast rule sees row 1's
    assert referenced_states(img, truth, half_width=8)[2] == STRIPE
    assert referenced_states(img, truth, min_contrast=0.1)[1] == STRIPE


@pytest.mark.parametrize("kwargs, msg", [
    ({"frame": np.zeros(5), "truth": np.zeros(5)}, "`frame` must be (H, W)"),
    ({"frame": np.zeros((5, 9)), "truth": np.zeros(4)}, "`truth` (H,)"),
    ({"frame": np.zeros((5, 9)), "truth": np.zeros(5), "half_width": 0}, "`half_width` must be an integer >= 1, got 0"),
    ({"frame": np.zeros((5, 9)), "truth": np.zeros(5), "min_contrast": -1.0}, "`min_contrast` must be a number > 0"),
])
def test_referenced_states_refuse_bad_input(kwargs, msg):
    from bench.evaluate.outcomes import referenced_states

    with pytest.raises(ValueError) as exc:
        referenced_states(**kwargs)
    assert msg in str(exc.value)


def test_referenced_columns_are_the_intensity_centre_where_the_reference_rule_sees_the_stripe():
    rng = np.random.default_rng(3)
    img = rng.normal(20.0, 1.0, (5, 40))
    x = np.arange(40)
    for r, c in enumerate((10.0, 14.3, 20.0, 25.6, 30.0)):
        img[r] += 60.0 * np.exp(-0.5 * ((x - c) / 1.2) ** 2)
    img[4] = rng.normal(20.0, 1.0, 40)  # no stripe to be seen in the last row
    truth = np.array([12.0, 14.3, 17.0, 25.6, 30.0])  # 2 and 3 px off in rows 0 and 2
    cols = referenced_columns(img, truth)
    assert np.allclose(cols[:4], [10.0, 14.3, 20.0, 25.6], atol=0.3)  # the stripe's centre, not the truth's
    assert np.isnan(cols[4]) and referenced_states(img, truth)[4] == UNSURE
    assert window_centre(np.array([0.0, 1.0, 9.0, 10.0, 10.0, 9.0, 1.0]), level=0.8) == pytest.approx(3.5)
