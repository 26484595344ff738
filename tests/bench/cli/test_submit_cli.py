"""The CLI of the export -> score -> leaderboard loop: outputs, and every expected failure as exit 2."""

from bench.cli import main


def test_score_and_leaderboard_through_the_cli(tiny_run, tiny_export, tiny_export_dev, tmp_path, capsys):
    sub = tmp_path / "bad"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\nnope,0,1\ncone-patchy-000,0,99\n")
    assert main(["score", str(tiny_export), str(sub), "--out", str(tmp_path / "r"), "--quiet"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and all(line.startswith("stripebench score: ") for line in err)
    (sub / "submission.csv").write_text("frame,row,col\ncone-patchy-000,10,30.5\n")
    assert main(["score", str(tiny_export), str(sub), "--out", str(tmp_path / "r"), "--quiet", "--no-report",
                 "--trackers", "threshold"]) == 0
    assert main(["leaderboard", str(tmp_path / "r"), "--out", str(tmp_path / "lb")]) == 0
    assert (tmp_path / "lb" / "leaderboard.html").is_file()
    capsys.readouterr()
    # a set with a test split: its test frames are not the run's, so the two are not one board
    assert main(["leaderboard", str(tmp_path / "r"), str(tiny_run[0]), "--out", str(tmp_path / "lb2")]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert main(["score", str(tiny_export_dev), str(sub), "--out", str(tmp_path / "rd"), "--quiet", "--no-report",
                 "--trackers", "threshold"]) == 0
    assert main(["leaderboard", str(tmp_path / "rd"), str(tiny_run[0]), "--out", str(tmp_path / "lb2")]) == 0
    capsys.readouterr()
    assert main(["export", "--out", str(tmp_path / "x")]) == 2
    assert "CONFIG.toml or --profile" in capsys.readouterr().err
    assert main(["score", str(tmp_path), str(sub), "--out", str(tmp_path / "r2")]) == 2
    assert "exported frame set" in capsys.readouterr().err


def test_export_refuses_a_bad_test_seed_in_one_line(tmp_path, capsys):
    import pytest

    with pytest.raises(SystemExit) as exit_:
        main(["export", "--profile", "quick", "--out", str(tmp_path / "x"), "--test-seed", "-1"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert "argument --test-seed: must be an integer >= 0" in err[-1] and not (tmp_path / "x").exists()
