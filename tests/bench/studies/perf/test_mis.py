"""The MIS study of the shiny objects' bounce light: its options and one tiny run."""

import pytest

import scenes
from bench.studies.perf import mis
from bench.cli import main


@pytest.mark.parametrize("argv, message", [
    (["--counts", "8"], "--counts must be camera+light counts >= 1 (e.g. 8+4), got '8'"),
    (["--counts", "8+0"], "--counts must be camera+light counts >= 1 (e.g. 8+4), got '8+0'"),
    (["--materials", "matte"], "--materials must name some of polished, glazed, got 'matte'"),
    (["--objects", "cube"], "--objects must name some of cone, hand, plane, sphere, got 'cube'")])
def test_bad_options_are_one_line_errors(argv, message, capsys):
    assert main(["perf", "mis", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


@pytest.mark.slow
def test_a_tiny_run_measures_todays_pass_and_each_count(monkeypatch, capsys):
    real_make = scenes.make
    monkeypatch.setattr(scenes, "make", lambda *a, **k: real_make(*a, **{**k, "width": 64, "height": 60}))
    assert main(["perf", "mis", "--materials", "polished", "--objects", "cone", "--counts", "2+1,4+2", "--angles", "1",
                     "--ref-object-spp", "8"]) == 0
    rows = [line.split(" | ") for line in capsys.readouterr().out.splitlines() if line.startswith("| cone/")]
    assert [r[1] for r in rows] == ["path@3 16 (today)", "mis 2+1", "mis 4+2"]
    for r in rows:
        assert all(float(v) >= 0 for v in r[2:5]) and 0.5 < float(r[5]) < 1.5
