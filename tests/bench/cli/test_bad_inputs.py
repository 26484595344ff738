"""Bad inputs found by probing every command from outside: each gets one line and exit status 2 (or the
correct result), never a traceback, a hang or a silent wrong result."""

import os

import pytest

from bench.cli import main


def _one_line(capsys):
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("stripebench: error:"), err
    return err


def test_a_symbolic_link_loop_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.symlink("loop.png", "loop.png")
    assert main(["track", "loop.png", "--out", "o", "--trackers", "threshold"]) == 2
    assert "loop.png': a symbolic link loop" in _one_line(capsys)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("bundle", ["out/bundle", "."])
def test_export_refuses_a_bundle_inside_or_around_the_frame_set_before_rendering(tmp_path, capsys, monkeypatch,
                                                                                  config_file, bundle):
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(config_file), "--out", "out", "--participants", bundle, "--quiet"]) == 2
    assert "must be a folder apart from the frame set" in _one_line(capsys)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("member", ["manifest.csv", "ag_tape_ref.csv"])
def test_a_fifo_in_a_real_set_is_refused_without_waiting(tmp_path, capsys, member):
    import shutil

    from bench.store.realset import SHIPPED

    real = tmp_path / "real"
    shutil.copytree(SHIPPED, real)
    (real / member).unlink()
    os.mkfifo(real / member)
    assert main(["real", str(real), "--check"]) == 2  # would block forever on open() of the FIFO
    err = capsys.readouterr().err
    assert ("no manifest.csv" in err) if member == "manifest.csv" else ("missing reference ag_tape_ref.csv" in err)


@pytest.mark.parametrize("member, kind, message", [
    ("times.csv", "dir", "times.csv: not a regular file"),
    ("times.csv", "fifo", "times.csv: not a regular file"),
    ("submission.csv", "fifo", "submission.csv: submission.csv is not a regular file (a FIFO)"),
    ("submission.csv", "dir", "submission.csv: submission.csv is not a regular file (a folder)"),
])
def test_score_refuses_a_submission_file_that_is_not_a_regular_file(tiny_export, tmp_path, capsys, member, kind,
                                                                     message):
    sub = tmp_path / "sub"
    sub.mkdir()
    if member == "times.csv":
        (sub / "submission.csv").write_text("frame,row,col\n")
    target = sub / member
    target.mkdir() if kind == "dir" else os.mkfifo(target)
    assert main(["score", str(tiny_export), str(sub), "--out", str(tmp_path / "run"), "--alone", "--quiet"]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("text, message", [
    ("[" * 100000 + "]" * 100000, "is nested too deeply"),
    ("[" + "9" * 500 + "]", "holds an integer of 500 digits"),
    ("{not json", "is not valid JSON"),
])
def test_score_on_a_frame_set_with_a_damaged_description_is_one_line(tiny_export, tmp_path, capsys, text, message):
    import shutil

    fs = tmp_path / "fs"
    shutil.copytree(tiny_export, fs)
    (fs / "dataset.json").write_text(text)
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\n")
    assert main(["score", str(fs), str(sub), "--out", str(tmp_path / "run"), "--alone", "--quiet"]) == 2
    assert message in _one_line(capsys)


def test_score_refuses_a_times_csv_that_is_a_symbolic_link_loop(tiny_export, tmp_path, capsys):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\n")
    os.symlink("times.csv", sub / "times.csv")
    assert main(["score", str(tiny_export), str(sub), "--out", str(tmp_path / "run"), "--alone", "--quiet"]) == 2
    assert "times.csv: not a regular file" in capsys.readouterr().err


@pytest.mark.parametrize("kind, message", [
    ("fifo", "is not a regular file (a FIFO)"),
    ("deep", "is nested too deeply"),
    ("list", "not a file of `stripebench perf sampling --save` (TypeError"),
    ("null", "not a file of `stripebench perf sampling --save` (TypeError"),
])
def test_perf_sampling_from_a_damaged_file_is_one_line(tmp_path, capsys, kind, message):
    p = tmp_path / "saved.json"
    if kind == "fifo":
        os.mkfifo(p)
    else:
        p.write_text({"deep": "[" * 100000 + "]" * 100000, "list": "[1, 2]", "null": "null"}[kind])
    assert main(["perf", "sampling", "--from", str(p)]) == 2
    assert message in _one_line(capsys)


def test_perf_lit_refuses_an_empty_list_of_sizes(capsys):
    with pytest.raises(SystemExit) as exit:
        main(["perf", "lit", "--sizes", ","])
    assert exit.value.code == 2 and "--sizes: must name at least one WIDTHxHEIGHT" in _one_line(capsys)


def test_an_output_folder_that_holds_an_input_is_refused_before_any_work(tiny_export, tmp_path, capsys, config_file):
    """With --force such a folder would be cleared: the real set, frame set, submission or configuration gone."""
    import shutil

    from bench.store.realset import SHIPPED

    real = tmp_path / "real"
    shutil.copytree(SHIPPED, real)
    fs = tmp_path / "fs"
    shutil.copytree(tiny_export, fs)
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\n")
    cases = [
        (["real", str(real), "--out", str(real), "--force", "--trackers", "threshold", "--quiet"], "DATASET", real),
        (["real", str(real), "--out", str(tmp_path), "--force", "--trackers", "threshold", "--quiet"], "DATASET", real),
        (["score", str(fs), str(sub), "--out", str(fs), "--force", "--alone", "--quiet"], "DATASET", fs),
        (["score", str(fs), str(sub), "--out", str(sub), "--force", "--alone", "--quiet"], "SUBMISSION", sub),
        (["run", str(config_file), "--out", str(tmp_path), "--force", "--quiet"], "CONFIG", config_file),
        (["export", str(config_file), "--out", str(tmp_path), "--force", "--quiet"], "CONFIG", config_file),
    ]
    for argv, what, kept in cases:
        before = sorted(p.name for p in kept.iterdir()) if kept.is_dir() else kept.read_bytes()
        assert main(argv) == 2, argv
        assert f"{what} '" in _one_line(capsys) and kept.exists()
        assert (sorted(p.name for p in kept.iterdir()) if kept.is_dir() else kept.read_bytes()) == before


def test_spread_refuses_a_write_folder_that_is_a_file_before_any_run(tmp_path, capsys):
    f = tmp_path / "f"
    f.write_text("x")
    assert main(["spread", "--out", str(tmp_path / "out"), "--write", str(f)]) == 2
    assert capsys.readouterr().err.strip() == f"gate_spread: `--write` must be a folder, got '{f}' (not a folder)"
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("tol", ["1e30", "101"])
def test_real_refuses_a_tolerance_that_counts_every_report_a_hit(tol, capsys):
    from bench.store.realset import SHIPPED

    with pytest.raises(SystemExit) as exit:
        main(["real", str(SHIPPED), "--check", "--tol", tol])
    assert exit.value.code == 2 and "--tol: must be a finite number > 0 and <= 100" in _one_line(capsys)
