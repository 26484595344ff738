"""``stripebench trainset`` and ``train``: usage errors are one line with status 2; training writes weights."""

import numpy as np
import pytest

from bench.cli import main


@pytest.mark.parametrize("argv, message", [
    (["trainset", "--out", "x", "--units", "0"], "--units: must be an integer 1 .. 100000, got '0'"),
    (["trainset", "--out", "x", "--size", "big"], "--size: must be WIDTHxHEIGHT"),
    (["trainset", "--out", "x", "--scheduler", "tcp://h:x"], "--scheduler"),
    (["train", "nowhere", "--holdout", "1.5"], "argument --holdout: must be a finite number > 0 and <= 1, got '1.5'"),
    (["train", "nowhere", "--holdout", "1"], "--holdout: must be a finite number > 0 and < 1, got '1'"),
    (["train", "nowhere", "--epochs", "0"], "--epochs: must be an integer 1 .. 100000"),
    (["train", "nowhere", "--views", "auto,purple"], "--views: must be distinct names among auto, laser"),
    (["trainset", "--out", "x", "--draws", "4"], "--draws: invalid choice"),
    (["train", "nowhere", "--shrink", "1"], "--shrink: must be distinct integers >= 2 separated by commas, or none, "
                                            "got '1'"),
    (["train", "nowhere", "--shrink", "2,two"], "--shrink: must be distinct integers >= 2"),
])
def test_usage_errors_are_one_line(argv, message, capsys):
    with pytest.raises(SystemExit) as exit:
        main(argv)
    assert exit.value.code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


def test_train_refuses_a_folder_that_is_no_training_set(tmp_path, capsys, jax_child):
    if not jax_child:  # ran in a child process (tests/conftest.py)
        return
    assert main(["train", str(tmp_path), "--out", str(tmp_path / "w.npz")]) == 2
    assert "not a finished training set" in capsys.readouterr().err


@pytest.mark.slow
def test_trainset_then_train_writes_weights_the_tracker_reads(tmp_path, capsys, jax_child):
    if not jax_child:  # ran in a child process (tests/conftest.py)
        return
    import trackers
    from trackers.learned import weights_info

    ts = tmp_path / "ts"
    assert main(["trainset", "--out", str(ts), "--units", "3", "--angles", "1", "--noise-draws", "1",
                 "--size", "64x60", "--quiet"]) == 0
    out = tmp_path / "w.npz"
    assert main(["train", str(ts), "--out", str(out), "--epochs", "1", "--holdout", "0.5", "--quiet"]) == 0
    assert out.is_file() and out.with_suffix(".png").is_file()
    info = weights_info(out)
    assert info["trainset"]["n_units"] == 3 and info["hyper_parameters"]["epochs"] == 1
    track = trackers.make("learned", weights=str(out)).track(np.zeros((60, 64), np.uint8))
    assert track.height == 60
    # the operating point alone, chosen again for the same network
    again = tmp_path / "w2.npz"
    assert main(["train", str(ts), "--from-weights", str(out), "--out", str(again), "--holdout", "0.5",
                 "--quiet"]) == 0
    from trackers.learned import PARAM_KEYS, load_weights

    a, b = load_weights(out), load_weights(again)
    assert all(np.array_equal(a[k], b[k]) for k in PARAM_KEYS)
    assert (a["threshold"], a["jump_cost"], a["switch_cost"]) == (b["threshold"], b["jump_cost"], b["switch_cost"])
    assert len(weights_info(again)["operating_point_history"]) == 1
    capsys.readouterr()
    assert main(["train", str(ts), "--from-weights", str(tmp_path / "none.npz"), "--out", str(again)]) == 2
    err = capsys.readouterr().err.strip()
    assert "cannot read learned weights" in err and "\n" not in err


def test_damaged_weights_stop_run_track_and_train_in_one_line_before_any_work(tmp_path, capsys):
    from trackers.learned import DEFAULT_WEIGHTS

    bad = tmp_path / "w.npz"
    bad.write_bytes(DEFAULT_WEIGHTS.read_bytes()[:5000])  # truncated
    spec = f'{{name="learned",params={{weights="{bad}"}}}}'
    cfg = tmp_path / "c.toml"
    cfg.write_text(f'name = "x"\ntrackers = [{spec}]\n')
    image = str(next(p for p in sorted((DEFAULT_WEIGHTS.parents[2] / "bench" / "data" / "real").glob("*.png"))))
    out = tmp_path / "out"
    for argv in (["run", str(cfg), "--out", str(out)],
                 ["run", "--profile", "ci", "--trackers", spec, "--out", str(out)],
                 ["track", image, "--out", str(out), "--trackers", spec],
                 ["train", str(tmp_path), "--from-weights", str(bad), "--out", str(out / "w.npz")]):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code
        err = capsys.readouterr().err.strip()
        assert code == 2, argv
        assert "learned weights" in err and str(bad) in err and "not a readable .npz archive" in err, err
        assert "\n" not in err and not out.exists(), argv


def test_train_writes_under_the_runs_folder_by_default_never_over_the_shipped_weights(tmp_path, monkeypatch):
    from bench.cli import build_parser
    from bench.cli.train import default_weights_out
    from trackers.learned import DEFAULT_WEIGHTS

    monkeypatch.setenv("STRIPEBENCH_RUNS", str(tmp_path / "runs"))
    args = build_parser().parse_args(["train", str(tmp_path / "ts-a"), "--seed", "3"])
    assert args.out is None
    out = default_weights_out(args.trainset, args.seed)
    assert out == tmp_path / "runs" / "learned" / "ts-a-seed3.npz" and out.resolve() != DEFAULT_WEIGHTS


@pytest.mark.parametrize("damage, message", [
    (lambda p: p.write_text("{not json"), "is not valid JSON"),
    (lambda p: p.write_bytes(b"\xff\xfe"), "is not UTF-8 text"),
    (lambda p: p.mkdir(), "is not a regular file (a folder)"),
    (lambda p: __import__("os").mkfifo(p), "is not a regular file (a FIFO)"),
    (lambda p: p.write_text("[" * 100000), "nested too deeply"),
    (lambda p: p.write_text('["x"]'), "holds a training set of other settings"),
])
def test_trainset_over_a_damaged_identity_file_is_one_line(tmp_path, capsys, damage, message):
    out = tmp_path / "ts"
    out.mkdir()
    (out / "images").mkdir()
    damage(out / "trainset.identity.json")
    assert main(["trainset", "--out", str(out), "--units", "1", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "trainset.identity.json" in err and "\n" not in err, err


def test_train_over_a_damaged_training_set_is_one_line(tmp_path, capsys):
    from bench.run.trainset import FORMAT, read_trainset
    from bench.errors import InputError

    ts = tmp_path / "ts"
    ts.mkdir()
    (ts / "trainset.json").write_text("[1, 2]")
    (ts / "frames.csv").write_text("frame\nx\n")
    with pytest.raises(InputError, match="is not a training set of format"):
        read_trainset(ts)
    (ts / "trainset.json").write_text(f'{{"kind": "stripebench-trainset", "format": {FORMAT}}}')
    with pytest.raises(InputError, match="no column 'image'"):
        read_trainset(ts)


def test_train_on_a_training_set_too_small_to_split_is_one_line(tmp_path, capsys):
    import sys

    from bench.run.trainset import FORMAT, FRAME_COLUMNS

    ts = tmp_path / "ts"
    ts.mkdir()
    (ts / "trainset.json").write_text(f'{{"kind": "stripebench-trainset", "format": {FORMAT}}}')
    row = {c: "1" for c in FRAME_COLUMNS} | {"image": "images/a.png", "background": "images/a_off.png"}
    (ts / "frames.csv").write_text(",".join(FRAME_COLUMNS) + "\n" + ",".join(row[c] for c in FRAME_COLUMNS) + "\n")
    assert main(["train", str(ts), "--out", str(tmp_path / "w.npz"), "--holdout", "0.5", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "left no training or no held-out frames (1 frames of 1 units, holdout 0.5)" in err and "\n" not in err
    assert "jax" not in sys.modules  # refused before any training
