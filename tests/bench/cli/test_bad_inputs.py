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
