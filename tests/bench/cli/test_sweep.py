"""``stripebench sweep`` (bench/cli/sweep.py)."""

import time

import pytest

from bench.cli import main
from cli_helpers import cli, one_line, one_line_err, status


SWEEP = ('name = "s"\ntrackers = ["threshold"]\nbaselines = []\ndp = []\n[render]\nwidth = 64\nheight = 60\n'
         '[[experiments]]\nscene = "cone"\nn_angles = 2\n[sweep]\n')


def test_sweep_command_bad_sweep_is_one_line_and_exit_2(tmp_path, capsys):
    cfg = tmp_path / "s.toml"
    cfg.write_text('name = "s"\ntrackers = ["threshold"]\nbaselines = []\ndp = []\n[render]\nwidth = 64\n'
                   'height = 60\n[[experiments]]\nscene = "cone"\n[sweep]\nambient_lux = []\n')
    assert main(["sweep", str(cfg), "--out", str(tmp_path / "o"), "--scheduler", "sync"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "stripebench: error: `sweep.ambient_lux` must be a non-empty list of values, got []"
    assert main(["run", str(cfg), "--out", str(tmp_path / "r")]) == 2
    assert "stripebench sweep CONFIG --out DIR" in capsys.readouterr().err
    cfg.write_text(cfg.read_text().replace("ambient_lux = []", "ambient_lux = [0, 400]"))
    assert status(["sweep", str(cfg), "--workers", "-1"]) == 2
    one_line_err(capsys, "argument --workers: must be an integer 0 ..")
    assert status(["sweep", str(cfg), "--scheduler", "localhost:1"]) == 2
    one_line_err(capsys, "argument --scheduler: must be 'sync' or an address like tcp://HOST:PORT")


@pytest.mark.parametrize("args, message", [
    (["--scheduler", "tcp://"], "argument --scheduler: must be 'sync' or an address like tcp://HOST:PORT"),
    (["--scheduler", "tcp://127.0.0.1:notaport"], "got 'tcp://127.0.0.1:notaport'"),
    (["--scheduler", "tcp://127.0.0.1:70000"], "(PORT 1..65535)"),
    (["--timeout", "nan"], "argument --timeout: must be a finite number > 0 and <= "),
    (["--timeout", "-1"], "argument --timeout: must be a finite number > 0"),
    (["--workers", "1000"], "argument --workers: must be an integer 0 .. "),
    (["--scheduler", "tcp://127.0.0.1:8786", "--workers", "1"], "--workers sizes the local cluster"),
])
def test_bad_engine_options_are_one_line_before_any_work(tmp_path, args, message):
    cfg = tmp_path / "s.toml"
    cfg.write_text(SWEEP + "ambient_lux = [0, 400]\n")
    proc = cli("sweep", cfg, "--out", tmp_path / "o", *args)
    one_line(proc, message)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("table, message", [
    ("ambient_lux = [400, 1e7]", "`sweep.ambient_lux` = 10000000.0 (experiment 0, cone-matte): must be at most 1e+06"),
    ("laser_power_mw = [3, 1e6]", "must be at most 100000"),
    ("exposure_ms = [5, 1e5]", "must be at most 10000"),
    ("f_number = [2.8, 0.01]", "must be at least 0.5"),
    ("ambient_lux = [0]\nrepeats = 1000000000", "`sweep.repeats` must be an integer 1 .. 1000"),
    ("ambient_lux = [" + ", ".join(map(str, range(3000))) + "]\nlaser_power_mw = ["
     + ", ".join(map(str, range(1, 3001))) + "]", "`sweep` has 9000000 grid points"),
])
def test_sweep_values_and_sizes_that_run_refuses_are_one_line_at_once(tmp_path, table, message):
    cfg = tmp_path / "s.toml"
    cfg.write_text(SWEEP + table + "\n")
    t0 = time.monotonic()
    proc = cli("sweep", cfg, "--out", tmp_path / "o", "--scheduler", "sync")
    one_line(proc, message)
    assert time.monotonic() - t0 < 60 and not (tmp_path / "o").exists()
