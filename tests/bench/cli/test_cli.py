"""The command tree and ``main`` (bench/cli/__init__.py): one parser, one-line errors, plain help,
every documented bad input with its test."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from bench.cli import build_parser, main
from cli_helpers import REPO, cli, one_line, one_line_err, status  # noqa: F401

def test_bad_seed_is_a_usage_error():
    out = subprocess.run([sys.executable, "-m", "bench.cli", "reproduce", "--seed", "-1"], capture_output=True,
                         text=True)
    assert out.returncode == 2 and "--seed: must be an integer >= 0 (at most 2**63 - 1), got '-1'" in out.stderr


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("stripebench 0.")


def test_argparse_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--bogus"])
    assert exc.value.code == 2
    one_line_err(capsys, "unrecognized arguments: --bogus")
    with pytest.raises(SystemExit):
        main(["reproduce", "--profile", "nope"])
    one_line_err(capsys, "invalid choice: 'nope'")


@pytest.mark.parametrize("argv", [["estimators", "-h"], ["perf", "scenes", "-h"], ["perf", "-h"], ["tune", "-h"], ["translucency", "-h"], ["trackers", "-h"], ["-h"]])
def test_help_is_plain_text(argv, capsys):
    with pytest.raises(SystemExit):
        main(argv)
    out = capsys.readouterr().out
    assert "``" not in out and ":func:" not in out and "python -m" not in out
