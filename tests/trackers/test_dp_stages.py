"""``trackers.dp_stages``: the DP trackers' stages, composed, give what the trackers and the
validated solvers of ``trackers.dp`` and ``trackers.dp_gap`` give."""

import numpy as np
import pytest

import trackers
from trackers import dp_stages as S
from trackers.dp import accumulated_cost, node_cost, shortest_path
from trackers.dp_gap import gap_path
from trackers.testing import make_stripe_image


def frames():
    """uint8 stripe frames with a cut and a jump, and a float64 signed difference."""
    out = []
    for seed in range(2):
        img, _ = make_stripe_image(48, 64, seed=seed, noise=2.0)
        img[10:14] = 6
        img[30:] = np.roll(img[30:], 12, axis=1)
        out.append(img)
    rng = np.random.default_rng(4)
    out.append(out[0].astype(np.float64) - rng.integers(0, 20, out[0].shape))
    return out


@pytest.mark.parametrize("name", ["dp4", "dp8", "dp_gap", "dp8_subpixel"])
@pytest.mark.parametrize("rule", ["crossing", "mean", "brightest"])
def test_the_stages_give_the_trackers_readings_and_tracks(name, rule):
    t = trackers.make(name, row_rule=rule)
    for img in frames():
        frame, *want = t.readings(img)
        got = S.row_readings(frame, *S.labelled_nodes(t, frame), t.side_inner, t.side_outer, t.row_rule)
        for a, b in zip(got, want):
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
        if name == "dp8_subpixel":  # its columns are refined after the rule
            continue
        col, contrast, side_sd, span = got
        rule_out = S.reporting_rule(frame, contrast, side_sd, span, t)
        track = t.track(img)
        if rule_out is None:
            assert np.isnan(track.columns).all()
        else:
            z, support, report = rule_out
            report = report & ~np.isnan(col)
            assert support.dtype == report.dtype == bool
            np.testing.assert_array_equal(np.where(report, col, np.nan), track.columns)
            np.testing.assert_array_equal(np.where(report, z, np.nan), track.score)


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("h_weight", [1.0, 0.25])
def test_the_exact_field_is_the_accumulated_cost(connectivity, h_weight):
    for img in frames():
        hc, rowmin, left, right = S.half_costs(img, 2.0)
        D, sweeps = S.distance_field(hc, rowmin, left, connectivity, h_weight, right=right, exact=True)
        want = accumulated_cost(img, connectivity=connectivity, eps=2.0, h_weight=h_weight)
        assert D[:-1].tobytes() == want[:-1].tobytes() and D[-1].min() == want[-1, 0]
        assert sweeps >= 1
        again, _ = S.distance_field(hc, rowmin, left, connectivity, h_weight, exact=True, out=np.empty_like(hc))
        assert again.tobytes() == D.tobytes()  # the rightmost columns are computed when not given


@pytest.mark.parametrize("connectivity", [4, 8])
def test_the_path_and_the_labels_are_those_of_shortest_path(connectivity):
    for img in frames():
        hc, rowmin, left, right = S.half_costs(img)
        D, _ = S.distance_field(hc, rowmin, left, connectivity, 0.25, right=right)
        rows, cols = S.backtrack(D, hc, connectivity, 0.25)
        want_r, want_c, _ = shortest_path(node_cost(img), connectivity, 0.25)
        np.testing.assert_array_equal(rows, want_r)
        np.testing.assert_array_equal(cols, want_c)
        mark, lr, lc = S.optimal_nodes(D, hc, connectivity, 0.25)
        on = np.zeros(hc.shape, bool)
        on[lr, lc] = True
        assert lr.size == np.count_nonzero(on)  # each labelled node listed once
        np.testing.assert_array_equal(on, (mark & 1).astype(bool))
        assert not ((mark & 2).astype(bool) & ~on).any()  # bit 2 only on labelled nodes
        assert on[rows, cols].all()  # the backtracked path is one of the optimal ones


def test_the_gap_fields_give_gap_paths_optimum():
    rng = np.random.default_rng(2)
    for connectivity in (4, 8):
        cost = rng.uniform(0.1, 2.0, (12, 9))
        off = rng.uniform(0.5, 1.5, 12)
        F, Foff = S.gap_fields(0.5 * cost, 0.5 * off, 0.3, connectivity, 0.5)
        total = gap_path(cost, off, 0.3, connectivity, 0.5)[3]
        assert min(F[-1].min(), Foff[-1]) == total
        assert (F[0] == 0).all()


def test_bad_choices_are_refused():
    img = np.zeros((3, 4), np.uint8)
    hc, rowmin, left, _ = S.half_costs(img)
    with pytest.raises(ValueError, match="connectivity"):
        S.distance_field(hc, rowmin, left, connectivity=6)
    with pytest.raises(ValueError, match="row_rule"):
        S.row_readings(img, np.zeros((3, 4), np.uint8), np.empty(0, np.int64), np.empty(0, np.int64),
                       row_rule="median")
