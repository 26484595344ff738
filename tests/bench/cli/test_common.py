"""The shared parts of the command tree (bench/cli/common.py): lazy sub-parsers, default sub-commands,
the environment and ``--out`` checks."""

import subprocess
import sys

import pytest

from bench.cli.common import Command, LazyParser, UsageError, add_commands, check_env, check_out_folder
from bench.cli.options import OneLineParser
from bench.errors import StripebenchError
from cli_helpers import REPO


def test_a_commands_options_are_added_only_when_it_is_parsed():
    loaded = []

    def add(p):
        loaded.append(p.prog)
        p.add_argument("--x", type=int, default=1)

    parser = OneLineParser(prog="t")
    sub = parser.add_subparsers(dest="command", parser_class=LazyParser)
    add_commands(sub, [Command("a", "A", add, lambda args: args.x), Command("b", "B", lambda p: None, lambda a: 0)])
    assert loaded == []
    args = parser.parse_args(["a", "--x", "3"])
    assert loaded == ["t a"] and args.func(args) == 3


def test_a_default_sub_command_runs_with_its_own_defaults():
    inner = Command("one", "1", lambda p: p.add_argument("--n", type=int, default=7), lambda args: args.n)
    outer = Command("group", "g", lambda p: None, None, subcommands=(inner,), default_subcommand="one")
    parser = OneLineParser(prog="t")
    add_commands(parser.add_subparsers(dest="command", parser_class=LazyParser), [outer])
    args = parser.parse_args(["group"])
    assert args.func(args) == 7
    args = parser.parse_args(["group", "one", "--n", "2"])
    assert args.func(args) == 2


def test_listing_trackers_imports_no_study_and_no_renderer():
    code = ("import sys; from bench.cli import main; main(['trackers']); "
            "bad = [m for m in sys.modules if m.startswith('bench.studies') or m in ('mitsuba', 'drjit', 'dask')]; "
            "print('BAD', ','.join(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True).stdout
    assert out.strip().splitlines()[-1] == "BAD"


def test_usage_errors_are_stripebench_errors():
    assert issubclass(UsageError, StripebenchError)


def test_environment_and_out_checks(tmp_path, monkeypatch):
    f = tmp_path / "f"
    f.write_text("x")
    monkeypatch.setenv("STRIPEBENCH_RUNS", str(f))
    with pytest.raises(UsageError, match=r"\$STRIPEBENCH_RUNS must name a folder"):
        check_env()
    with pytest.raises(UsageError, match="--out must be a folder"):
        check_out_folder(f)
    check_out_folder(tmp_path / "new")  # a missing folder is created later
