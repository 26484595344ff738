"""bench.report.leaderboard: comparable runs ranked per condition, ties by overlapping intervals."""

import csv

import pytest

from bench.report.leaderboard import LeaderboardError, build_leaderboard, leaderboard_rows


@pytest.fixture(scope="module")
def scored_run(tiny_run, tiny_export_dev, tmp_path_factory):
    from bench.run.score import score
    from bench.store import frameset as fs
    from bench.store.checkpoint import read_checkpoint

    fset = fs.read_frameset(tiny_export_dev)
    cols = {}
    for key in dict.fromkeys(f["experiment"] for f in fset.frames):
        res, _ = read_checkpoint(tiny_run[0] / "scans" / f"{key}.npz", key)
        for i, f in enumerate(fset.frames_of(key)):
            cols[f["frame"]] = res.columns["dp8"][i]
    tmp = tmp_path_factory.mktemp("lb")
    (tmp / "sub").mkdir()
    (tmp / "sub" / "submission.csv").write_text(fs.submission_csv(cols))
    return score(tiny_export_dev, tmp / "sub", tmp / "run", label="mine", trackers=None, quiet=True)


def _alone(tiny_run, tiny_export, folder, label, *, eager: bool, split: str = "all"):
    """``dp8``'s columns of the tiny run scored alone as ``label``; ``eager``: with a report (column 1.0) on
    every row with no stripe added."""
    import numpy as np

    from bench.run.score import score
    from bench.store import frameset as fs
    from bench.store.checkpoint import read_checkpoint

    fset = fs.read_frameset(tiny_export)
    cols = {}
    for key in dict.fromkeys(f["experiment"] for f in fset.frames):
        res, _ = read_checkpoint(tiny_run[0] / "scans" / f"{key}.npz", key)
        for i, f in enumerate(fset.frames_of(key)):
            c = res.columns["dp8"][i].copy()
            if eager:
                c[np.isnan(res.truth_columns[i])] = 1.0
            cols[f["frame"]] = c
    (folder / label).mkdir(parents=True)
    (folder / label / "submission.csv").write_text(fs.submission_csv(cols))
    return score(tiny_export, folder / label, folder / f"run_{label}_{split}", trackers=(), split=split, quiet=True)


@pytest.fixture(scope="module")
def eager_quiet(tiny_run, tiny_export_dev, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("eq")
    return (_alone(tiny_run, tiny_export_dev, tmp, "eager", eager=True),
            _alone(tiny_run, tiny_export_dev, tmp, "quiet", eager=False))


def test_the_default_ranking_prices_false_reports(eager_quiet):
    """Issue 66: a submission that reports on every stripe-less row ties a quiet one by the ±5 mm fraction
    (its sample points lie on the object's stripe) but ranks below it by default (F1 over rows)."""
    eager, quiet = eager_quiet
    for runs in ([eager, quiet], [quiet, eager]):
        rows = [r for r in leaderboard_rows(runs) if r["condition"] == "patchy cone"]
        assert [r["tracker"] for r in rows] == ["quiet", "eager"] and all(r["rank_by"] == "f1" for r in rows)
        q, e = rows
        assert q["f1"] > e["f1"] and q["false_report_rate"] < e["false_report_rate"]
        assert q["false_points_per_scan"] < e["false_points_per_scan"]
        assert q["within"] == e["within"]  # the paper's reading cannot tell them apart
        by_within = {r["tracker"]: r for r in leaderboard_rows(runs, "within") if r["condition"] == "patchy cone"}
        assert by_within["eager"]["rank"] == by_within["quiet"]["rank"] == 1


def test_the_cli_ranks_by_f1_by_default():
    from bench.cli import build_parser

    args = build_parser().parse_args(["leaderboard", "a", "--out", "b"])
    assert args.rank_by == "f1"


def test_runs_of_different_splits_are_refused_whatever_their_order(tiny_run, tiny_export, eager_quiet, tmp_path):
    """Issue 66: a run of every frame, a submission scored on the test split and one scored on every frame of a
    set with a test split (its test frames rendered at angles of their own) are not one board."""
    test_only = _alone(tiny_run, tiny_export, tmp_path, "quiet", eager=False, split="test")
    with_test = _alone(tiny_run, tiny_export, tmp_path / "all", "quiet", eager=False, split="all")
    for runs in ([eager_quiet[1], test_only], [test_only, eager_quiet[1]], [tiny_run[0], test_only],
                 [with_test, tiny_run[0]], [with_test, test_only]):
        with pytest.raises(LeaderboardError, match=r"scored different frames.*\(\d+ frames\)") as err:
            leaderboard_rows(runs)
        assert "\n" not in str(err.value)
    with pytest.raises(LeaderboardError, match=r"--split test \(\d+ frames\)"):
        leaderboard_rows([tiny_run[0], test_only])
    assert leaderboard_rows([tiny_run[0], *eager_quiet])  # a set without a test split: the run's own frames


def test_the_order_of_the_arguments_does_not_change_the_board(tiny_run, scored_run, eager_quiet):
    import json

    runs = [tiny_run[0], scored_run, *eager_quiet]
    boards = []
    for order in (runs, runs[::-1], [runs[2], runs[0], runs[3], runs[1]]):
        notes = []
        boards.append(json.dumps([leaderboard_rows(order, notes=notes), notes]))  # NaN written as NaN
    assert boards[0] == boards[1] == boards[2]


def test_rows_rank_every_tracker_once_per_condition(tiny_run, scored_run):
    rows = leaderboard_rows([tiny_run[0], scored_run], "within")
    conds = dict.fromkeys(r["condition"] for r in rows)
    assert "patchy cone" in conds
    cone = [r for r in rows if r["condition"] == "patchy cone"]
    assert sorted(r["tracker"] for r in cone) == ["centroid", "dp4", "dp8", "mine", "threshold"]
    within = [r["within"] for r in cone]
    assert within == sorted(within, reverse=True)
    mine, dp8 = (next(r for r in cone if r["tracker"] == t) for t in ("mine", "dp8"))
    # the scored run is read first (canonical_order): the built-ins it re-tracked come from it
    assert mine["within"] == dp8["within"] and mine["kind"] == "score" and dp8["kind"] == "score"
    assert mine["origin"] == "submission" and dp8["origin"] == "built-in (scored run)"
    leader = cone[0]
    for i, b in enumerate(cone[1:], start=2):  # the interval rule against the rank's leader decides ties and ranks
        overlap = b["within_high"] >= leader["within_low"]
        assert b["tied"] == overlap and b["rank"] == (leader["rank"] if overlap else i)
        leader = leader if overlap else b


def test_ties_do_not_chain_down_the_table():
    from bench.report.leaderboard import rank_with_ties

    # each interval overlaps its neighbour's, none overlaps one two steps up
    rows = [{"tracker": f"t{i}", "within": w, "within_low": w - 0.04, "within_high": w + 0.04}
            for i, w in enumerate((0.96, 0.91, 0.86, 0.81, 0.76))]
    ranked = rank_with_ties(list(reversed(rows)))
    assert [r["tracker"] for r in ranked] == ["t0", "t1", "t2", "t3", "t4"]
    assert [(r["rank"], r["tied"]) for r in ranked] == [(1, False), (1, True), (3, False), (3, True), (5, False)]
    nan = {"tracker": "broken", "within": float("nan"), "within_low": float("nan"), "within_high": float("nan")}
    assert rank_with_ties([nan, rows[0]])[-1] == {**nan, "rank": 2, "tied": False}


def test_page_and_csv(tiny_run, scored_run, tmp_path):
    page = build_leaderboard([tiny_run[0], scored_run], tmp_path / "lb")
    text = page.read_text()
    assert "patchy cone" in text and "mine</b> <span class='scale'>submission</span>" in text
    rows = leaderboard_rows([tiny_run[0], scored_run])
    assert text.count("class='track'") == sum(r["f1"] == r["f1"] for r in rows)  # one interval track per ranked row
    with (tmp_path / "lb" / "leaderboard.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == len(leaderboard_rows([tiny_run[0], scored_run]))


def test_incomparable_runs_are_refused_in_one_line(tiny_run, gate_run, tmp_path):
    with pytest.raises(LeaderboardError, match="is not comparable with .* they differ in"):
        build_leaderboard([tiny_run[0], gate_run[0]], tmp_path / "lb")
    with pytest.raises(LeaderboardError, match="finished run"):
        build_leaderboard([tmp_path], tmp_path / "lb")


def test_every_row_names_its_origin_and_duplicates_are_said(tiny_run, scored_run):
    """Issue 37 item 9: the scored run first, then the run: the run's built-ins (the same settings,
    re-tracked by score on the exported frames) are dropped with a note, never mislabelled."""
    notes = []
    rows = leaderboard_rows([scored_run, tiny_run[0]], notes=notes)
    cone = {r["tracker"]: r for r in rows if r["condition"] == "patchy cone"}
    assert cone["mine"]["origin"] == "submission"
    assert {cone[t]["origin"] for t in cone if t != "mine"} == {"built-in (scored run)"}
    assert any(n.startswith(f"dp8 of {tiny_run[0].name}: the same setting as {scored_run.name}'s dp8") for n in notes)


def test_a_label_with_other_parameters_enters_again_and_an_empty_run_is_said(tiny_run, tmp_path):
    import json
    import shutil

    other = tmp_path / "other"
    shutil.copytree(tiny_run[0], other)
    s = json.loads((other / "summary.json").read_text())
    s["config"]["trackers"] = [t if t != "dp4" else {"label": "dp4", "name": "dp4", "params": {"h_weight": 1.0}}
                               for t in s["config"]["trackers"]]
    (other / "summary.json").write_text(json.dumps(s))
    empty = tmp_path / "empty"
    shutil.copytree(tiny_run[0], empty)
    s.pop("conditions")
    (empty / "summary.json").write_text(json.dumps(s))
    notes = []
    rows = leaderboard_rows([tiny_run[0], other, empty], notes=notes)
    names = {r["tracker"] for r in rows if r["condition"] == "patchy cone"}
    # the runs are read by path (canonical_order): the first of the two dp4 settings keeps its label
    a, b = sorted([tiny_run[0], other], key=lambda p: str(p.resolve()))
    renamed = f"dp4 [{b.name}]"
    assert "dp4" in names and renamed in names and f"dp8 [{b.name}]" not in names
    assert f"dp4 of {b.name} is another setting than {a.name}'s dp4: shown as {renamed!r}" in notes
    assert "empty: its summary.json lists no conditions; it adds nothing to the board" in notes
