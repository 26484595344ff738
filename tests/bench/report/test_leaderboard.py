"""bench.report.leaderboard: comparable runs ranked per condition, ties by overlapping intervals."""

import csv

import pytest

from bench.report.leaderboard import LeaderboardError, build_leaderboard, leaderboard_rows


@pytest.fixture(scope="module")
def scored_run(tiny_run, tiny_export, tmp_path_factory):
    from bench.run.score import score
    from bench.store import frameset as fs
    from bench.store.checkpoint import read_checkpoint

    fset = fs.read_frameset(tiny_export)
    cols = {}
    for key in dict.fromkeys(f["experiment"] for f in fset.frames):
        res, _ = read_checkpoint(tiny_run[0] / "scans" / f"{key}.npz", key)
        for i, f in enumerate(fset.frames_of(key)):
            cols[f["frame"]] = res.columns["dp8"][i]
    tmp = tmp_path_factory.mktemp("lb")
    (tmp / "sub").mkdir()
    (tmp / "sub" / "submission.csv").write_text(fs.submission_csv(cols))
    return score(tiny_export, tmp / "sub", tmp / "run", label="mine", trackers=None, quiet=True)


def test_rows_rank_every_tracker_once_per_condition(tiny_run, scored_run):
    rows = leaderboard_rows([tiny_run[0], scored_run])
    conds = dict.fromkeys(r["condition"] for r in rows)
    assert "patchy cone" in conds
    cone = [r for r in rows if r["condition"] == "patchy cone"]
    assert sorted(r["tracker"] for r in cone) == ["centroid", "dp4", "dp8", "mine", "threshold"]
    within = [r["within"] for r in cone]
    assert within == sorted(within, reverse=True)
    mine, dp8 = (next(r for r in cone if r["tracker"] == t) for t in ("mine", "dp8"))
    assert mine["within"] == dp8["within"] and mine["kind"] == "score" and dp8["kind"] == "run"
    assert mine["origin"] == "submission" and dp8["origin"] == "built-in (run)"
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
    assert text.count("class='track'") == sum(r["within"] == r["within"] for r in rows)  # one interval track per ranked row
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
    assert "dp4" in names and "dp4 [other]" in names and "dp8 [other]" not in names
    assert f"dp4 of other is another setting than {tiny_run[0].name}'s dp4: shown as 'dp4 [other]'" in notes
    assert "empty: its summary.json lists no conditions; it adds nothing to the board" in notes
