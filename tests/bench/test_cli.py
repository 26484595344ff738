import subprocess
import sys

import pytest

from bench.cli import main

TOML = """
name = "cli"
seed = 0
trackers = ["threshold", "dp4"]
baselines = ["threshold"]
dp = ["dp4"]
n_samples = 5
n_boot = 20
[render]
width = 64
height = 60
spp = 1
ambient_spp = 1
[[experiments]]
scene = "plane"
material = "matte"
n_angles = 2
"""


def test_trackers_and_scenes_lists(capsys):
    assert main(["trackers"]) == 0
    out = capsys.readouterr().out
    assert "dp8" in out and "threshold" in out and "sub-pixel" in out
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    assert "cone" in out and "specular" in out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["reproduce", "--trackers", "nope"], "--trackers: unknown tracker 'nope'"),
        (["reproduce", "--trackers", ","], "--trackers must name at least one tracker"),
        (["run"], "give a CONFIG.toml or --profile"),
        (["run", "missing.toml"], "cannot read configuration 'missing.toml'"),
        (["report", "not-a-run"], "RUN must be a finished run folder"),
    ],
)
def test_bad_values_give_one_line_and_status_2(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and err[0].startswith("stripebench: error:")


def test_bad_config_file_names_the_key(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(TOML.replace("n_samples = 5", "n_samples = -5"))
    assert main(["run", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "stripebench: error: `n_samples` must be an integer >= 1, got -5"


def test_bad_seed_is_a_usage_error():
    out = subprocess.run([sys.executable, "-m", "bench.cli", "reproduce", "--seed", "-1"], capture_output=True,
                         text=True)
    assert out.returncode == 2 and "--seed: must be an integer >= 0, got '-1'" in out.stderr


def test_run_a_config_file_then_rebuild_its_report(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    out_dir = tmp_path / "run"
    assert main(["run", str(cfg), "--out", str(out_dir), "--quiet"]) == 0
    assert f"report at {out_dir / 'report.html'}" in capsys.readouterr().out
    (out_dir / "report.html").unlink()
    assert main(["report", str(out_dir), "--quiet"]) == 0
    assert (out_dir / "report.html").is_file()


@pytest.mark.parametrize("argv", [["perf", "-h"], ["perf", "--scenes", "-h"], ["estimators", "-h"],
                                  ["translucency", "-h"]])
def test_pass_through_commands_show_their_own_help(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 0 and "usage:" in capsys.readouterr().out
