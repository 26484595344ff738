"""Helpers of the command-line tests (imported by name: ``tests/bench/cli/conftest.py`` puts this folder on
``sys.path``): the tiny configuration, a subprocess runner and the one-line check
(``stripebench: error: ...`` on one stderr line, exit status 2)."""

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]

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


def cli(*args, env=None, timeout=120, cwd=None):
    """``python -m bench.cli ARGS`` in a fresh process; the CompletedProcess."""
    full_env = {**os.environ, **(env or {})}
    full_env["PYTHONPATH"] = str(REPO) + (os.pathsep + full_env["PYTHONPATH"] if full_env.get("PYTHONPATH") else "")
    return subprocess.run([sys.executable, "-m", "bench.cli", *map(str, args)], capture_output=True, text=True,
                          env=full_env, timeout=timeout, cwd=cwd or REPO)


def one_line(proc, *needles):
    """Assert exit status 2 and exactly one stderr line ``stripebench: error: ...`` holding every needle."""
    lines = [ln for ln in proc.stderr.splitlines() if not ln.startswith("stripebench.scenes: Mitsuba variant")]
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    assert len(lines) == 1 and lines[0].startswith("stripebench: error:"), proc.stderr[-2000:]
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


def one_line_err(capsys, *needles):
    """The in-process form of :func:`one_line` on captured stderr."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("stripebench: error:"), err
    for n in needles:
        assert n in err[0], (n, err[0])
    return err[0]


def status(argv):
    """``bench.cli.main(argv)``'s exit status, also when argparse exits (usage errors, -h)."""
    from bench.cli import main

    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code
