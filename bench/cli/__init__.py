"""The ``stripebench`` command line: one parser tree.

Every command is a :class:`bench.cli.common.Command` in the ``COMMANDS`` of its
group's module (``run``: reproduce, run, report, check, compare; ``real``:
track, real; ``submit``: export, score, leaderboard; ``sweep``; ``studies``:
estimators, translucency, tune, loro, spread, perf {trackers, scenes, sweep, shiny,
sampling, lit, mis}; ``info``: trackers, scenes; ``train``: trainset, train; ``predict``:
predict, predictcheck, predictloro, predictscore; ``tables``: tables; a test
checks this list against :func:`command_groups`), built from an
``add_arguments(parser)`` and a ``run(args)``; a study command's ``run`` calls the
study's plain function with the parsed options (:func:`bench.cli.common.study_command`),
and only this package knows argparse. The options they share (``--out``,
``--quiet``, ``--seed``, ``--trackers``, counts, finite numbers) are defined once
in :mod:`bench.cli.options` (their value checks in :mod:`bench.config.options`).

Exit status: 0 success, 1 a failed check (``stripebench check``/``compare``,
``perf trackers --strict``, a file ``track`` could not read), 2 a usage, configuration,
input or file-system error (one line on stderr, ``stripebench: error: ...``,
see ``docs/errors.md``), 130 interrupted. Every expected failure is a
:class:`bench.errors.StripebenchError` (or an ``OSError``), caught once in
:func:`main`.
"""

from __future__ import annotations

import argparse
import errno
import os
import sys
from pathlib import Path

from bench.cli.common import LazyParser, UsageError, add_commands, check_variant
from bench.cli.options import HelpFormatter, OneLineParser, plain

__all__ = ["main", "build_parser", "plain", "version", "tracker_table", "UsageError", "command_groups"]


def version() -> str:
    """The installed ``stripebench`` version (or the source tree's, from ``pyproject.toml``)."""
    from importlib import metadata

    try:
        return metadata.version("stripebench")
    except metadata.PackageNotFoundError:
        import tomllib

        pyproject = Path(__file__).resolve().parents[2] / "pyproject.toml"
        try:
            return tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]["version"]
        except (OSError, KeyError, ValueError):
            return "unknown"


def tracker_table() -> list[dict]:
    """Every registered tracker (:func:`bench.cli.info.tracker_table`)."""
    from bench.cli.info import tracker_table as table

    return table()


def command_groups():
    """The command groups in the order ``stripebench -h`` lists them: (module name, commands)."""
    from bench.cli import info, predict, real, run, studies, submit, sweep, tables, train

    return (("run", run.COMMANDS), ("tables", tables.COMMANDS), ("real", real.COMMANDS), ("submit", submit.COMMANDS),
            ("sweep", sweep.COMMANDS), ("studies", studies.COMMANDS), ("info", info.COMMANDS), ("train", train.COMMANDS),
            ("predict", predict.COMMANDS))


def build_parser() -> argparse.ArgumentParser:
    """The whole command tree (one parser; each command's options are added when it is used)."""
    parser = OneLineParser(prog="stripebench", formatter_class=HelpFormatter,
                           description="A physically based rendering benchmark for laser-stripe trackers.",
                           epilog="Exit status: 0 ok, 1 a failed check, 2 a bad input (one line on stderr), "
                                  "130 interrupted.")
    parser.add_argument("--version", action="version", version=f"stripebench {version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=LazyParser)
    sub.required = True
    for _, commands in command_groups():
        add_commands(sub, commands)
    return parser


def _os_message(exc: OSError) -> str:
    reason = "no space left on the device" if exc.errno == errno.ENOSPC else (exc.strerror or str(exc))
    if exc.filename is None:
        return f"{type(exc).__name__}: {reason}"
    return f"cannot use {str(exc.filename)!r}: {reason}"


def main(argv=None) -> int:
    """Parse ``argv`` (default ``sys.argv[1:]``) and run the command; returns the exit status."""
    from bench.errors import StripebenchError, one_line

    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if getattr(args, "command_renders", False):
            check_variant()
        return int(args.func(args) or 0)
    except StripebenchError as exc:
        print(f"stripebench: error: {one_line(exc)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # `stripebench trackers | head`: the reader left
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:
        print(f"stripebench: error: {one_line(_os_message(exc))}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # Python < 3.13: Path.resolve() on a symbolic link that points at itself
        if not str(exc).startswith("Symlink loop from "):
            raise
        print(f"stripebench: error: cannot use {one_line(str(exc)[len('Symlink loop from '):])}: a symbolic link "
              "loop", file=sys.stderr)
        return 2
    except MemoryError:
        print("stripebench: error: out of memory; use fewer or smaller frames (see docs/errors.md)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("stripebench: interrupted; rerun the same command to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
