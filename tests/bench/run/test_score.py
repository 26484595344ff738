"""bench.run.score: a built-in tracker's own output, submitted, scores what `run` gives it, byte for byte."""

import json

import pytest

from bench.store import frameset as fs
from bench.store.checkpoint import read_checkpoint


def _submit(run_dir, fset, tracker, folder, times=False, scores=True):
    cols, score, ms = {}, {}, {}
    for key in dict.fromkeys(f["experiment"] for f in fset.frames):
        res, why = read_checkpoint(run_dir / "scans" / f"{key}.npz", key)
        assert why is None
        for i, f in enumerate(fset.frames_of(key)):
            cols[f["frame"]] = res.columns[tracker][i]
            score[f["frame"]] = res.scores[tracker][i]
            ms[f["frame"]] = float(1e3 * res.seconds[tracker][i])
    folder.mkdir()
    (folder / "submission.csv").write_text(fs.submission_csv(cols, score if scores else None))
    if times:
        (folder / "times.csv").write_text("frame,ms\n" + "".join(f"{k},{v!r}\n" for k, v in ms.items()))
    return folder


@pytest.fixture(scope="module")
def scored(tiny_run, tiny_export_dev, tmp_path_factory):
    from bench.run.score import score

    tmp = tmp_path_factory.mktemp("score")
    sub = _submit(tiny_run[0], fs.read_frameset(tiny_export_dev), "dp4", tmp / "mine", times=True)
    return score(tiny_export_dev, sub, tmp / "run", quiet=True)


def _lines(path):
    return path.read_text().splitlines()


def test_a_submitted_tracker_scores_its_run_metrics_byte_for_byte(tiny_run, scored):
    run_lines, score_lines = _lines(tiny_run[0] / "metrics.csv"), _lines(scored / "metrics.csv")
    assert run_lines[0] == score_lines[0]
    dp4 = [line for line in run_lines[1:] if ",dp4," in line]
    mine = [line for line in score_lines[1:] if ",mine," in line]
    assert len(dp4) == 4 and [line.replace(",dp4,", ",mine,") for line in dp4] == mine


def test_the_builtin_trackers_score_their_run_metrics_on_the_exported_pngs(tiny_run, scored):
    score_lines = set(_lines(scored / "metrics.csv"))
    assert all(line in score_lines for line in _lines(tiny_run[0] / "metrics.csv"))


def test_the_samples_and_statistics_match(tiny_run, scored):
    import pandas as pd

    a, b = pd.read_csv(tiny_run[0] / "samples.csv"), pd.read_csv(scored / "samples.csv")
    assert b["error_mm_mine"].tolist() == pytest.approx(a["error_mm_dp4"].tolist(), nan_ok=True, rel=0, abs=0)
    s = json.loads((scored / "summary.json").read_text())
    r = json.loads((tiny_run[0] / "summary.json").read_text())
    assert s["kind"] == "score" and s["submission"]["label"] == "mine" and s["submission"]["timed"]
    rob = {(x["group"], x["tracker"]): x for x in s["robust"]}
    for x in r["robust"]:
        if x["tracker"] == "dp4":
            assert {k: v for k, v in rob[(x["group"], "mine")].items() if k != "tracker"} == \
                   {k: v for k, v in x.items() if k != "tracker"}
    assert any(i["dp"] == "mine" and i["baseline"] == "threshold" for i in s["improvement"])


def test_a_submission_without_scores_gets_its_operating_points_figures(tiny_run, tiny_export_dev, tmp_path):
    import pandas as pd

    from bench.run.score import score

    sub = _submit(tiny_run[0], fs.read_frameset(tiny_export_dev), "dp4", tmp_path / "plain", scores=False)
    m = pd.read_csv(score(tiny_export_dev, sub, tmp_path / "run", quiet=True) / "metrics.csv")
    mine, dp4 = m[m["tracker"] == "plain"], m[m["tracker"] == "dp4"]
    assert mine["ap_constant"].all() and not dp4["ap_constant"].all()
    assert mine["ap"].to_numpy() == pytest.approx((mine["recall"] * mine["precision"]).to_numpy(), nan_ok=True)
    assert mine["f1"].to_numpy() == pytest.approx(dp4["f1"].to_numpy(), nan_ok=True)  # the same reports
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert all(d["ap_constant"] for d in s["detection"] if d["tracker"] == "plain")


def test_the_scored_run_builds_a_report_and_a_baseline(scored):
    from bench.report.run import build_report
    from bench.run import gate

    assert build_report(scored, quiet=True).is_file()
    assert any("/mine/" in k for k in gate.baseline_from_run(scored)["metrics"])


def test_score_on_the_test_split_only(tiny_run, tiny_export, tmp_path):
    from bench.run.score import score

    fset = fs.read_frameset(tiny_export)
    sub = _submit(tiny_run[0], fset, "threshold", tmp_path / "t")
    n_test = sum(f["split"] == "test" for f in fset.frames)
    # the split is seeded: this seed and test fraction put frames in both splits (never a silent skip)
    assert 0 < n_test < len(fset.frames)
    out = score(tiny_export, sub, tmp_path / "run", trackers=None, split="test", quiet=True)
    s = json.loads((out / "summary.json").read_text())
    assert s["submission"]["frames"] == n_test


def test_score_refuses_a_bad_submission_with_every_problem(tiny_export, tmp_path):
    from bench.run.score import SubmissionError, score

    sub = tmp_path / "bad"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\nnope-000,1,2.0\ncone-patchy-000,99,2.0\n")
    with pytest.raises(SubmissionError) as err:
        score(tiny_export, sub, tmp_path / "run", quiet=True)
    assert len(err.value.problems) == 2 and "unknown frame 'nope-000'" in err.value.problems[0]
    assert not (tmp_path / "run").exists()


def test_score_refuses_a_label_of_a_builtin_tracker(tiny_export, tmp_path):
    from bench.config import ConfigError
    from bench.run.score import score

    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "submission.csv").write_text("frame,row,col\n")
    with pytest.raises(ConfigError, match="built-in tracker"):
        score(tiny_export, tmp_path / "s", tmp_path / "run", label="dp4", quiet=True)


def _damaged(tiny_export, tmp_path, edit_meta=None, edit_rows=None):
    """A copy of the tiny frame set with dataset.json and/or frames.csv edited."""
    import shutil

    from bench.store.textfiles import loads_csv

    root = tmp_path / "damaged"
    shutil.copytree(tiny_export, root)
    if edit_meta is not None:
        meta = json.loads((root / "dataset.json").read_text())
        edit_meta(meta)
        (root / "dataset.json").write_text(json.dumps(meta))
    if edit_rows is not None:
        _, rows = loads_csv((root / "frames.csv").read_text(), "frames.csv")
        edit_rows(rows)
        fs.write_frames_csv(root / "frames.csv", rows)
    (tmp_path / "s").mkdir(exist_ok=True)
    (tmp_path / "s" / "submission.csv").write_text("frame,row,col\n")
    return root


def _first_image(rows, value):
    rows[0]["image"] = value


def _resize(rows):
    rows[1]["height"] = str(int(rows[1]["height"]) + 1)


def _resize_all(rows):
    for r in rows:
        r["height"] = str(int(r["height"]) + 1)


@pytest.mark.parametrize("edit_meta, edit_rows, message", [
    (lambda m: m.pop("config"), None, r"`config` must be a dict \(missing\)"),
    (lambda m: m.pop("config_hash"), None, r"`config_hash` must be a str \(missing\)"),
    (lambda m: m["experiments"][0].pop("rig"), None, r"`experiments\[0\].rig` must be a dict \(missing\)"),
    (lambda m: m["experiments"][0].update(rig={"f_mm": 1.0}), None, r"has no valid `rig`"),
    (lambda m: m["config"].update(seed=m["config"].get("seed", 0) + 1), None,
     r"its `config` does not match its `config_hash`"),
    (None, lambda rows: _first_image(rows, "/etc/hostname"), r"image '/etc/hostname' must be a path inside"),
    (None, lambda rows: _first_image(rows, "../../x.png"), r"image '../../x.png' must be a path inside"),
    (None, _resize, r"but experiment '.*' is"),
    (None, _resize_all, r"but frames.csv says"),
])
def test_score_refuses_a_damaged_frame_set_in_one_line(tiny_export, tmp_path, edit_meta, edit_rows, message):
    """Issue 37 items 1, 4 and 5: no KeyError, broadcast error or escape; an edited configuration is refused."""
    from bench.run.score import score

    root = _damaged(tiny_export, tmp_path, edit_meta, edit_rows)
    with pytest.raises(fs.FrameSetError, match=message) as err:
        score(root, tmp_path / "s", tmp_path / "run", quiet=True)
    assert "\n" not in str(err.value)


def test_a_submission_scored_alone(tiny_run, tiny_export_dev, tmp_path):
    import pandas as pd

    from bench.run.score import score

    sub = _submit(tiny_run[0], fs.read_frameset(tiny_export_dev), "dp4", tmp_path / "mine")
    out = score(tiny_export_dev, sub, tmp_path / "run", trackers=(), quiet=True)
    m = pd.read_csv(out / "metrics.csv")
    assert set(m["tracker"]) == {"mine"}
    run = pd.read_csv(tiny_run[0] / "metrics.csv")
    a = m.drop(columns=["tracker"]).reset_index(drop=True)
    b = run[run["tracker"] == "dp4"].drop(columns=["tracker"]).reset_index(drop=True)
    pd.testing.assert_frame_equal(a, b[a.columns])  # the same figures as dp4's in the run
    # issue 66: the frame set's built-in trackers never ran, so neither the summary nor a board lists them
    from bench.report.leaderboard import leaderboard_rows

    s = json.loads((out / "summary.json").read_text())
    assert s["submission"]["alone"] is True
    assert {r["tracker"] for r in s["robust"]} == {"mine"} and {r["tracker"] for r in s["detection"]} == {"mine"}
    assert {r["tracker"] for r in leaderboard_rows([out])} == {"mine"}
    from bench.report.run import build_report

    assert build_report(out, quiet=True).is_file()  # the page of a run without built-ins


def test_score_quotes_a_huge_field_in_a_bounded_line(tiny_export, tmp_path, capsys):
    from bench.cli import main
    from bench.errors import QUOTE_CHARS

    sub = tmp_path / "huge"
    sub.mkdir()
    (sub / "submission.csv").write_text(f"frame,row,col\n{'x' * 10 * 2**20},0,1.0\ncone-patchy-000,0,{'9' * 2**20}\n")
    assert main(["score", str(tiny_export), str(sub), "--out", str(tmp_path / "run"), "--alone"]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert "unknown frame 'xxxx" in lines[0] and f"... ({10 * 2**20} characters)" in lines[0]
    assert "is not a finite number" not in lines[1] or len(lines[1]) < 300
    assert all(len(line) < QUOTE_CHARS + 200 for line in lines), [len(line) for line in lines]
