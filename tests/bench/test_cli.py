import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

import trackers
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
        (["reproduce", "--trackers", "nope"], "`--trackers[0]` names unknown tracker 'nope'"),
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


@pytest.mark.slow
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


# -- every bad input: one line on stderr, exit status 2 (docs/errors.md) ------------------------

def _one_line(capsys, *needles):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("stripebench: error:"), err
    for n in needles:
        assert n in err[0], (n, err[0])
    return err[0]


@pytest.mark.parametrize(
    "change, message",
    [
        (("n_angles = 2", "angles = [0.0, nan]"), "`experiments[0].angles` must be finite"),
        (("n_angles = 2", "angles = [0.0, inf]"), "`experiments[0].angles` must be finite"),
        (("n_angles = 2", "angles = [0.0, 1e30]"), "within +-45 deg"),
        (("n_angles = 2", "n_angles = 1000000000"), "`experiments[0].n_angles` must be at most"),
        (("n_angles = 2", "n_angles = 2\nlaser_power_mw = 1e30"), "`experiments[0].laser_power_mw` must be at most"),
        (("n_angles = 2", "n_angles = 2\nambient_lux = nan"), "`ambient_lux` must be a finite number"),
        (("n_angles = 2", "n_angles = 2\nf_number = 1e-6"), "`experiments[0].f_number` must be at least 0.5"),
        (("n_angles = 2", "n_angles = 2\nline_fwhm_mrad = 1e-9"), "`experiments[0].line_fwhm_mrad` must be at least"),
        (("spp = 1", "spp = 1000000000"), "`render.spp` must be at most 65536"),
        (("width = 64", "width = 1000000"), "`render.width` must be at most 8192"),
        (("[[experiments]]", "[[experiments]]\nangles = [0.0, 1.0]", "n_angles = 2", "n_angles = 100000",
          "width = 64", "width = 8192", "height = 60", "height = 7680", "angles = [0.0, 1.0]\n", ""),
         "GiB of memory"),
        (("n_boot = 20", "n_boot = 1e9"), "`n_boot` must be an integer"),
        (("name = \"cli\"", "name = \"cli\"\nbogus = 1"), "unknown key `bogus`"),
    ],
)
def test_ranges_that_break_the_renderer_or_memory_are_refused_before_any_work(change, message, tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    text = TOML
    for old, new in zip(change[::2], change[1::2]):
        text = text.replace(old, new)
    cfg.write_text(text)
    t0 = time.monotonic()
    assert main(["run", str(cfg), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    _one_line(capsys, message)
    assert time.monotonic() - t0 < 20 and not (tmp_path / "out").exists()


def test_spp_times_pixels_beyond_mitsubas_count_is_refused(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML.replace("width = 64", "width = 8192").replace("height = 60", "height = 7680")
                   .replace("spp = 1\n", "spp = 100\n"))
    assert main(["run", str(cfg), "--out", str(tmp_path / "out")]) == 2
    _one_line(capsys, "2**32 - 1 samples")


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """A finished 64x60 run made through the command line (no report)."""
    d = tmp_path_factory.mktemp("clirun")
    cfg = d / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--out", str(d / "run"), "--quiet", "--no-report"]) == 0
    return d / "run", cfg


@pytest.mark.slow
def test_out_problems_are_one_line_with_the_path(cli_run, tmp_path, capsys, monkeypatch):
    run_dir, cfg = cli_run
    capsys.readouterr()
    f = tmp_path / "afile"
    f.write_text("x")
    assert main(["run", str(cfg), "--out", str(f), "--quiet"]) == 2
    _one_line(capsys, "--out must be a folder", "afile")
    assert main(["run", str(cfg), "--out", str(f / "sub"), "--quiet"]) == 2
    _one_line(capsys, "afile")
    assert main(["run", str(cfg), "--out", "/sys/stripebench-readonly-test", "--quiet"]) == 2
    _one_line(capsys, "cannot create run folder", "/sys/stripebench-readonly-test")
    # another configuration into the same folder
    other = tmp_path / "other.toml"
    other.write_text(TOML.replace("seed = 0", "seed = 1"))
    assert main(["run", str(other), "--out", str(run_dir), "--quiet"]) == 2
    _one_line(capsys, "holds a run of another configuration", "--force")


@pytest.mark.slow
def test_a_full_disk_is_one_line(cli_run, tmp_path, capsys, monkeypatch):
    import errno

    from bench import runfolder

    def full(path, data):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(runfolder, "atomic_write_bytes", full)
    monkeypatch.setattr(runfolder, "atomic_write_text", lambda p, t: full(p, t))
    assert main(["run", str(cli_run[1]), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    _one_line(capsys, "no space left on the device", str(tmp_path / "o"))


@pytest.mark.parametrize("var", ["STRIPEBENCH_RUNS", "STRIPEBENCH_CACHE_DIR"])
def test_environment_variables_naming_a_file_are_one_line(var, tmp_path, capsys, monkeypatch):
    f = tmp_path / "afile"
    f.write_text("x")
    monkeypatch.setenv(var, str(f))
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--quiet"]) == 2
    _one_line(capsys, f"${var} must name a folder", "afile")


def test_a_malformed_llvm_target_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("STRIPEBENCH_LLVM_TARGET", "haswell/6")
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--quiet"]) == 2
    _one_line(capsys, "`STRIPEBENCH_LLVM_TARGET` must be", "'haswell/6'")


@pytest.mark.slow
@pytest.mark.parametrize(
    "doc, message",
    [
        ("null", "is not a stripebench baseline"),
        ('"a string"', "is not a stripebench baseline"),
        ('{"format": 1, "metrics": null}', "`metrics` must be an object"),
        ('{"format": 1, "metrics": {"a/b/all": {"px_mae": "x"}}}', "must be a number or null"),
        ('{"format": 1, "metrics": {}, "tolerances": {"px_mae": {"direction": "lower", "rel": 0.1}}}',
         "must have exactly `direction`, `abs` and `rel`"),
        ('{"format": 1, "metrics": {}, "tolerances": {"px_mae": {"direction": "up", "abs": 0, "rel": 0}}}',
         "'lower' or 'higher'"),
        ("{nope", "is not valid JSON"),
    ],
)
def test_malformed_baselines_are_one_line(doc, message, cli_run, tmp_path, capsys):
    base = tmp_path / "b.json"
    base.write_text(doc)
    assert main(["check", str(cli_run[0]), "--baseline", str(base)]) == 2
    _one_line(capsys, message)


@pytest.mark.slow
def test_corrupt_run_files_in_report_check_and_compare_are_one_line(cli_run, tmp_path, capsys):
    import shutil

    run_dir = tmp_path / "copy"
    shutil.copytree(cli_run[0], run_dir)
    (run_dir / "metrics.parquet").write_bytes(b"PAR1 garbage")
    base = tmp_path / "b.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 2
    _one_line(capsys, "metrics.parquet")
    assert main(["compare", str(cli_run[0]), str(run_dir)]) == 2
    _one_line(capsys, "metrics.parquet")
    (run_dir / "summary.json").write_text("{")
    assert main(["report", str(run_dir), "--quiet"]) == 2
    _one_line(capsys, "summary.json", "is not valid JSON")


@pytest.mark.slow
def test_check_and_compare_refuse_runs_of_another_resolution(cli_run, tmp_path, capsys):
    run_dir, cfg = cli_run
    big = tmp_path / "big.toml"
    big.write_text(TOML.replace("width = 64", "width = 128").replace("height = 60", "height = 120"))
    other = tmp_path / "other"
    assert main(["run", str(big), "--out", str(other), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(other)]) == 2
    _one_line(capsys, "are not comparable", "render", "compared: render, experiments, seed")
    base = tmp_path / "base.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 0
    capsys.readouterr()
    assert main(["check", str(other), "--baseline", str(base)]) == 2
    _one_line(capsys, "are not comparable")


@pytest.mark.slow
def test_compare_two_runs_of_the_same_configuration(cli_run, tmp_path, capsys):
    run_dir, cfg = cli_run
    again = tmp_path / "again"
    assert main(["run", str(cfg), "--out", str(again), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(again)]) == 0
    assert "0 failed" in capsys.readouterr().out
    assert main(["compare", str(run_dir), str(again), "--json", "--all"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["checks"] == len(doc["rows"]) > 0
    assert {r["verdict"] for r in doc["rows"]} == {"ok"}
    base = tmp_path / "b.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 0
    capsys.readouterr()
    assert main(["check", str(again), "--baseline", str(base), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["rows"] == []


def test_version_and_trackers_json(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("stripebench 0.")
    assert main(["trackers", "--json"]) == 0
    table = {t["name"]: t for t in json.loads(capsys.readouterr().out)}
    assert table["dp8"]["params"]["eps"] == trackers.make("dp8").eps
    assert table["threshold"]["subpixel"] is False and table["steger"]["module"] == "trackers.steger"


def test_argparse_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--bogus"])
    assert exc.value.code == 2
    _one_line(capsys, "unrecognized arguments: --bogus")
    with pytest.raises(SystemExit):
        main(["reproduce", "--profile", "nope"])
    _one_line(capsys, "invalid choice: 'nope'")


@pytest.mark.parametrize("argv", [["estimators", "-h"], ["perf", "--scenes", "-h"], ["trackers", "-h"], ["-h"]])
def test_help_is_plain_text(argv, capsys):
    with pytest.raises(SystemExit):
        main(argv)
    out = capsys.readouterr().out
    assert "``" not in out and ":func:" not in out and "python -m" not in out


def test_run_help_points_to_the_config_reference(capsys):
    with pytest.raises(SystemExit):
        main(["run", "-h"])
    out = capsys.readouterr().out
    assert "docs/config.md" in out
    assert (Path(__file__).resolve().parents[2] / "docs" / "config.md").is_file()


# -- stripebench sweep -------------------------------------------------------------------------------------------

def test_sweep_command_bad_sweep_is_one_line_and_exit_2(tmp_path, capsys):
    from bench.cli import main

    cfg = tmp_path / "s.toml"
    cfg.write_text('name = "s"\ntrackers = ["threshold"]\nbaselines = []\ndp = []\n[render]\nwidth = 64\n'
                   'height = 60\n[[experiments]]\nscene = "cone"\n[sweep]\nambient_lux = []\n')
    assert main(["sweep", str(cfg), "--out", str(tmp_path / "o"), "--scheduler", "sync"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "stripebench: error: `sweep.ambient_lux` must be a non-empty list of values, got []"
    assert main(["run", str(cfg), "--out", str(tmp_path / "r")]) == 2
    assert "stripebench sweep CONFIG --out DIR" in capsys.readouterr().err
    cfg.write_text(cfg.read_text().replace("ambient_lux = []", "ambient_lux = [0, 400]"))
    assert main(["sweep", str(cfg), "--workers", "-1"]) == 2
    assert capsys.readouterr().err.strip() == "stripebench: error: --workers must be an integer >= 0, got -1"
    assert main(["sweep", str(cfg), "--scheduler", "localhost:1"]) == 2
    assert "--scheduler must be 'sync' or an address like tcp://HOST:PORT" in capsys.readouterr().err


@pytest.mark.slow
def test_no_render_ahead_turns_the_helper_off_and_resumes_the_same_run_folder(cli_run, capsys):
    """``--no-render-ahead`` on two experiments: no helper; the flag is not part of the run's identity,
    so it resumes (does not refuse) the folder of the same configuration run with the helper on."""
    run_dir, _ = cli_run
    cfg = run_dir.parent / "two.toml"
    cfg.write_text(TOML + '[[experiments]]\nscene = "cone"\nmaterial = "patchy"\nn_angles = 2\n')
    out = run_dir.parent / "two"
    assert main(["run", str(cfg), "--out", str(out), "--quiet", "--no-report", "--no-render-ahead"]) == 0
    assert json.loads((out / "summary.json").read_text())["render_ahead"] == {"off": "turned off"}
    assert main(["run", str(cfg), "--out", str(out), "--quiet", "--no-report"]) == 0
    ra = json.loads((out / "summary.json").read_text())["render_ahead"]
    assert ra["started"] is False and ra["frames"] == 4  # resumed: every frame was done, no helper needed
